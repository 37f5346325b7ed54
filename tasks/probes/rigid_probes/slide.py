"""L1 slide (tasks.probes.rigid.slide_probe): sticks just below atan(mu), slides just above with a = g (sin - mu cos)."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.probes import ProbeMetrics, ProbeResult
from tasks.probes import rigid
from tasks.probes.probe import ProbeContext, ProbeModule
from tasks.probes.rigid_probe import body_inputs, l1_parameters, run_rigid

VERSION = "4"  # bump when tasks/probes/rigid.py changes what it returns (2: asset-frame pose, inertia lock;
# 3: at rest by the pose's own change, not pybullet's velocity; 4: no spin kept through the lock)


class SlideMetrics(ProbeMetrics):
    """tasks.probes.rigid.slide_probe's metrics."""

    slide_critical_angle_deg: float | None = None
    slide_below_angle_deg: float | None = None
    slide_above_angle_deg: float | None = None
    slide_below_speed_m_per_s: float | None = None
    slide_below_sticks: float | None = None
    slide_above_slides: float | None = None
    slide_accel_m_per_s2: float | None = None
    slide_accel_expected_m_per_s2: float | None = None
    slide_accel_error_rel: float | None = None


def measure(body: rigid.RigidBodySpec, params: dict[str, float], trace: rigid.Trace) -> dict[str, float]:
    """The slide probe (looked up at call time)."""
    return rigid.slide_probe(body, params["margin_deg"], params["measure_s"], trace=trace)


def run(hulls: list[np.ndarray], particles_m: np.ndarray, mass_kg: float, center_of_mass_m: tuple[float, float, float],
        friction: float, margin_deg: float, measure_s: float) -> ProbeResult:
    """Incline just below / above atan(mu): sticks, then slides with a = g (sin - mu cos)."""
    return run_rigid("slide", "slide", measure, hulls, particles_m, mass_kg, center_of_mass_m, friction,
                     {"margin_deg": margin_deg, "measure_s": measure_s}, sim_calls=2)


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The candidate body on the contract's inclines."""
    p = l1_parameters(ctx)
    return {**body_inputs(ctx), "margin_deg": p.slide_angle_margin_deg, "measure_s": p.slide_measure_s}


PROBE = ProbeModule(stage="L1", name="slide", version=VERSION, metrics=SlideMetrics, run=run, inputs=inputs)
