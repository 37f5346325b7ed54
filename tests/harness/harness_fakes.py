"""Deterministic fake probes and helpers for the harness tests (no simulation, no network); fixtures in conftest."""

from __future__ import annotations

import math

from contracts import ProbeResult, ProbeSpec
from contracts.agents import TargetBand, TargetBehaviour

HEALTHY = {"finite": 1.0, "in_domain": 1.0, "engine_health_ok": 1.0, "j_min": 0.9, "j_max": 1.1, "ground_tunnelling_m": 0.0,
           "stable_long_rollout": 1.0}


def fake_modulus_pa(e_pa: float) -> float:
    """Measured effective modulus: a wavy, monotone function of E (not a plain identity)."""
    return e_pa * (1.0 + 0.1 * math.sin(math.log(e_pa)))


def fake_rebound(damping_per_s: float) -> float:
    """Rebound ratio falling with damping."""
    return 0.8 * math.exp(-damping_per_s / 8.0)


class FakeL2Probes:
    """Compression + drop + stability on a fake material; counts calls; optional gate failure rule."""

    def __init__(self, unstable_below_pa: float = 0.0) -> None:
        self.calls: list[dict[str, float]] = []
        self.unstable_below_pa = unstable_below_pa

    def __call__(self, values: dict[str, float], action: str) -> list[ProbeResult]:
        self.calls.append(dict(values))
        e, d = values["youngs_modulus_pa"], values["damping_rate_per_s"]
        health = dict(HEALTHY)
        if e < self.unstable_below_pa:
            health["j_min"] = 0.1  # collapses: too soft
        compress = {**health, "effective_modulus_pa": fake_modulus_pa(e), "recovery_ratio": 0.97}
        drop = {**health, "rebound_ratio": fake_rebound(d), "max_impact_strain": min(1.0, 2e3 / e)}
        lift = {"sag_ratio": min(1.0, 300.0 / e)}
        return [ProbeResult(spec=ProbeSpec(kind="compress"), metrics=compress, sim_calls=1),
                ProbeResult(spec=ProbeSpec(kind="drop"), metrics=drop, sim_calls=1),
                ProbeResult(spec=ProbeSpec(kind="lift"), metrics=lift, sim_calls=1)]


def l2_targets(modulus_pa: float, rebound: float = 0.1, tol: float = 1.1) -> TargetBehaviour:
    """A modulus band of +-10% around modulus_pa and a rebound band of +-0.02."""
    return TargetBehaviour(
        bands=[TargetBand(metric="effective_modulus_pa", unit="Pa", low=modulus_pa / tol, high=modulus_pa * tol, scale="log"),
               TargetBand(metric="rebound_ratio", low=rebound - 0.02, high=rebound + 0.02)],
        priors={"youngs_modulus_pa": 3e4, "poisson_ratio": 0.3, "damping_rate_per_s": 5.0})
