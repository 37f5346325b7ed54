"""L1 placement (tasks.probes.rigid.placement_probe): the object set on the ground settles upright."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.probes import ProbeMetrics, ProbeResult
from tasks.probes import rigid
from tasks.probes.probe import ProbeContext, ProbeModule
from tasks.probes.rigid_probe import body_inputs, l1_parameters, run_rigid

VERSION = "3"  # bump when tasks/probes/rigid.py changes what it returns (2: asset-frame pose, inertia lock;
# 3: at rest by the pose's own change, not pybullet's velocity)


class PlaceMetrics(ProbeMetrics):
    """tasks.probes.rigid.placement_probe's metrics."""

    place_tilt_deg: float | None = None
    place_penetration_m: float | None = None
    place_settle_time_s: float | None = None
    place_drift_m: float | None = None


def measure(body: rigid.RigidBodySpec, params: dict[str, float], trace: rigid.Trace) -> dict[str, float]:
    """The placement probe (looked up at call time)."""
    return rigid.placement_probe(body, duration_s=params["duration_s"], trace=trace)


def run(hulls: list[np.ndarray], particles_m: np.ndarray, mass_kg: float, center_of_mass_m: tuple[float, float, float],
        friction: float, duration_s: float) -> ProbeResult:
    """Placement probe: settles on the ground; tilt, penetration, settle time."""
    return run_rigid("place", "place", measure, hulls, particles_m, mass_kg, center_of_mass_m, friction,
                     {"duration_s": duration_s})


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The candidate body for the contract's settling time."""
    return {**body_inputs(ctx), "duration_s": l1_parameters(ctx).place_duration_s}


PROBE = ProbeModule(stage="L1", name="place", version=VERSION, metrics=PlaceMetrics, run=run, inputs=inputs)
