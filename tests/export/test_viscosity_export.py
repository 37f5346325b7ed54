"""The Kelvin-Voigt viscosity in the exports: as a stiffness-proportional (Rayleigh) damping time eta / mu where the
target has one (MuJoCo's flex damping, Drake's stiffness_damping, SOFA's rayleighStiffness), recorded elsewhere."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.export import ExportMaterial
from tasks.export.drake import deformable_sdf
from tasks.export.mujoco import flex_params

KW = dict(youngs_modulus_pa=1.2e6, poisson_ratio=0.48, density_kg_per_m3=950.0, damping_rate_per_s=0.5,
          ground_friction=0.9, gripper_friction=1.0, mass_kg=0.05)
NODES = np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, 0.05, 0.0], [0.0, 0.0, 0.05]])
TETS = np.array([[0, 1, 2, 3]])


def test_the_stiffness_damping_time_is_eta_over_mu() -> None:
    m = ExportMaterial(**KW, viscosity_pa_s=120.0)
    mu = 1.2e6 / (2.0 * 1.48)
    assert m.stiffness_damping_s == pytest.approx(120.0 / mu)
    assert ExportMaterial(**KW).stiffness_damping_s == 0.0


def test_mujoco_adds_it_to_the_flex_damping_time() -> None:
    plain = flex_params(NODES, TETS, ExportMaterial(**KW))
    viscous = flex_params(NODES, TETS, ExportMaterial(**KW, viscosity_pa_s=120.0))
    assert viscous.damping_s - plain.damping_s == pytest.approx(120.0 / (1.2e6 / 2.96))


def test_drake_sets_stiffness_damping() -> None:
    m = ExportMaterial(**KW, viscosity_pa_s=120.0)
    assert f"<drake:stiffness_damping>{m.stiffness_damping_s!r}</drake:stiffness_damping>" in deformable_sdf(
        "ball", "ball.vtk", m)
    assert "<drake:stiffness_damping>0.0</drake:stiffness_damping>" in deformable_sdf("ball", "ball.vtk",
                                                                                    ExportMaterial(**KW))
