"""Per-simulator calibration: fit a target's own stiffness and damping so its probes match L2's (few simulations).

Two 1-D searches, each on a log scale:
  1. stiffness: the target's Young's modulus so that its compression probe gives L2's effective modulus. The
     effective modulus is close to proportional to E, so the first step is E * (target / measured), then secant steps
     on (log E, log measured) until within `tol` (3 compressions at most);
  2. rebound: a damping knob (decreasing rebound) so that the drop probe gives L2's rebound ratio: bracketed on a log
     scale from the exported value, then regula falsi inside the bracket (5 drops at most). A simulator whose damping
     alone cannot reach the rebound (MuJoCo's contacts absorb the impact by themselves) offers a second knob, used
     once the first is at its bound (fit_rebound's `knobs`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from pydantic import BaseModel, ConfigDict, Field


class CalibrationStep(BaseModel):
    """One simulation of the search: the parameter tried and the metric it gave."""

    model_config = ConfigDict(extra="forbid")

    parameter: str
    value: float
    metric: str
    measured: float
    target: float


class Calibration(BaseModel):
    """Fitted parameters, their residuals and the probes used (TargetManifest.calibrated)."""

    model_config = ConfigDict(extra="forbid")

    sim: str
    parameters: dict[str, float] = Field(description="fitted values of the target's own parameters")
    initial: dict[str, float] = Field(description="the values exported before calibration")
    residuals: dict[str, float] = Field(description="metric -> (theirs - ours) / ours after calibration")
    residuals_before: dict[str, float] = Field(default_factory=dict)
    probes: list[str] = Field(description="L2 probes (and their settings) the fit used")
    history: list[CalibrationStep] = Field(default_factory=list)
    sim_calls: int = 0
    converged: bool = False
    notes: list[str] = Field(default_factory=list)


def rel(measured: float, target: float) -> float:
    """(measured - target) / target."""
    return (measured - target) / target if target else math.nan


def fit_modulus(measure: Callable[[float], float], young0: float, target: float, tol: float = 0.05,
                max_sims: int = 3, first: float | None = None) -> tuple[float, float, list[CalibrationStep]]:
    """Secant on (log E, log effective modulus); `first` is the measurement at young0 when already made.
    Returns (best E, its measurement, steps)."""
    steps: list[CalibrationStep] = []
    pts: list[tuple[float, float]] = []

    def run(e: float) -> float:
        m = measure(e)
        steps.append(CalibrationStep(parameter="young_pa", value=e, metric="effective_modulus_pa", measured=m,
                                     target=target))
        return m

    m0 = first if first is not None else run(young0)
    pts.append((young0, m0))
    e = young0
    while len(steps) < max_sims and math.isfinite(pts[-1][1]) and pts[-1][1] > 0 and abs(rel(pts[-1][1], target)) > tol:
        if len(pts) >= 2 and pts[-1][1] != pts[-2][1] and pts[-1][0] != pts[-2][0]:
            (e1, m1), (e2, m2) = pts[-2], pts[-1]
            slope = (math.log(m2) - math.log(m1)) / (math.log(e2) - math.log(e1))
            slope = min(3.0, max(0.3, slope))
        else:
            slope = 1.0
        e = pts[-1][0] * math.exp((math.log(target) - math.log(pts[-1][1])) / slope)
        pts.append((e, run(e)))
    best = min(pts, key=lambda p: abs(rel(p[1], target)) if math.isfinite(p[1]) else math.inf)
    return best[0], best[1], steps


@dataclass
class Knob:
    """A damping parameter that lowers the rebound as it grows, searched on a log scale within [low, high]."""

    name: str
    start: float
    low: float
    high: float
    values: dict[float, float] = field(default_factory=dict)  # tried value -> rebound


def fit_rebound(measure: Callable[[dict[str, float]], float], knobs: Sequence[Knob], target: float, tol: float = 0.05,
                max_sims: int = 5, first: float | None = None) -> tuple[dict[str, float], float, list[CalibrationStep]]:
    """Fit the rebound ratio with the knobs in turn: the first knob moves within its bounds; when the target lies
    beyond its low bound (too little rebound even at the least damping), it stays there and the next knob moves.
    measure(values) runs the drop with every knob at the given value and returns the rebound ratio; `first` is the
    rebound at the knobs' start values when already measured. Returns (knob values, rebound, steps)."""
    steps: list[CalibrationStep] = []
    chosen = {k.name: k.start for k in knobs}
    best: list = [math.nan, dict(chosen)]

    def run(k: Knob, v: float) -> float:
        values = {**chosen, k.name: v}
        r = measure(values)
        k.values[v] = r
        steps.append(CalibrationStep(parameter=k.name, value=v, metric="rebound_ratio", measured=r, target=target))
        if not math.isfinite(best[0]) or abs(r - target) < abs(best[0] - target):
            best[0], best[1] = r, values
        return r

    if first is not None:
        knobs[0].values[knobs[0].start] = first
        best[0] = first
    for k in knobs:
        if (math.isfinite(best[0]) and abs(rel(best[0], target)) <= tol) or len(steps) >= max_sims:
            break
        if not k.values:
            run(k, k.start)
        # bracket on this knob: more damping -> less rebound
        while len(steps) < max_sims:
            above = [v for v, r in k.values.items() if r >= target]
            below = [v for v, r in k.values.items() if r <= target]
            if above and below:
                break
            v = k.low if not above else k.high
            if v in k.values:
                break
            run(k, v)
        above = [v for v, r in k.values.items() if r >= target]
        below = [v for v, r in k.values.items() if r <= target]
        if not (above and below):
            bound = k.low if not above else k.high  # the bound nearest the target; on to the next knob
            chosen[k.name] = bound
            nxt = knobs.index(k) + 1
            if nxt < len(knobs) and bound in k.values:  # the next knob's start is this very setting
                knobs[nxt].values.setdefault(knobs[nxt].start, k.values[bound])
            continue
        lo_v, hi_v = max(above), min(below)
        ra, rb = k.values[lo_v], k.values[hi_v]
        side = 0
        while len(steps) < max_sims and abs(rel(best[0], target)) > tol:
            a, b = math.log(lo_v), math.log(hi_v)
            w = (ra - target) / (ra - rb) if ra != rb else 0.5
            v = math.exp(a + min(0.9, max(0.1, w)) * (b - a))
            r = run(k, v)
            if r >= target:  # Illinois: halve the far end's weight when the same end moves twice
                lo_v, ra = v, r
                rb = target + 0.5 * (rb - target) if side == 1 else rb
                side = 1
            else:
                hi_v, rb = v, r
                ra = target + 0.5 * (ra - target) if side == -1 else ra
                side = -1
        break
    return dict(best[1]), float(best[0]), steps


__all__ = ["Calibration", "CalibrationStep", "Knob", "fit_modulus", "fit_rebound", "rel"]
