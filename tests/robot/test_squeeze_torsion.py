"""The hold force covers the weight's torque about the closing axis on a stiff object (Hertzian torsional friction)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tasks.robot.squeeze import squeeze_plan, torque_lever_m, torsion_force_n

DUCK = dict(youngs_modulus_pa=1.6e6, poisson_ratio=0.45, mass_kg=0.026, gravity_m_per_s2=9.81, friction=0.8)
PAD_AREA_M2 = 4 * 0.0085 * 0.01


def test_the_force_found_holds_the_torque_by_hertzian_torsional_friction() -> None:
    """At N the two patches' torsional friction 2 (3 pi / 16) mu N a(N) equals margin x m g d (Johnson 7.3)."""
    lever, radius, margin = 0.025, 0.021, 3.0
    n = torsion_force_n(DUCK["mass_kg"], 9.81, 0.8, lever, 1.6e6, 0.45, radius, 0.05, hold_n=1.0, margin=margin)
    e_star = 1.6e6 / (1 - 0.45**2)
    a = (3 * n * radius / (4 * e_star)) ** (1 / 3)
    assert 2 * (3 * math.pi / 16) * 0.8 * n * a == pytest.approx(margin * DUCK["mass_kg"] * 9.81 * lever, rel=1e-9)
    # twice the lever: N grows as lever^(3/4)
    n2 = torsion_force_n(DUCK["mass_kg"], 9.81, 0.8, 2 * lever, 1.6e6, 0.45, radius, 0.05, hold_n=1.0)
    assert n2 / n == pytest.approx(2 ** 0.75, rel=1e-9)


def test_a_stiff_object_held_off_its_centre_of_mass_gets_a_firmer_grip_within_the_caps() -> None:
    through = squeeze_plan(width_m=0.042, pad_area_m2=PAD_AREA_M2, budget_n=20.0, gripper_max_n=70.0, **DUCK)
    off = squeeze_plan(width_m=0.042, pad_area_m2=PAD_AREA_M2, budget_n=20.0, gripper_max_n=70.0, lever_m=0.03,
                       **DUCK)
    assert through.force_target_n == 1.0 and through.torsion_force_n == 0.0  # the floor: m g / (2 mu) x 3 = 0.48 N
    assert 5.0 < off.force_target_n == off.torsion_force_n < 10.0
    capped = squeeze_plan(width_m=0.042, pad_area_m2=PAD_AREA_M2, budget_n=8.0, gripper_max_n=70.0, lever_m=0.06,
                          **DUCK)
    assert capped.force_target_n == 4.0  # half the force budget


def test_a_soft_toy_that_fills_the_pads_gets_no_torsion_term() -> None:
    plush = dict(DUCK, youngs_modulus_pa=1.6e4, poisson_ratio=0.3, mass_kg=0.095)
    sq = squeeze_plan(width_m=0.06, pad_area_m2=PAD_AREA_M2, budget_n=20.0, gripper_max_n=70.0, lever_m=0.03, **plush)
    assert sq.torsion_force_n == 0.0


def test_the_lever_is_the_horizontal_offset_across_the_closing_axis() -> None:
    center, com = np.zeros(3), np.array([0.01, 0.02, -0.05])
    assert torque_lever_m(center, np.array([1.0, 0.0, 0.0]), com) == pytest.approx(0.02)  # along the axis: no lever
    assert torque_lever_m(center, np.array([0.0, 2.0, 0.0]), com) == pytest.approx(0.01)
    assert torque_lever_m(center, np.array([0.0, 0.0, 1.0]), com) == pytest.approx(0.0)  # a vertical axis
