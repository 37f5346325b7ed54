"""L1 rigid drop (tasks.probes.rigid.drop_probe): no penetration, rest after the bounce."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.probes import ProbeMetrics, ProbeResult
from tasks.probes import rigid
from tasks.probes.probe import ProbeContext, ProbeModule
from tasks.probes.rigid_probe import body_inputs, l1_parameters, run_rigid

VERSION = "3"  # bump when tasks/probes/rigid.py changes what it returns (2: asset-frame pose, inertia lock;
# 3: at rest by the pose's own change, not pybullet's velocity)


class RigidDropMetrics(ProbeMetrics):
    """tasks.probes.rigid.drop_probe's metrics."""

    drop_clearance_m: float | None = None
    drop_penetration_m: float | None = None
    drop_max_transient_penetration_m: float | None = None
    drop_rest_displacement_m: float | None = None
    drop_tilt_deg: float | None = None
    drop_settle_time_s: float | None = None


def measure(body: rigid.RigidBodySpec, params: dict[str, float], trace: rigid.Trace) -> dict[str, float]:
    """The rigid drop probe (looked up at call time)."""
    return rigid.drop_probe(body, params["clearance_fraction"], params["duration_s"], trace=trace)


def run(hulls: list[np.ndarray], particles_m: np.ndarray, mass_kg: float, center_of_mass_m: tuple[float, float, float],
        friction: float, clearance_fraction: float, duration_s: float) -> ProbeResult:
    """Rigid drop from a fraction of the height: penetration and rest after the bounce."""
    return run_rigid("drop", "rigid_drop", measure, hulls, particles_m, mass_kg, center_of_mass_m, friction,
                     {"clearance_fraction": clearance_fraction, "duration_s": duration_s})


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The candidate body from the contract's drop clearance."""
    p = l1_parameters(ctx)
    return {**body_inputs(ctx), "clearance_fraction": p.drop_clearance_fraction_of_height,
            "duration_s": p.drop_duration_s}


PROBE = ProbeModule(stage="L1", name="drop", version=VERSION, metrics=RigidDropMetrics, run=run, inputs=inputs,
                    spec_kind="rigid_drop", recording="L1_drop.rrd")
