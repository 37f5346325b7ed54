"""The reduced analytic suite (what `deformsmith verify physics --quick` runs) must pass case by case."""

from __future__ import annotations

import math

import pytest

from tasks.mpm.verify import run_case


def _one(name: str):
    """Run a quick case and return its single result."""
    (res,) = run_case(name, quick=True, device="cpu")
    return res


def test_free_fall_matches_g_t() -> None:
    res = _one("free_fall")
    assert res.passed, res
    assert res.measured == pytest.approx(-9.81 * 0.3, rel=1e-3)


def test_momentum_conserved_through_collision() -> None:
    res = _one("momentum_conservation")
    assert res.details["blocks_collided"]
    assert res.measured < 1e-4, res


def test_fixed_free_bar_period() -> None:
    res = _one("bar_period")
    assert res.passed, res
    assert abs(res.measured - res.expected) / res.expected <= 0.05


def test_column_self_weight_settlement() -> None:
    res = _one("column_settlement")
    assert res.passed, res
    assert res.error <= 0.10


def test_uniaxial_compression_stress_and_poisson() -> None:
    stress, lateral = run_case("uniaxial_compression", quick=True, device="cpu")
    assert stress.passed and lateral.passed, (stress, lateral)
    strain = stress.details["strain"]
    assert -0.02 < strain < -0.005  # a small-strain test really compressed the block
    assert stress.measured == pytest.approx(1e5 * strain, rel=0.05)
    assert lateral.measured == pytest.approx(-0.3 * strain, rel=0.05)


def test_incline_threshold_within_two_degrees() -> None:
    res = _one("incline")
    assert res.passed, res
    assert abs(res.measured - math.degrees(math.atan(0.5))) <= 2.0


def test_cantilever_tip_deflection() -> None:
    res = _one("cantilever")
    assert res.passed, res


def test_two_jaw_grasp_threshold() -> None:
    res = _one("grasp")
    assert res.passed, res
    holds = res.details["holds"]
    assert not holds[0] and holds[-1]  # far below the threshold it slips, far above it holds
