"""Quasi-static probes of a stiff body run mass-scaled (density x k, gravity / k): the same loads, strains and
modulus, in fewer steps; a soft body runs exactly as before."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from benchmarks.quasi_static_scaling import step_counter, unscaled
from contracts.material import Material
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.probes import deformable
from tasks.probes.rollout import fundamental_period_s, quasi_static_mass_scale, scaled_gravity
from tests.l2.helpers import box_body

RUBBER = Material(youngs_modulus_pa=2.0e6, poisson_ratio=0.3, damping_rate_per_s=2.0)  # a firm rubber [Pa]


def _both_ways(probe: Callable[[], ProbeResult]) -> tuple[ProbeResult, int, ProbeResult, int]:
    """The probe mass-scaled, then unscaled: (scaled result, its MPM steps, unscaled result, its MPM steps)."""
    with step_counter() as steps:
        scaled = probe()
    with unscaled(), step_counter() as plain_steps:
        plain = probe()
    return scaled, steps[0], plain, plain_steps[0]


def test_mass_scale_brings_the_period_up_to_the_bound_and_no_further() -> None:
    """k makes 4H/c exactly the bound for a stiff body; a body already slower keeps k = 1 and SimConfig's gravity."""
    stiff = box_body((0.03, 0.03, 0.03), 6, density=1100.0)
    k = quasi_static_mass_scale(stiff, RUBBER, 0.01)
    assert k > 10.0
    assert fundamental_period_s(stiff, RUBBER, k) == pytest.approx(0.01, rel=1e-9)
    plush = box_body((0.2, 0.15, 0.08), 8, density=120.0)
    soft = Material(youngs_modulus_pa=1.0e4, poisson_ratio=0.3, damping_rate_per_s=10.0)
    assert fundamental_period_s(plush, soft) > 0.02 and quasi_static_mass_scale(plush, soft, 0.02) == 1.0
    assert scaled_gravity(SimConfig(), 1.0) is None
    assert scaled_gravity(SimConfig(), 4.0) == pytest.approx((0.0, 0.0, -9.81 / 4.0))


def test_stiff_cube_compression_scaled_matches_unscaled_in_fewer_steps() -> None:
    """A 3 cm rubber cube (T = 2.6 ms) at 10 % strain: the scaled compression gives E within 15 % (uniaxial secant)
    and the unscaled run's modulus, force, strain and recovery within 3 %, in at least 2x fewer steps; the record
    names k. Its squeeze (3 mm after a 15 mm approach) bounds k below the 0.01 s period (compress_qs_period_s)."""
    cube = box_body((0.03, 0.03, 0.03), 6, density=1100.0)
    bound = deformable.compress_qs_period_s(1.5 * 2 * 0.005, 0.1 * 0.03)
    assert bound < deformable.COMPRESS_QS_PERIOD_S
    k = quasi_static_mass_scale(cube, RUBBER, bound)
    scaled, n_scaled, plain, n_plain = _both_ways(lambda: deformable.compress(cube, RUBBER, strain=0.1)[0])
    assert scaled.health.ok and plain.health.ok
    assert scaled.spec.params["mass_scale"] == pytest.approx(k) and "mass_scale" not in plain.spec.params
    e = scaled.metrics["effective_modulus_pa"]
    assert abs(e - RUBBER.youngs_modulus_pa) / RUBBER.youngs_modulus_pa < 0.15, e
    for name in ("effective_modulus_pa", "compression_force_n", "compression_strain", "recovery_ratio"):
        a, b = scaled.metrics[name], plain.metrics[name]
        assert abs(a - b) <= 0.03 * abs(b), (name, a, b)
    assert n_plain >= 2.0 * n_scaled, (n_plain, n_scaled, k)


def test_stiff_body_rests_the_same_scaled() -> None:
    """The 3 s rest of a hard rubber block (8 MPa): stable both ways, the same sag under its weight (deformation
    within 10 % or 1e-4 H), k recorded, at least 2.5x fewer steps (the scaled step reaches SimConfig.dt_max_s)."""
    block = box_body((0.05, 0.04, 0.03), 6, density=1100.0)
    hard = RUBBER.model_copy(update={"youngs_modulus_pa": 8.0e6})
    k = quasi_static_mass_scale(block, hard, deformable.STABILITY_QS_PERIOD_S)
    assert k > 100.0
    scaled, n_scaled, plain, n_plain = _both_ways(lambda: deformable.stability(block, hard, duration_s=3.0)[0])
    for r in (scaled, plain):
        assert r.health.ok and r.metrics["stable_long_rollout"] == 1.0
    assert scaled.spec.params["mass_scale"] == pytest.approx(k)
    a, b = scaled.metrics["deformation_ratio"], plain.metrics["deformation_ratio"]
    assert abs(a - b) <= max(0.1 * b, 1e-4), (a, b)
    assert n_plain >= 2.5 * n_scaled, (n_plain, n_scaled)


def test_soft_body_is_not_scaled() -> None:
    """A plush-like block (T above both bounds): bit for bit the same rest and compression with scaling on and off,
    no mass_scale in either record."""
    block = box_body((0.1, 0.1, 0.06), 6, density=120.0)
    soft = Material(youngs_modulus_pa=1.0e4, poisson_ratio=0.3, damping_rate_per_s=10.0)
    for probe in (lambda: deformable.stability(block, soft, duration_s=3.0)[0],
                  lambda: deformable.compress(block, soft, strain=0.1)[0]):
        a, _, b, _ = _both_ways(probe)
        assert a.metrics == b.metrics and a.spec.params == b.spec.params and "mass_scale" not in a.spec.params
