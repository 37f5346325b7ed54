"""The offline default backend: deterministic Planner, Designer and Critic driven by the route tables."""

from __future__ import annotations

import math

from contracts.agents import (
    Candidate, Critique, CriticRequest, DesignerRequest, HistoryEntry, PlannerContext, PlannerDecision, TargetBehaviour,
)
from contracts.evidence import AgentSource
from contracts.stage import EditableField
from tasks.agents.backend import RoleReply
from tasks.agents.search import Point, bisect_step, enumerate_step, from_u, root_step, span, to_u
from tasks.agents.vocab import StageRoutes, stage_routes

STAGE_DIAGNOSIS = {"L0": "geometry", "L1": "material", "L2": "material", "L3": "action"}
INITIAL_PREFIXES = ("propose", "build", "import")


def rule_source() -> AgentSource:
    """The AgentSource of the rule backend."""
    return AgentSource(backend="rule")


def _fmt(values: dict[str, float]) -> str:
    return ", ".join(f"{k}={v:.4g}" for k, v in values.items()) or "no change"


def _primary_band(field: str, targets: TargetBehaviour, history: list[HistoryEntry], routes: StageRoutes):
    """(band, slope) of the unmet target this field should chase: the worst weighted deviation at the latest probe."""
    latest = next((h for h in reversed(history) if h.probed), None)
    if latest is None:
        return None
    best = None
    for metric, slope in routes.couplings_of(field).items():
        band = targets.band(metric)
        if band is None or band.weight <= 0 or metric not in latest.metrics:
            continue
        dev = band.deviation(latest.metrics[metric])
        if dev > 0 and math.isfinite(dev) and (best is None or band.weight * dev > best[0]):
            best = (band.weight * dev, band, slope)
    return None if best is None else best[1:]


def propose_field(
    spec: EditableField, direction: str, current: float, history: list[HistoryEntry], targets: TargetBehaviour,
    routes: StageRoutes,
) -> float | None:
    """A new value for one field following the critique's direction; None when the field cannot move usefully."""
    if direction == "keep":
        return None
    name = spec.name
    method = routes.methods.get(name, "secant")
    tested_here = [h for h in history if h.probed and name in h.values]
    if method == "enumerate" or name in routes.integers:
        step = -1 if direction == "decrease" else 1
        tested = {int(round(h.values[name])) for h in tested_here}
        return enumerate_step(current, tested, spec.low, spec.high, step)
    if direction == "next":
        direction = "increase"
    width = span(spec)
    lo, hi = to_u(spec, spec.low), to_u(spec, spec.high)
    u_ref = to_u(spec, current)
    # failed-gate evidence bounds the feasible interval: 'increase' marks a lower limit, 'decrease' an upper one
    too_low = [to_u(spec, h.values[name]) for h in tested_here if not h.valid and h.directions.get(name) == "increase"]
    too_high = [to_u(spec, h.values[name]) for h in tested_here if not h.valid and h.directions.get(name) == "decrease"]
    primary = _primary_band(name, targets, history, routes)
    points: list[Point] = []
    if primary is not None:
        band, slope = primary
        points = [Point(to_u(spec, h.values[name]), band.signed_residual(h.metrics[band.metric]))
                  for h in tested_here if h.valid and band.metric in h.metrics]
    if points:
        u = root_step(points, slope, method, lo, hi, u_ref, width, log_field=spec.scale == "log",
                      lo_open=max(too_low, default=-math.inf), hi_open=min(too_high, default=math.inf))
    else:
        pass_low = [to_u(spec, h.values[name]) for h in tested_here if h.directions.get(name) == "increase"]
        pass_high = [to_u(spec, h.values[name]) for h in tested_here if h.directions.get(name) == "decrease"]
        if direction == "increase":
            pass_low.append(u_ref)
            one_sided = not pass_high and len(set(pass_low)) >= 2
        else:
            pass_high.append(u_ref)
            one_sided = not pass_low and len(set(pass_high)) >= 2
        if one_sided:  # moved this way before and never overshot: go straight to the bound, or a larger step
            u = float(hi if direction == "increase" else lo)
            factor = routes.expansion.get(name)
            behind = [v for v in (pass_low if direction == "increase" else pass_high) if v != u_ref]
            if factor is not None and behind:
                last = min(behind, key=lambda v: abs(v - u_ref))  # the step that led here
                grown = factor * abs(u_ref - last)
                u = min(u, u_ref + grown) if direction == "increase" else max(u, u_ref - grown)
            u = None if abs(u - u_ref) < 1e-12 * max(1.0, abs(u_ref)) else u
        else:
            u = bisect_step(pass_low, pass_high, lo, hi, u_ref, width)
    if u is None:
        return None
    x = from_u(spec, u)
    return None if math.isclose(x, current, rel_tol=1e-9, abs_tol=1e-12) else x


def _unmet(h: HistoryEntry, targets: TargetBehaviour) -> list[str]:
    """Metrics an attempt left failing: its failed gates and its unmet target bands."""
    return h.failed_gates + targets.unmet(h.metrics)


def _progressed(a: HistoryEntry, b: HistoryEntry, targets: TargetBehaviour) -> bool:
    """True when b fails fewer gates than a, or moved any metric that a left failing."""
    if len(b.failed_gates) < len(a.failed_gates):
        return True
    for m in _unmet(a, targets):
        x, y = a.metrics.get(m), b.metrics.get(m)
        if x is not None and y is not None and not math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-12):
            return True
    return False


def _stale(action: str, history: list[HistoryEntry], targets: TargetBehaviour, patience: int = 2) -> bool:
    """True when the last `patience` probed attempts all took this action and none moved what was failing."""
    probed = [h for h in history if h.probed]
    if len(probed) <= patience or any(h.action != action for h in probed[-patience:]):
        return False
    tail = probed[-patience - 1:]
    return not any(_progressed(a, b, targets) for a, b in zip(tail, tail[1:]))


class RulePlanner:
    """Ordered enumeration of revision routes: the first route whose fields the critique flags and can still move."""

    def __init__(self, routes: StageRoutes | None = None) -> None:
        self.routes = routes

    def plan(self, ctx: PlannerContext) -> RoleReply[PlannerDecision]:
        """Pick the initial action, the next revision route, an escalation, or stop."""
        routes = self.routes or stage_routes(ctx.stage)
        probed = [h for h in ctx.history if h.probed]
        if not probed:
            action = ctx.initial_action if ctx.initial_action in ctx.permitted_actions else next(
                (a for a in ctx.permitted_actions if a.startswith(INITIAL_PREFIXES)), ctx.permitted_actions[0])
            return RoleReply(PlannerDecision(action=action, rationale="initial proposal"), rule_source())
        crit = ctx.last_critique
        flagged = {f: d for f, d in (crit.directions if crit else {}).items() if d != "keep"}
        specs = {f.name: f for f in ctx.editable_fields}
        order = [a for a in routes.route_order if a in ctx.permitted_actions]
        order += [a for a in ctx.permitted_actions if a not in order and not a.startswith(INITIAL_PREFIXES)]
        for action in order:
            if action in routes.escalations or _stale(action, ctx.history, ctx.targets):
                continue
            for name in ctx.action_fields.get(action, []):
                if name in flagged and name in specs and propose_field(
                        specs[name], flagged[name], ctx.current_values.get(name, specs[name].low), ctx.history,
                        ctx.targets, routes) is not None:
                    return RoleReply(PlannerDecision(
                        action=action, rationale=f"{crit.diagnosis if crit else 'none'}: {name} should {flagged[name]}"),
                        rule_source())
        tried = {h.action for h in ctx.history}
        for metric in (crit.unmet if crit else []):
            route = routes.gates.get(metric)
            if route and route.escalate in ctx.permitted_actions and (
                    route.escalate in routes.escalations or route.escalate not in tried):
                return RoleReply(PlannerDecision(action=route.escalate, rationale=f"'{metric}' needs {route.escalate}"),
                                 rule_source())
        why = f"unmet: {crit.unmet}" if crit else "nothing to revise"
        return RoleReply(PlannerDecision(action=ctx.permitted_actions[0], stop=True,
                                         rationale=f"no route can still move a flagged field ({why})"), rule_source())


class RuleDesigner:
    """Searches each flagged field of the action (secant / bisection / enumeration); first proposal = priors."""

    def __init__(self, routes: StageRoutes | None = None) -> None:
        self.routes = routes

    def design(self, req: DesignerRequest) -> RoleReply[Candidate]:
        """Values for the action's fields."""
        routes = self.routes or stage_routes(req.stage)
        if not any(h.probed for h in req.history) or req.critique is None:
            values = {}
            for f in req.fields:
                x = req.current_values.get(f.name, req.targets.priors.get(f.name))
                values[f.name] = min(max(x, f.low), f.high) if x is not None else from_u(f, 0.5 * (to_u(f, f.low) + to_u(f, f.high)))
            src = ", ".join(req.targets.matched_words) or "defaults"
            return RoleReply(Candidate(values=values, rationale=f"initial proposal from priors ({src}): {_fmt(values)}"),
                             rule_source())
        values, notes = {}, []
        for f in req.fields:
            d = req.critique.directions.get(f.name, "keep")
            x = propose_field(f, d, req.current_values.get(f.name, f.low), req.history, req.targets, routes)
            if x is not None:
                values[f.name] = float(x)
                notes.append(f"{f.name}: {req.current_values.get(f.name, float('nan')):.4g} -> {x:.4g} ({d})")
        rationale = "; ".join(notes) or "no field can move in the suggested direction"
        return RoleReply(Candidate(values=values, rationale=rationale), rule_source())


class RuleCritic:
    """Gates first (diagnosis + directions from the gate table), then target bands (directions from couplings)."""

    def __init__(self, routes: StageRoutes | None = None) -> None:
        self.routes = routes

    def critique(self, req: CriticRequest) -> RoleReply[Critique]:
        """Accept when every gate passes and every band holds; otherwise revise with directions."""
        routes = self.routes or stage_routes(req.stage)
        editable = {f.name for f in req.editable_fields}
        failed = [g for g in req.gates if not g.passed]
        missed = set(req.targets.unmet(req.metrics))  # measured outside its band; a target not measured is no miss
        unmet = [b for b in req.targets.bands if b.metric in missed]
        band_dirs, band_notes = self._band_directions(req, unmet, routes, editable)
        if not failed and not unmet:
            unmeasured = req.targets.not_measured(req.metrics)
            held = (f"every measured target band holds ({', '.join(unmeasured)} not measured)" if unmeasured
                    else "every target band holds")
            return RoleReply(Critique(verdict="accept", diagnosis="none",
                                      rationale=f"every hard gate passes and {held}"), rule_source())
        if not failed:
            return RoleReply(Critique(verdict="revise", diagnosis=STAGE_DIAGNOSIS.get(req.stage, "material"),
                                      directions=band_dirs, rationale="; ".join(band_notes),
                                      unmet=[b.metric for b in unmet]), rule_source())
        directions: dict[str, str] = {}
        ranks: dict[str, int] = {}
        diagnosis = None
        failed_metrics = {g.metric for g in failed}
        for g in failed:
            route = routes.gates.get(g.metric)
            if route is None or (route.after is not None and route.after in failed_metrics):
                continue  # no route, or a consequence of an earlier phase's failure (not lifted -> not transported)
            diagnosis = diagnosis or route.diagnosis
            for f, d in route.directions.items():
                if f in editable and route.priority > ranks.get(f, -10**9):
                    directions[f], ranks[f] = d, route.priority
        seen = [m for m in routes.modes if req.metrics.get(m) == 1]  # the failure mode the probe diagnosed
        mode_note = []
        if seen and not any(g.metric in failed_metrics and routes.gates.get(g.metric) is not None
                            and routes.gates[g.metric].priority > 1 for g in failed):
            route = routes.modes[seen[0]]  # a hard limit's gate (force budget, health) still outranks a mode
            diagnosis = route.diagnosis if route.diagnosis != "none" else diagnosis
            directions = {f: d for f, d in route.directions.items() if f in editable}
            mode_note = [f"diagnosed {seen[0]}: " + (", ".join(f"{f} {d}" for f, d in directions.items()) or
                                                    "no field to change")]
        for f, d in band_dirs.items():  # targets still guide the fields that no failed gate speaks for (e.g. mass)
            directions.setdefault(f, d)
        if diagnosis is None:
            diagnosis = "numerical" if any(g.value is None or not math.isfinite(g.value) for g in failed) else "none"
        text = "; ".join([f"gate '{g.gate}' failed ({g.metric}={g.value})" for g in failed] + mode_note + band_notes)
        return RoleReply(Critique(verdict="revise", diagnosis=diagnosis, directions=directions,
                                  rationale=text, unmet=[g.metric for g in failed] + [b.metric for b in unmet]),
                         rule_source())

    @staticmethod
    def _band_directions(req: CriticRequest, unmet: list, routes: StageRoutes, editable: set[str]):  # noqa: ANN205
        """Weighted vote per field from the unmet bands and the couplings, plus one note per band."""
        votes: dict[str, float] = {}
        notes = []
        for b in unmet:
            value = req.metrics.get(b.metric)
            if value is None or not math.isfinite(value):
                notes.append(f"{b.metric} not measured")
                continue
            need = 1.0 if value < b.low else -1.0
            unit = "" if b.unit == "-" else f" {b.unit}"
            notes.append(f"{b.metric}={value:.4g}{unit} outside [{b.low:.4g}, {b.high:.4g}]")
            for f, slope in routes.couplings_of_metric(b.metric):
                if f in editable:
                    votes[f] = votes.get(f, 0.0) + b.weight * min(b.deviation(value), 3.0) * need * math.copysign(1, slope)
        return {f: ("increase" if v > 0 else "decrease") for f, v in votes.items() if v != 0}, notes
