"""Per-simulator calibration: fit a target's own stiffness and damping so its probes match L2's (few simulations).

Two 1-D searches, each on a log scale:
  1. stiffness: the target's Young's modulus so that its compression probe gives L2's effective modulus. The
     effective modulus is close to proportional to E, so the first step is E * (target / measured), then secant steps
     on (log E, log measured) until within `tol` (3 compressions at most);
  2. rebound: knobs that lower the rebound as they grow (fit_rebound), in turn: bracketed on a log scale from the
     current value (in one jump to the bound, or in steps of at most `max_step` for a knob whose simulations cost more
     as it moves, such as the timestep), then regula falsi inside the bracket. A knob that cannot reach the target
     stays at its bound and the next one moves (MuJoCo: its timestep first, whose numerical dissipation takes energy
     from a stiff body's impact, then its flex damping).
fit_both alternates the two until both hold: a damping fitted to the rebound can move the modulus, a timestep too.
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


MAX_YOUNG_STEP = 4.0  # a modulus fit moves E at most this factor per simulation


def fit_modulus(measure: Callable[[float], float], young0: float, target: float, tol: float = 0.05,
                max_sims: int = 3, first: float | None = None) -> tuple[float, float, list[CalibrationStep]]:
    """Secant on (log E, log effective modulus), each step at most MAX_YOUNG_STEP from the last E (a probe that
    barely responds to E, as a mis-measured one, must not send E to 1e12 Pa and the simulator's substeps with it);
    `first` is the measurement at young0 when already made. Returns (best E, its measurement, steps)."""
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
        e = min(pts[-1][0] * MAX_YOUNG_STEP, max(pts[-1][0] / MAX_YOUNG_STEP, e))
        pts.append((e, run(e)))
    best = min(pts, key=lambda p: abs(rel(p[1], target)) if math.isfinite(p[1]) else math.inf)
    return best[0], best[1], steps


@dataclass
class Knob:
    """A parameter that lowers the rebound as it grows (a damping, a timestep), searched on a log scale in [low, high]."""

    name: str
    start: float
    low: float
    high: float
    max_step: float | None = None  # bracketing moves at most this factor from the nearest tried value (None: bound)
    values: dict[float, float] = field(default_factory=dict)  # tried value -> rebound

    def toward(self, low: bool) -> float:
        """The next bracketing value toward the low (more rebound) or the high bound."""
        bound = self.low if low else self.high
        if self.max_step is None or not self.values:
            return bound
        near = min(self.values) if low else max(self.values)
        return max(bound, near / self.max_step) if low else min(bound, near * self.max_step)


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
            if (above and below) or abs(rel(best[0], target)) <= tol:
                break
            v = k.toward(low=not above)
            if v in k.values:
                break
            run(k, v)
        above = [v for v, r in k.values.items() if r >= target]
        below = [v for v, r in k.values.items() if r <= target]
        if not (above and below):
            bound = min(k.values) if not above else max(k.values)  # the tried value nearest the target; next knob
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


def fit_both(modulus: Callable[[dict[str, float]], float], rebound: Callable[[dict[str, float]], float],
             knobs_of: Callable[[dict[str, float]], list[Knob]], values: dict[str, float], e_target: float,
             r_target: float, tol: float = 0.05, refit_tol: float = 0.10, rounds: int = 3,
             rebound_sims: int = 6) -> tuple[dict[str, float], list[CalibrationStep]]:
    """Young's modulus to e_target (fit_modulus), then the knobs to r_target (fit_rebound), both again while the
    modulus misses by more than refit_tol after a round (a damping or timestep fitted to the rebound can move it; a
    rebound still missing with the modulus in place is the knobs' best, and another round would not change it). Each
    fit aims at tol. modulus / rebound take every parameter (values, "young_pa" among them) and should be memoized by
    the caller: a round re-reads values it already measured. Returns (values, steps)."""
    values = dict(values)
    steps: list[CalibrationStep] = []
    for _ in range(rounds):
        m = modulus(values)
        if abs(rel(m, e_target)) > tol:
            young, _, s = fit_modulus(lambda e: modulus({**values, "young_pa": e}), values["young_pa"], e_target, tol,
                                      first=m)
            values["young_pa"] = young
            steps += s
        r = rebound(values)
        if abs(rel(r, r_target)) > tol:
            fitted, _, s = fit_rebound(lambda v: rebound({**values, **v}), knobs_of(values), r_target, tol,
                                       max_sims=rebound_sims, first=r)
            values.update(fitted)
            steps += s
        if abs(rel(modulus(values), e_target)) <= refit_tol:  # else the rebound's knobs moved it: once more
            break
    return values, steps


__all__ = ["Calibration", "CalibrationStep", "Knob", "fit_both", "fit_modulus", "fit_rebound", "rel"]
