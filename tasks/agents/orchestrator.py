"""The generic harness loop: plan -> design -> check the contract -> probe -> gates -> critique -> keep / roll back."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from contracts.agents import (
    Candidate, CriticRequest, DesignerRequest, HistoryEntry, PlannerContext, StageOutcome, TargetBehaviour,
)
from contracts.errors import ContractError
from contracts.evidence import AgentSource, Attempt, EvidenceRecord, GateResult
from contracts.probes import ProbeResult, not_measured_reason
from contracts.stage import HardGate, StageContract
from tasks.agents.backend import Critic, Designer, InvalidAnswer, Planner, check_candidate, check_decision
from tasks.agents.rule import RuleCritic, RuleDesigner, RulePlanner
from tasks.agents.search import from_u, to_u
from tasks.agents.vocab import StageRoutes, stage_routes


class ProbeRunner(Protocol):
    """The layer's Prober: runs the stage's required probes on a full candidate and returns their results."""

    def __call__(self, values: dict[str, float], action: str, /) -> Sequence[ProbeResult]:
        """Probe one candidate (values = every editable field) produced by one action (positional: any callable of
        this shape is a ProbeRunner)."""
        ...


class AttemptSink(Protocol):
    """Where attempts go as they happen (see tasks.agents.records.AttemptRecorder)."""

    def record(self, attempt: Attempt) -> None:
        """Store one attempt."""
        ...


@dataclass
class Roles:
    """The three agent roles of a harness run."""

    planner: Planner
    designer: Designer
    critic: Critic

    @classmethod
    def rule(cls, routes: StageRoutes | None = None) -> Roles:
        """Every role played by the offline rule backend."""
        return cls(RulePlanner(routes), RuleDesigner(routes), RuleCritic(routes))


def _worst(values: list[float], gate: HardGate | None) -> float:
    """Combine one metric reported by several probes: the value that is worst for its gate (else the last)."""
    finite = [v for v in values if math.isfinite(v)]
    if len(finite) < len(values):
        return math.nan
    if gate is None:
        return values[-1]
    if gate.op in ("<=", "<"):
        return max(values)
    if gate.op in (">=", ">"):
        return min(values)
    failing = [v for v in values if not gate.passes(v)]
    return failing[0] if failing else values[-1]


def merge_metrics(results: Sequence[ProbeResult], contract: StageContract) -> dict[str, float]:
    """One metrics dict from several probes; a metric reported twice keeps its worst value for its gate."""
    gates = {g.metric: g for g in contract.hard_gates}
    seen: dict[str, list[float]] = {}
    for r in results:
        for k, v in r.metrics.items():
            seen.setdefault(k, []).append(float(v))
    return {k: _worst(vs, gates.get(k)) for k, vs in seen.items()}


def initial_values(contract: StageContract, targets: TargetBehaviour, initial: dict[str, float] | None) -> dict[str, float]:
    """Start values: the layer's initial values (must be in bounds), else clamped priors, else the range's middle."""
    names = {f.name for f in contract.editable_fields}
    unknown = sorted(set(initial or {}) - names)
    if unknown:
        raise ContractError(f"{contract.stage}: initial values name fields that are not editable: {unknown}")
    out = {}
    for f in contract.editable_fields:
        if initial and f.name in initial:
            if not f.contains(float(initial[f.name])):
                raise ContractError(f"{contract.stage}: initial {f.name}={initial[f.name]} outside [{f.low}, {f.high}]")
            out[f.name] = float(initial[f.name])
        elif f.name in targets.priors:
            out[f.name] = min(max(float(targets.priors[f.name]), f.low), f.high)
        else:
            out[f.name] = from_u(f, 0.5 * (to_u(f, f.low) + to_u(f, f.high)))
    return out


@dataclass
class _Best:
    iteration: int
    values: dict[str, float]
    metrics: dict[str, float]
    score: float


def run_stage(
    contract: StageContract,
    probe_runner: ProbeRunner,
    targets: TargetBehaviour | None = None,
    *,
    roles: Roles | None = None,
    initial: dict[str, float] | None = None,
    initial_action: str | None = None,
    recorder: AttemptSink | None = None,
    routes: StageRoutes | None = None,
) -> StageOutcome:
    """Run one stage's harness loop under its contract; every attempt (rejected ones too) costs one unit of budget."""
    targets = targets or TargetBehaviour()
    routes = routes or stage_routes(contract.stage, contract.parameters)
    roles = roles or Roles.rule(routes)
    names = [f.name for f in contract.editable_fields]
    action_fields = {a: routes.fields_of(a, names) for a in contract.permitted_actions}
    budget = 1 + contract.revision_budget
    current = initial_values(contract, targets, initial)
    base_iteration: int | None = None
    attempts: list[Attempt] = []
    history: list[HistoryEntry] = []
    best: _Best | None = None
    last_critique = None
    feedback: str | None = None
    sim_calls = 0
    status, escalation, message = None, None, ""

    def record(a: Attempt) -> None:
        attempts.append(a)
        if recorder is not None:
            recorder.record(a)

    def reject(action: str, values: dict[str, float], source: AgentSource, reason: str, rationale: str) -> None:
        record(Attempt(stage=contract.stage, iteration=len(attempts), action=action, proposal=values, source=source,
                       rationale=rationale, rejected_before_probe=reason, verdict="rejected", parent_iteration=base_iteration))
        history.append(HistoryEntry(iteration=len(attempts) - 1, action=action, values=values, valid=False, probed=False,
                                    rejection=reason))

    while len(attempts) < budget:
        ctx = PlannerContext(
            stage=contract.stage, permitted_actions=contract.permitted_actions, action_fields=action_fields,
            editable_fields=contract.editable_fields, iteration=len(attempts), budget_left=budget - len(attempts),
            current_values=current, targets=targets, last_critique=last_critique, history=history,
            initial_action=initial_action)
        plan = roles.planner.plan(ctx)
        decision = plan.value
        assert decision is not None, "a planner must answer or raise"
        if err := check_decision(ctx, decision):
            reject(decision.action, {}, plan.source, err, decision.rationale)
            feedback = err
            continue
        if decision.stop:
            message = f"planner stopped: {decision.rationale}"
            break
        if decision.action in routes.escalations:
            record(Attempt(stage=contract.stage, iteration=len(attempts), action=decision.action, proposal={},
                           source=plan.source, planner_source=plan.source, rationale=decision.rationale,
                           verdict="escalated", diagnosis=last_critique.diagnosis if last_critique else None,
                           parent_iteration=base_iteration))
            status, escalation = "escalated", decision.action
            message = f"escalated via '{decision.action}': {decision.rationale}"
            break
        fields = [f for f in contract.editable_fields if f.name in action_fields[decision.action]]
        dreq = DesignerRequest(stage=contract.stage, action=decision.action, fields=fields, current_values=current,
                               targets=targets, critique=last_critique, history=history, feedback=feedback,
                               budget_left=budget - len(attempts))
        design = roles.designer.design(dreq)
        for bad in design.invalid:
            if len(attempts) >= budget:
                break
            reject(decision.action, bad.values or {}, design.source.model_copy(update={"errors": [bad.error]}),
                   bad.error, bad.text[:500])
            feedback = bad.error
        if len(attempts) >= budget:
            break
        cand = design.value or Candidate(values={})
        err = check_candidate(dreq, cand)
        values = {**current, **{k: float(v) for k, v in cand.values.items()}}
        if err is None:
            # same values = same probes; only a field-less action (e.g. remesh) changes something by itself
            dup = next((h for h in history if h.probed and h.values == values
                        and (fields or h.action == decision.action)), None)
            if dup is not None:
                err = f"identical to attempt {dup.iteration}, which was already probed; propose different values"
        if err is not None:
            reject(decision.action, dict(cand.values), design.source, err, cand.rationale)
            feedback = err
            continue
        feedback = None
        results = list(probe_runner(dict(values), decision.action))
        metrics = merge_metrics(results, contract)
        sim_calls += sum(r.sim_calls for r in results)
        gates = [GateResult(gate=g.name, metric=g.metric, value=metrics.get(g.metric), passed=g.passes(metrics.get(g.metric)))
                 for g in contract.hard_gates]
        valid = all(g.passed for g in gates)
        missing = sorted(set(contract.required_observations) - set(metrics))
        score = targets.score(metrics) if valid else None
        creq = CriticRequest(stage=contract.stage, values=values, metrics=metrics, gates=gates, targets=targets,
                             editable_fields=contract.editable_fields, history=history)
        judged = roles.critic.critique(creq)
        crit = judged.value
        assert crit is not None, "a critic must answer or raise"
        i = len(attempts)
        if not valid:
            verdict = "revise"
        elif best is None or score > best.score + 1e-12:  # type: ignore[operator]
            best = _Best(i, values, metrics, score)  # type: ignore[arg-type]
            verdict = "accepted" if (targets.met(metrics) or crit.verdict == "accept") else "best_so_far"
        else:
            verdict = "rolled_back"
        unmeasured = {m: not_measured_reason(m, metrics) for m in targets.not_measured(metrics)}
        note = f" (missing observations: {missing})" if missing else ""
        note += "".join(f"; {m} not measured: {why}" for m, why in unmeasured.items())
        record(Attempt(
            stage=contract.stage, iteration=i, action=decision.action, proposal=values, source=design.source,
            rationale=cand.rationale, evidence=EvidenceRecord(
                probe_keys=[r.cache_key for r in results if r.cache_key], metrics=metrics,
                recordings=[r.recording for r in results if r.recording], sim_calls=sum(r.sim_calls for r in results),
                not_measured=unmeasured),
            gates=gates, score=score, verdict=verdict, diagnosis=crit.diagnosis, critique=crit.rationale + note,
            parent_iteration=base_iteration, directions=dict(crit.directions), planner_source=plan.source,
            critic_source=judged.source))
        history.append(HistoryEntry(iteration=i, action=decision.action, values=values, metrics=metrics, valid=valid,
                                    probed=True, score=score, directions=crit.directions,
                                    failed_gates=[g.metric for g in gates if not g.passed]))
        last_critique = crit
        if best is not None:
            current, base_iteration = dict(best.values), best.iteration
        else:
            current, base_iteration = dict(values), i
        if verdict == "accepted":
            status = "accepted"
            message = f"accepted attempt {i} (score {score:.3f}): {crit.rationale}"
            break
    if status is None:
        if best is not None:
            status = "best_valid"
            message = (message + "; " if message else "") + (
                f"targets not all met after {len(attempts)} attempt(s); keeping the best valid candidate "
                f"(attempt {best.iteration}, score {best.score:.3f})")
        else:
            status = "no_valid_candidate"
            failing = sorted({g.gate for a in attempts for g in a.gates if not g.passed})
            message = (message + "; " if message else "") + (
                f"no valid candidate: none of {len(attempts)} attempt(s) passed every hard gate"
                + (f" (failing gates: {failing})" if failing else ""))
    return StageOutcome(
        stage=contract.stage, status=status, values=best.values if best else None,
        metrics=best.metrics if best else {}, score=best.score if best else None,
        best_iteration=best.iteration if best else None, attempts=attempts, attempts_used=len(attempts),
        sim_calls=sim_calls, escalation=escalation, message=message)


__all__ = ["ProbeRunner", "AttemptSink", "Roles", "run_stage", "merge_metrics", "initial_values", "InvalidAnswer"]
