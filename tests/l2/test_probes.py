"""The MPM probes measure the physics they claim (cube modulus, rebound ordering, sag ordering, stability)."""

from __future__ import annotations

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.probes.deformable import compress, drop, lift, stability
from tests.l2.helpers import box_body


def test_cube_compression_gives_youngs_modulus_within_15_percent() -> None:
    """Small-strain compression of a cube: secant stress/strain matches E for two batched materials."""
    body = box_body((0.1, 0.1, 0.1), 8)
    mats = [Material(youngs_modulus_pa=e, poisson_ratio=0.3, damping_rate_per_s=5.0) for e in (1.0e4, 4.0e4)]
    results = compress(body, mats, strain=0.05)
    assert len(results) == 2 and results[0].sim_calls == 1
    for m, r in zip(mats, results):
        assert r.health.ok
        e_eff = r.metrics["effective_modulus_pa"]
        assert abs(e_eff - m.youngs_modulus_pa) / m.youngs_modulus_pa < 0.15, (m.youngs_modulus_pa, e_eff)
        assert abs(r.metrics["compression_strain"] - 0.05) < 0.01
        assert r.metrics["recovery_ratio"] > 0.9
        assert r.metrics["finite"] == 1.0 and r.metrics["j_min"] > 0.8


def test_drop_rebound_separates_lively_from_dead() -> None:
    """A stiff lightly damped body rebounds more and dissipates less than a soft heavily damped one."""
    body = box_body((0.08, 0.08, 0.06), 6)
    lively = Material(youngs_modulus_pa=3.0e5, poisson_ratio=0.3, damping_rate_per_s=0.5)
    dead = Material(youngs_modulus_pa=2.0e4, poisson_ratio=0.3, damping_rate_per_s=30.0)
    r_lively, r_dead = drop(body, [lively, dead], height_fraction=0.5)
    for r in (r_lively, r_dead):
        assert r.health.ok and r.metrics["ground_tunnelling_m"] <= 0.002
        assert 0.0 <= r.metrics["rebound_ratio"] <= 1.0
    assert r_lively.metrics["rebound_ratio"] > r_dead.metrics["rebound_ratio"] + 0.1
    assert r_dead.metrics["dissipated_energy_fraction"] > r_lively.metrics["dissipated_energy_fraction"]
    assert r_lively.metrics["max_impact_strain"] > 0.0


def test_lift_sag_matches_a_cantilever_under_self_weight() -> None:
    """A bar pinched at its centre and lifted: each half droops like a cantilever, 3 rho g l^4 / (2 E h^2)."""
    body = box_body((0.24, 0.05, 0.06), 24, density=100.0, gripper_friction=1.0)
    mats = [Material(youngs_modulus_pa=e, poisson_ratio=0.3, damping_rate_per_s=10.0) for e in (5.0e3, 1.0e5)]
    results = lift(body, mats)
    half_length, h = 0.12, 0.06
    for m, r in zip(mats, results):
        assert r.health.ok and r.metrics["lift_held"] == 1.0
        expected = 3 * 100.0 * 9.81 * half_length**4 / (2 * m.youngs_modulus_pa * h * h)
        assert abs(r.metrics["sag_m"] - expected) < 0.3 * expected + 5e-4, (m.youngs_modulus_pa, r.metrics["sag_m"])
    assert results[0].metrics["sag_ratio"] > 5.0 * results[1].metrics["sag_ratio"]


def test_stability_passes_a_sane_material_and_flags_a_blowup() -> None:
    """3 s at rest: healthy numerics give stable_long_rollout = 1; a fixed dt far above the CFL limit gives 0."""
    body = box_body((0.06, 0.06, 0.04), 6)
    mat = Material(youngs_modulus_pa=2.0e4, poisson_ratio=0.3, damping_rate_per_s=5.0)
    good = stability(body, mat, duration_s=3.0)[0]
    assert good.health.ok and good.metrics["stable_long_rollout"] == 1.0
    bad = stability(body, mat, duration_s=3.0, sim=SimConfig(dt_fixed_s=5e-3))[0]
    assert not bad.health.ok and bad.health.check is not None
    assert bad.metrics["stable_long_rollout"] == 0.0 and bad.metrics["engine_health_ok"] == 0.0
