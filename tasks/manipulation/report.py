"""How L3's result reaches the user: a failed trial's reason in words, progress lines, the attempt the manifest shows,
and the record of an object no gripper can hold (no grasp is a result, not an error)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from contracts.agents import StageOutcome
from contracts.evidence import AgentSource, Attempt
from contracts.manipulation import TrialRow
from contracts.stage import StageContract
from tasks.agents.records import AttemptRecorder
from tasks.manipulation.diagnosis import diagnose
from tasks.manipulation.outcome import TrialTolerances

Progress = Callable[[str], None]
NO_GRASP_GATE = "grasp available"  # the failed gate named in the validation summary when no grasp exists
OUTCOME_METRICS = ("lifted", "transported", "released_in_target", "settled")  # the gates a diagnosis explains


def _finite(labels: dict[str, Any], key: str) -> float | None:
    v = labels.get(key)
    return float(v) if isinstance(v, (int, float)) and math.isfinite(float(v)) else None


def failed_gate_names(labels: dict[str, Any], contract: StageContract) -> list[str]:
    """The contract's hard gates a trial's labels fail."""
    return [g.name for g in contract.hard_gates if not g.passes(labels.get(g.metric))]


def trial_reason(labels: dict[str, Any], contract: StageContract, tol: TrialTolerances) -> str:
    """One line saying why a trial failed L3 (the first failed gate in physical terms, then the others); '' when it
    passed every hard gate."""
    if labels.get("plan_failed"):
        return "the plan could not be executed (no reachable approach or grasp pose)"
    failed = failed_gate_names(labels, contract)
    if not failed:
        return ""
    gates = {g.name: g for g in contract.hard_gates}
    metric_of = {name: g.metric for name, g in gates.items()}
    first = failed[0]
    metric = metric_of[first]
    if metric == "numerically_healthy":
        why = "numerically unhealthy: the simulation produced non-finite or escaping particles"
    elif metric == "max_finger_force_n":
        peak = _finite(labels, "max_finger_force_n")
        why = (f"force budget exceeded: peak finger force {peak:.3g} N > {gates[first].threshold:g} N"
               if peak is not None else "force budget: finger force not measured")
    elif metric in OUTCOME_METRICS:
        # what happened, from the trial's own data (slipped at the lift, lost contact, released off target ...)
        d = diagnose(labels, tol)
        why = d.words if d is not None else f"failed gate: {first}"
    elif metric == "strain_p99":
        s = _finite(labels, "strain_p99")
        why = (f"deformation bound exceeded: strain (1 % of volume) {s:.2g} > {gates[first].threshold:g}"
               if s is not None else "deformation bound: strain not measured")
    else:
        why = f"failed gate: {first}"
    return why + (f" (also failed: {', '.join(failed[1:])})" if len(failed) > 1 else "")


def best_attempt(attempts: list[TrialRow], contract: StageContract) -> TrialRow | None:
    """The attempt a failed L3 reports: among the selection trials (the asset's own material, the nominal condition)
    the one failing the fewest hard gates, the latest of those; a plan that never ran only when no trial ran."""
    selection = [a for a in attempts if a.role == "selection" and a.labels]
    ran = [a for a in selection if not a.labels.get("plan_failed")]
    if ran:
        return min(reversed(ran), key=lambda a: len(failed_gate_names(a.labels, contract)))
    return selection[0] if selection else None


@dataclass
class L3Progress:
    """'L3 trial k of at most n: <what> (elapsed s)' lines while L3 works; silent without a sink."""

    sink: Progress | None = None
    planned: int = 0  # the most trials this L3 run can take (harness budget + robustness + revision + held-out)
    t0: float = field(default_factory=time.perf_counter)

    def elapsed(self) -> str:
        """Seconds since L3 started."""
        return f"{time.perf_counter() - self.t0:.0f} s"

    def say(self, message: str) -> None:
        """One line with the elapsed time."""
        if self.sink is not None:
            self.sink(f"{message} ({self.elapsed()})")

    def trials(self, first: int, count: int, what: str) -> None:
        """Trials first..first+count-1 (1-based) start."""
        k = f"{first}" if count == 1 else f"{first}-{first + count - 1}"
        noun = "trial" if count == 1 else "trials"
        self.say(f"L3 {noun} {k} of at most {max(self.planned, first + count - 1)}: {what}")

    def result(self, number: int, reason: str) -> None:
        """How trial `number` (1-based) ended."""
        self.say(f"L3 trial {number}: {reason or 'passed every gate'}")


def planned_trials(contract: StageContract, robustness: int, held_out: int, material_fallback: bool) -> int:
    """The most trials one L3 run can take: the harness budget, the robustness conditions, a material revision's
    confirmation and its robustness conditions, the held-out conditions."""
    return 1 + contract.revision_budget + robustness + (1 + robustness if material_fallback else 0) + held_out


def record_no_grasp(asset_dir: Path, reason: str) -> list[TrialRow]:
    """The no-grasp outcome as L3's one harness attempt in evidence/ (attempts.jsonl, L3_outcome.json, harness_L3.rrd);
    returns the attempt as manipulation.json lists it."""
    attempt = Attempt(stage="L3", iteration=0, action="select_grasp", proposal={}, source=AgentSource(),
                      rationale="grasp selection on the object's surface (every gripper of the L3 contract)",
                      rejected_before_probe=reason, verdict="rejected", diagnosis="geometry", critique=reason)
    recorder = AttemptRecorder(asset_dir, "L3")
    recorder.record(attempt)
    recorder.close(StageOutcome(stage="L3", status="no_valid_candidate", attempts=[attempt], attempts_used=1,
                                message=reason))
    return [TrialRow(attempt=None, role="grasp_selection", action="select_grasp", values={}, labels={}, cache_key=None,
                     reason=reason)]
