"""A bouncy class's prior restitution as a Kelvin-Voigt viscosity, calibrated on the object's own impact
(tasks.realworld.loss): the engine then gives the object that restitution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.realworld.impact import impact
from tasks.realworld.loss import (RESTITUTION_TOLERANCE, damping_ratio, material_loss, restitution_loss_task,
                                  viscosity_for_damping_ratio)
from tests.spheres import resting_sphere

R, SPACING, RHO = 0.02, 0.004, 1000.0
MAT = Material(youngs_modulus_pa=2e5, poisson_ratio=0.3)


def sphere() -> tuple[np.ndarray, np.ndarray, PhysicalModel]:
    """A 4 cm solid sphere of 552 particles resting on z = 0, and its physical model."""
    return resting_sphere(R, SPACING, RHO)


@pytest.mark.parametrize("zeta", [0.01, 0.1, 0.3])
def test_the_damping_ratio_inverts_a_half_cycle(zeta: float) -> None:
    e = math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta))
    assert damping_ratio(e) == pytest.approx(zeta, rel=1e-12)
    assert viscosity_for_damping_ratio(zeta, 1e6, 4e-3) == pytest.approx(zeta * 1e6 * 4e-3 / math.pi)


def test_the_calibrated_viscosity_gives_the_sphere_its_restitution() -> None:
    """Target 0.7 at 2 m/s (the engine alone: ~0.9): the adopted viscosity's impact is within the tolerance of it,
    and an impact run anew with that viscosity shows the same."""
    pos, vol, phys = sphere()
    sim = SimConfig()
    rec = restitution_loss_task.fn(positions_m=pos, volumes_m3=vol, physical=phys, material=MAT, restitution=0.7,
                                   speed_m_per_s=2.0, sim=sim)
    assert rec["restitution_engine"] > 0.85
    assert rec["viscosity_pa_s"] > 0.0
    assert abs(rec["restitution"] - 0.7) <= RESTITUTION_TOLERANCE, rec
    again = impact(pos, vol, phys, MAT.model_copy(update={"viscosity_pa_s": rec["viscosity_pa_s"]}), 2.0, sim)
    assert again["restitution"] == pytest.approx(rec["restitution"], abs=1e-9)


def test_no_viscosity_where_the_engine_already_loses_enough() -> None:
    pos, vol, phys = sphere()
    rec = restitution_loss_task.fn(positions_m=pos, volumes_m3=vol, physical=phys, material=MAT, restitution=0.99,
                                   speed_m_per_s=2.0, sim=SimConfig())
    assert rec["viscosity_pa_s"] == 0.0
    assert rec["restitution"] == rec["restitution_engine"] < 0.99


def test_a_class_without_a_restitution_prior_gets_no_loss() -> None:
    pos, vol, phys = sphere()
    assert material_loss(pos, vol, phys, MAT, {"youngs_modulus_pa": 2e5}, SimConfig()) == ({}, {})
