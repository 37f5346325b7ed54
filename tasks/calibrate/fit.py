"""Fit E and the Kelvin-Voigt viscosity to the video's metrics (and a press test) with the engine's own probes and
the crosscheck calibration's searches (tasks.export.calibrate):

- E from the impact strain: Hertz puts the compression of an impact at strain ~ E^(-2/5), so strain^(-5/2) (the
  "impact modulus index") is close to proportional to E, as fit_modulus expects of its metric; from a press test
  instead (when given): L2's compression probe's effective modulus against the table's (fit_modulus as crosscheck);
- the viscosity from the rebound ratio: a knob that lowers the rebound as it grows (fit_rebound's bracketing and
  regula falsi on a log scale);
- both together (fit_both) when the video gives both: a viscosity fitted to the rebound moves the strain a little;
- E from the settle time when the video shows no compression (an impact between two frames) nor a press test but
  shows the bounces end: how the restitution changes over the slower bounces depends on E (a softer body's longer
  contact: the engine loses less at low speed, the Kelvin-Voigt loss grows with speed), so E is searched on a log
  scale (secant on log settle time, bounded) with the viscosity refitted to the rebound at each E, until the
  simulated settle time is within SETTLE_TOLERANCE of the video's.
A metric the video could not determine leaves its parameter at the prior (no bounce: the viscosity is fitted to the
rebound's detection limit, a lower bound on the loss); the caller records which.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from contracts.material import VISCOUS_DT_FACTOR, Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from contracts.video_fit import FitStep, PressTest
from tasks.calibrate.press import probe_modulus
from tasks.calibrate.sim import bounce_settle, drop_impact
from tasks.export.calibrate import Knob, fit_both, fit_modulus, fit_rebound, rel
from tasks.probes.rollout import DeformableBody, dx_of
from tasks.realworld.impact import contact_time_s
from tasks.realworld.loss import damping_ratio, viscosity_for_damping_ratio

TOLERANCE = 0.03  # each metric is fitted to within 3 %
ENGINE_RESTITUTION = 0.9  # the engine's own restitution at no viscosity, for the first guess only (loss.py: 0.82-0.94)
MIN_DT_S = 2e-6  # the viscosity's upper bound: its explicit time step stays above this
SETTLE_TOLERANCE = 0.05  # E from the settle time: fitted to within 5 %
SETTLE_E_RANGE = (0.1, 10.0)  # ... searched within a decade of the prior's E either way
SETTLE_E_SIMS = 6  # ... with at most this many values of E


def strain_index(strain: float) -> float:
    """strain^(-5/2): close to proportional to E for an impact (Hertz)."""
    return max(strain, 1e-4) ** -2.5


@dataclass
class FitProblem:
    """The scaled body, the prior, the drop and what the fit aims at (None: not determined)."""

    positions_m: np.ndarray
    volumes_m3: np.ndarray
    physical: PhysicalModel
    prior: Material
    drop_height_m: float
    sim: SimConfig
    strain: float | None = None
    rebound: float | None = None
    rebound_limit: float | None = None  # no bounce: the rebound the video would have seen
    press: PressTest | None = None
    settle: float | None = None  # the video's settle time [s]
    settle_tolerance_m: float | None = None
    frame_times_s: np.ndarray | None = None  # the video's tracked frames, for the settle rule
    release_t_s: float = 0.0
    settle_tail: int = 5
    steps: list[FitStep] = field(default_factory=list)
    _memo: dict[tuple[float, float, float], dict[str, float]] = field(default_factory=dict)
    _settle_memo: dict[tuple[float, float, float], dict[str, float]] = field(default_factory=dict)

    def bounces(self, young: float, eta: float, damping: float | None = None) -> dict[str, float]:
        """The bounces after the drop until a rise is under the video's settle tolerance (sim.bounce_settle), sampled
        at the video's frames (memoized)."""
        assert self.settle_tolerance_m is not None
        d = self.prior.damping_rate_per_s if damping is None else damping
        key = (float(f"{young:.6g}"), float(f"{eta:.6g}"), float(f"{d:.6g}"))
        if key not in self._settle_memo:
            mat = self.prior.model_copy(update={"youngs_modulus_pa": key[0], "viscosity_pa_s": key[1],
                                                "damping_rate_per_s": key[2]})
            out = bounce_settle(self.positions_m, self.volumes_m3, self.physical, mat, self.drop_height_m, self.sim,
                                self.settle_tolerance_m, self.frame_times_s, self.release_t_s, self.settle_tail)
            self._settle_memo[key] = out
            self.steps.append(FitStep(youngs_modulus_pa=key[0], viscosity_pa_s=key[1], damping_rate_per_s=key[2],
                                      probe="bounces", metrics={k: v for k, v in out.items() if math.isfinite(v)}))
        return self._settle_memo[key]

    def settle_time(self, young: float, eta: float, damping: float | None = None) -> float:
        """The simulated settle time as the video's rule reads it (the continuous one when it outlasts the frames)."""
        out = self.bounces(young, eta, damping)
        return out.get("settle_time_frames_s", out["settle_time_s"])

    def drop(self, young: float, eta: float, damping: float | None = None) -> dict[str, float]:
        """The video's drop in the engine with this E, viscosity and damping rate (None: the prior's; memoized)."""
        d = self.prior.damping_rate_per_s if damping is None else damping
        key = (float(f"{young:.6g}"), float(f"{eta:.6g}"), float(f"{d:.6g}"))
        if key not in self._memo:
            mat = self.prior.model_copy(update={"youngs_modulus_pa": key[0], "viscosity_pa_s": key[1],
                                                "damping_rate_per_s": key[2]})
            m = drop_impact(self.positions_m, self.volumes_m3, self.physical, mat, self.drop_height_m, self.sim)
            self._memo[key] = m
            self.steps.append(FitStep(youngs_modulus_pa=key[0], viscosity_pa_s=key[1], damping_rate_per_s=key[2],
                                      probe="drop_impact", metrics={k: v for k, v in m.items() if k in SHOWN}))
        return self._memo[key]

    def press_modulus(self, young: float, eta: float) -> float:
        """L2's compression probe on the body at the press test's strain."""
        assert self.press is not None
        body = DeformableBody.from_physical(self.positions_m, self.volumes_m3, self.physical)
        mat = self.prior.model_copy(update={"youngs_modulus_pa": young, "viscosity_pa_s": eta})
        v = probe_modulus(body, mat, self.press.strain, self.sim)
        self.steps.append(FitStep(youngs_modulus_pa=young, viscosity_pa_s=eta, probe="compress",
                                  metrics={"effective_modulus_pa": v} if math.isfinite(v) else {}))
        return v

    def metric(self, name: str) -> Callable[[dict[str, float]], float]:
        """A metric of the drop as a function of the parameters (young_pa, viscosity_pa_s)."""
        def f(v: dict[str, float]) -> float:
            m = self.drop(v["young_pa"], v["viscosity_pa_s"], v.get("damping_rate_per_s"))
            if name == "index":
                return strain_index(m["impact_strain"]) if "impact_strain" in m else math.nan
            return m.get(name, math.nan)
        return f

    def viscosity_knob(self, young: float, start: float | None = None) -> Knob:
        """The viscosity as a knob: from `start` (else a first guess), bounded on a log scale."""
        guess = start if start and start > 0 else self.first_viscosity(young)
        body = DeformableBody.from_physical(self.positions_m, self.volumes_m3, self.physical)
        dx = dx_of(body, self.sim)
        high = VISCOUS_DT_FACTOR * self.physical.density_kg_per_m3 * dx * dx / MIN_DT_S
        return Knob("viscosity_pa_s", start=min(guess, high), low=min(guess, high) * 1e-3, high=high, max_step=10.0)

    def knobs(self, v: dict[str, float]) -> list[Knob]:
        """The rebound's knobs in turn: the viscosity, then (when even the least viscosity leaves too little rebound)
        the asset's damping rate, which also slows the fall and the rise, down to a thousandth of the prior's."""
        out = [self.viscosity_knob(v["young_pa"], v.get("viscosity_pa_s"))]
        d = v.get("damping_rate_per_s", self.prior.damping_rate_per_s)
        if d > 0:
            out.append(Knob("damping_rate_per_s", start=d, low=1e-3 * self.prior.damping_rate_per_s,
                            high=max(d, self.prior.damping_rate_per_s), max_step=4.0))
        return out

    def first_viscosity(self, young: float) -> float:
        """The closed form of tasks.realworld.loss for the rebound aimed at (its restitution sqrt(rebound)), with the
        engine's own loss taken as ENGINE_RESTITUTION."""
        target = self.rebound if self.rebound is not None else (self.rebound_limit or 0.01)
        e = min(0.999, math.sqrt(max(target, 1e-4)) / ENGINE_RESTITUTION)
        radius = 0.5 * float(np.ptp(self.positions_m, axis=0).min() + self.physical.particle_spacing_m)
        tc = contact_time_s(self.physical.mass_kg, radius, young, self.prior.poisson_ratio,
                            math.sqrt(2 * 9.81 * self.drop_height_m))
        return max(viscosity_for_damping_ratio(damping_ratio(e), young, tc), 1e-3 * young * tc)


SHOWN = ("impact_strain", "rebound_ratio", "restitution", "contact_time_s", "contact_sink_m", "finite")


@dataclass
class FitResult:
    """The fitted material, where each parameter came from, the simulated metrics and residuals."""

    material: Material
    young_source: Literal["impact_strain", "press", "settle_time", "prior"]
    viscosity_source: Literal["rebound", "no_bounce_lower_bound", "prior"]
    simulated: dict[str, float]
    residuals: dict[str, float]
    converged: bool
    notes: list[str]


def rebound_at(p: FitProblem, young: float, damping: float, target: float) -> tuple[float, float]:
    """The viscosity (and, past its reach, the damping rate) that gives the rebound `target` at this E."""
    start = {"young_pa": young, "viscosity_pa_s": p.viscosity_knob(young).start, "damping_rate_per_s": damping}
    values, _, _ = fit_rebound(lambda v: p.metric("rebound_ratio")({**start, **v}), p.knobs(start), target,
                               TOLERANCE, max_sims=10)
    return values["viscosity_pa_s"], values.get("damping_rate_per_s", damping)


def fit_settle(p: FitProblem, prior_young: float, damping: float, target: float, notes: list[str]
               ) -> tuple[float, float, float]:
    """E from the settle time, the viscosity from the rebound at each E (see the module docstring): (E, viscosity,
    damping) of the E whose simulated settle time is nearest the video's."""
    assert p.settle is not None
    goal = p.settle
    lo, hi = prior_young * SETTLE_E_RANGE[0], prior_young * SETTLE_E_RANGE[1]
    tried: dict[float, tuple[float, float, float]] = {}  # E -> (settle, viscosity, damping)
    short: set[float] = set()  # E whose rebound stays short of the target even at the knobs' least loss

    def at(young: float) -> float:
        young = float(min(hi, max(lo, young)))
        if young not in tried:
            eta, d = rebound_at(p, young, damping, target)
            tried[young] = (p.settle_time(young, eta, d), eta, d)
            if p.drop(young, eta, d).get("rebound_ratio", 0.0) < target * (1.0 - 2 * TOLERANCE):
                short.add(young)
        return tried[young][0]

    def log_slope(reach: list[float]) -> float | None:
        """d log(settle) / d log(E) between the two reachable E whose settle times are nearest the video's."""
        a, b = sorted(reach, key=lambda e: abs(math.log(tried[e][0] / goal)))[:2]
        k = math.log(tried[b][0] / tried[a][0]) / math.log(b / a)
        return k if abs(k) > 1e-3 else None

    young = prior_young
    s = at(young)
    step = 4.0
    while len(tried) < SETTLE_E_SIMS and (abs(s / p.settle - 1.0) > SETTLE_TOLERANCE or young in short):
        reach = [e for e in tried if e not in short]
        if not reach or young in short:
            # a body that loses more than the rebound allows at the least viscosity (a hollow shell buckling at
            # the impact) is too soft: the rebound rules the E out whatever its settle time; stiffer, bisecting
            # on log E toward the softest E that reached it
            stiffer = [e for e in reach if e > max(short)]
            young = float(min(hi, math.sqrt(max(short) * min(stiffer)) if stiffer else max(short) * step))
            if young in tried:
                break
            s = at(young)
            continue
        below = [e for e in reach if tried[e][0] < p.settle]  # too short: a softer E lengthens it (a solid's)
        above = [e for e in reach if tried[e][0] >= p.settle]
        if below and above:  # bracketed: secant on log E against log settle time between the nearest two
            a = max(below, key=lambda e: tried[e][0])
            b = min(above, key=lambda e: tried[e][0])
            sa, sb = math.log(tried[a][0]), math.log(tried[b][0])
            f = (math.log(p.settle) - sa) / (sb - sa) if sb != sa else 0.5
            young = math.exp(math.log(a) + min(0.9, max(0.1, f)) * (math.log(b) - math.log(a)))
        elif len(reach) >= 2 and (slope := log_slope(reach)) is not None:
            # not bracketed: the settle time's own trend with E (a shell's may run either way), from the two
            # nearest the video's, extrapolated at most a step
            a = min(reach, key=lambda e: abs(math.log(tried[e][0] / goal)))
            young = a * min(step, max(1.0 / step, math.exp(math.log(goal / tried[a][0]) / slope)))
        elif below:
            young = min(below) / step
        else:
            young = max(above) * step
        floor = [e for e in short if e < min(reach)]
        if floor and young <= max(floor):  # not past an E the rebound ruled out: bisect on log E
            young = math.sqrt(max(floor) * min(reach))
        young = float(min(hi, max(lo, young)))
        if young in tried:
            break
        s = at(young)
    reach = [e for e in tried if e not in short] or list(tried)
    best = min(reach, key=lambda e: abs(math.log(tried[e][0] / goal)))
    settle, eta, d = tried[best]
    if short:
        notes.append(f"the rebound is out of the viscosity's reach at E <= {max(short):.4g} Pa (too much loss at the "
                     "least viscosity): those E were ruled out")
    if len(tried) == 1:
        notes.append(f"E from the settle time (the video shows no compression): the prior's {prior_young:.4g} Pa "
                     f"already gives it (simulated {settle:.3g} s, the video's {goal:.3g} s)")
    else:
        notes.append(f"E from the settle time (the video shows no compression): {best:.4g} Pa, {len(tried)} values "
                     f"tried from the prior's {prior_young:.4g} Pa, the viscosity refitted to the rebound at each; "
                     f"simulated settle {settle:.3g} s against the video's {goal:.3g} s")
    if abs(settle / p.settle - 1.0) > 2 * SETTLE_TOLERANCE:
        notes.append(f"the settle time is out of E's reach within {SETTLE_E_RANGE[0]:g}-{SETTLE_E_RANGE[1]:g} x the "
                     "prior's E")
    return best, eta, d


def fit(p: FitProblem) -> FitResult:
    """Fit E and the viscosity as the module docstring says."""
    young, eta, damping = p.prior.youngs_modulus_pa, p.prior.viscosity_pa_s, p.prior.damping_rate_per_s
    notes: list[str] = []
    young_source: Literal["impact_strain", "press", "settle_time", "prior"] = "prior"
    if p.press is not None:
        target = p.press.effective_modulus_pa
        young, _, _ = fit_modulus(lambda e: p.press_modulus(e, eta), young, target, TOLERANCE, max_sims=4)
        young_source = "press"
    r_target = p.rebound if p.rebound is not None and p.rebound > 0 else p.rebound_limit
    visc_source: Literal["rebound", "no_bounce_lower_bound", "prior"] = (
        "prior" if r_target is None else ("rebound" if p.rebound else "no_bounce_lower_bound"))
    if young_source == "prior" and p.strain is not None and r_target is not None:
        values, _ = fit_both(p.metric("index"), p.metric("rebound_ratio"), p.knobs,
                             {"young_pa": young, "viscosity_pa_s": p.viscosity_knob(young).start,
                              "damping_rate_per_s": damping},
                             strain_index(p.strain), r_target, tol=TOLERANCE, refit_tol=TOLERANCE, rebound_sims=10)
        young, eta, young_source = values["young_pa"], values["viscosity_pa_s"], "impact_strain"
        damping = values["damping_rate_per_s"]
    elif young_source == "prior" and p.strain is not None:
        young, _, _ = fit_modulus(lambda e: p.metric("index")({"young_pa": e, "viscosity_pa_s": eta}), young,
                                  strain_index(p.strain), TOLERANCE, max_sims=5)
        young_source = "impact_strain"
    elif r_target is not None and young_source == "prior" and p.rebound and p.settle and p.settle_tolerance_m:
        young, eta, damping = fit_settle(p, young, damping, r_target, notes)
        young_source = "settle_time"
    elif r_target is not None:
        eta, damping = rebound_at(p, young, damping, r_target)
    material = p.prior.model_copy(update={"youngs_modulus_pa": young, "viscosity_pa_s": eta,
                                          "damping_rate_per_s": damping})
    sim = p.drop(young, eta, damping)
    simulated: dict[str, float] = {k: sim[k] for k in ("impact_strain", "rebound_ratio", "restitution",
                                                        "contact_time_s") if k in sim}
    residuals: dict[str, float] = {}
    if p.strain is not None and "impact_strain" in sim:
        residuals["impact_strain"] = rel(sim["impact_strain"], p.strain)
    if p.rebound is not None and p.rebound > 0 and "rebound_ratio" in sim:
        residuals["rebound_ratio"] = rel(sim["rebound_ratio"], p.rebound)
    if p.press is not None:
        last = [s for s in p.steps if s.probe == "compress" and s.youngs_modulus_pa == young]
        if last and "effective_modulus_pa" in last[-1].metrics:
            simulated["effective_modulus_pa"] = last[-1].metrics["effective_modulus_pa"]
            residuals["effective_modulus_pa"] = rel(simulated["effective_modulus_pa"], p.press.effective_modulus_pa)
    if damping != p.prior.damping_rate_per_s:
        notes.append(f"the damping rate moved {p.prior.damping_rate_per_s:.4g} -> {damping:.4g} 1/s: even the least "
                     "viscosity left less rebound than the video shows")
    if visc_source == "rebound" and abs(residuals.get("rebound_ratio", 0.0)) > 2 * TOLERANCE:
        notes.append(f"the rebound is out of the knobs' reach: simulated {simulated.get('rebound_ratio', math.nan):.3g} "
                     f"at the viscosity's and the damping's bounds, the video's {p.rebound:.3g}")
    if visc_source == "no_bounce_lower_bound":
        notes.append(f"no bounce: the viscosity is the least that keeps the rebound under the video's detection limit "
                     f"({r_target:.3g}); more would look the same")
    fitted = {"impact_strain": young_source == "impact_strain", "rebound_ratio": visc_source == "rebound",
              "effective_modulus_pa": young_source == "press", "settle_time_s": young_source == "settle_time"}
    converged = all(abs(v) <= 2 * TOLERANCE for k, v in residuals.items() if fitted.get(k))
    return FitResult(material, young_source, visc_source, simulated, residuals, converged, notes)


__all__ = ["FitProblem", "FitResult", "SETTLE_TOLERANCE", "TOLERANCE", "fit", "fit_settle", "rebound_at",
           "strain_index"]
