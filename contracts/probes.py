"""Probe requests and their measured evidence (SI units in every metric name)."""

from __future__ import annotations

import math

from pydantic import ConfigDict, Field

from contracts.base import Model

# What a ProbeSpec's kind names: the probes of the registry (tasks/probes/registry.py: 'place', 'rigid_drop', 'slide',
# 'compress', 'drop', 'lift', 'stability', 'specimen_compress', 'specimen_drop', ...), the mass model ('mass'), L0's
# 'geometry_checks' and L3's 'pick_and_place'. A new probe module adds its own kind; no list here to edit.
ProbeKind = str


class ProbeMetrics(Model):
    """A probe's metrics, typed: one optional float per metric, the unit in its name. A probe module subclasses it to
    declare what it measures; a metric it does not declare is rejected at the boundary (tasks.probes.probe)."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class ProbeSpec(Model):
    """One probe to run; params are probe-specific numbers named with their unit, e.g. 'strain', 'height_m'."""

    kind: ProbeKind
    params: dict[str, float] = Field(default_factory=dict, description="probe settings, unit in each name")
    held_out: bool = Field(default=False, description="an evaluation condition, kept apart from selection")
    duration_s: float | None = Field(default=None, gt=0, description="simulated time [s]")


class HealthStatus(Model):
    """Numerical health of a simulation: ok, or which check failed, when and where."""

    ok: bool = True
    check: str | None = Field(default=None, description="nan | out_of_domain | j_out_of_bounds | energy_blowup | ...")
    step: int | None = None
    sim_time_s: float | None = None
    scene: int | None = None
    particle: int | None = None
    detail: str | None = None


class ProbeResult(Model):
    """What a probe measured. Metrics are scalars with the unit in the name (e.g. 'rebound_ratio', 'sag_m')."""

    spec: ProbeSpec
    metrics: dict[str, float] = Field(default_factory=dict)
    health: HealthStatus = Field(default_factory=HealthStatus)
    sim_calls: int = Field(default=1, ge=0, description="simulations this probe ran")
    wall_time_s: float = Field(default=0.0, ge=0, description="wall time of the probe [s]")
    cache_key: str | None = Field(default=None, description="content key of the probe's cached result")
    recording: str | None = Field(default=None, description="path of the probe's .rrd, relative to the asset")


# Why a target metric can be absent from a candidate's evidence, from the metrics its probes did report (#36): a
# target that was not measured is "not measured" with this reason, never a miss.
def _lift_reason(metrics: dict[str, float]) -> str | None:
    if metrics.get("lift_held") == 0.0:
        rise = metrics.get("pinch_rise_m")
        rose = f": the pinched part rose {rise * 1000:.0f} mm" if isinstance(rise, float) and math.isfinite(rise) else ""
        return f"the lift probe's pinch did not hold the object{rose}, so its sag under its own weight was not seen"
    if "lift_held" not in metrics:
        return "the lift probe did not run for this candidate"
    return None


_MISSING_REASONS = {"sag_ratio": _lift_reason}


def not_measured_reason(metric: str, metrics: dict[str, float]) -> str:
    """Why `metric` is missing (or not finite) among a candidate's metrics, in words."""
    value = metrics.get(metric)
    if value is not None and not math.isfinite(value):
        return f"the probe returned no finite value ({value})"
    explain = _MISSING_REASONS.get(metric)
    why = explain(metrics) if explain else None
    return why or "no probe of this stage reported it"
