"""The L2 screening keeps a start value whose specimen metric is already well inside its band (the least change that
meets the target) and moves one that misses it towards the band's centre."""

from __future__ import annotations

import pytest

import cache
from contracts.agents import TargetBand, TargetBehaviour
from contracts.stage import load_contract
from flows.l2_material import screen
from contracts.sim import SimConfig
from tests.l2.helpers import box_asset

START = {"youngs_modulus_pa": 2.0e4, "poisson_ratio": 0.3, "damping_rate_per_s": 4.0}


def _contract():  # type: ignore[no-untyped-def]
    c = load_contract("L2")
    return c.model_copy(update={"parameters": {**c.parameters, "specimen_particles_per_axis": 8}})


def _targets(e_band: tuple[float, float], rebound_band: tuple[float, float]) -> TargetBehaviour:
    return TargetBehaviour(bands=[TargetBand(metric="effective_modulus_pa", unit="Pa", low=e_band[0], high=e_band[1],
                                             scale="log"),
                                  TargetBand(metric="rebound_ratio", low=rebound_band[0], high=rebound_band[1])])


def test_screening_keeps_an_in_band_start_and_moves_one_that_misses(prefect_api: str) -> None:
    asset, phys = box_asset((0.1, 0.08, 0.06), 6)
    contract, sim = _contract(), SimConfig()
    with cache.local_runtime():
        # bands the start misses: E is aimed at the band's centre (40 kPa), damping at rebound 0.025
        moved, s1 = screen(asset, phys, contract, _targets((3.0e4, 5.3e4), (0.0, 0.05)), dict(START), sim)
        e_start = s1["compress"]["effective_modulus_pa"][1]
        rb_start = s1["drop"]["rebound_ratio"][s1["drop"]["damping_rate_per_s"].index(START["damping_rate_per_s"])]
        assert not s1["compress"]["kept_start"] and not s1["drop"]["kept_start"]
        assert moved["youngs_modulus_pa"] > 1.5 * START["youngs_modulus_pa"]
        assert moved["damping_rate_per_s"] > START["damping_rate_per_s"]
        # bands that hold the start's own measurements well inside: nothing moves (the same rollouts, cached)
        kept, s2 = screen(asset, phys, contract, _targets((0.5 * e_start, 2.0 * e_start),
                                                          (max(rb_start - 0.2, 0.0), rb_start + 0.2)), dict(START), sim)
    assert s2["compress"]["kept_start"] and s2["drop"]["kept_start"]
    assert kept == START
    # the three moduli each at its own time step (one lock-step batch ran all at the stiffest dt for the softest
    # duration, 3x the steps), the damping sweep's three at one shared dt in one rollout
    assert s2["compress"]["sim_calls"] == s1["compress"]["sim_calls"] == 3
    assert s2["drop"]["sim_calls"] == s1["drop"]["sim_calls"] == 1


def test_the_inner_band_leaves_a_margin_at_each_end_in_the_band_scale() -> None:
    b = TargetBand(metric="effective_modulus_pa", unit="Pa", low=1.0e4, high=1.0e6, scale="log")
    assert b.point(0.5) == pytest.approx(1.0e5) and b.point(0.1) == pytest.approx(10 ** 4.2)
    assert b.contains(1.1e4) and not b.contains_inner(1.1e4) and b.contains_inner(2.0e4)
    lin = TargetBand(metric="rebound_ratio", low=0.4, high=0.8)
    assert lin.contains_inner(0.45) and not lin.contains_inner(0.42) and not lin.contains_inner(0.79)
