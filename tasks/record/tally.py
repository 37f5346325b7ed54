"""One count of attempts and simulations per stage, from the attempt records: `inspect`, `evidence` and `generate`'s
summary all print these tallies, so they cannot disagree. L3's attempts are its trials (manipulation.json's rows, each
one pick-and-place, numbered from 1 as the console numbers them), so its attempts and simulations agree.

Sources, under an asset directory (or a run directory's folder holding ``evidence/``):
  evidence/attempts.jsonl     every harness attempt (stage, iteration, evidence.sim_calls): attempts, loop simulations
  evidence/<stage>_outcome.json  how the harness ended (status, message), when the attempt lines are missing
  geometry.json / physical.json / material.json / manipulation.json
                              the stage's record: passed, and the simulations run outside the harness loop
                              (L2: screening and held-out probes; L3: robustness, held-out and confirmation trials)
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from contracts.agents import StageOutcome, TargetBehaviour
from contracts.evidence import Attempt, StageTally
from contracts.probes import not_measured_reason
from contracts.stage import StageName
from tasks.record.attempts import ATTEMPTS_FILE, read_attempts

if TYPE_CHECKING:
    from contracts.manipulation import ManipulationRecord

STAGE_RECORDS: dict[StageName, str] = {"L0": "geometry.json", "L1": "physical.json", "L2": "material.json",
                                       "L3": "manipulation.json"}
LOOP_ROLE = "selection"  # L3 trials of the harness loop itself (counted through the attempt lines)


def _json(path: Path) -> dict[str, Any] | None:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _outcome(path: Path) -> StageOutcome | None:
    try:
        return StageOutcome.model_validate_json(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _extra_sim_calls(stage: StageName, record: dict[str, Any], loop: int) -> dict[str, int]:
    """Simulations L1 or L2 ran outside its harness loop, by role, from its record."""
    extra: dict[str, int] = {}
    if stage == "L2":
        screening = int(((record.get("selection") or {}).get("screening") or {}).get("sim_calls", 0))
        held = sum(int(p.get("sim_calls", 0)) for p in (record.get("held_out") or {}).get("probes") or [])
        extra = {"screening": screening, "held_out": held}
    if "sim_calls" in record:  # what the record counts beyond the parts named above
        rest = int(record["sim_calls"]) - loop - sum(extra.values())
        if rest > 0:
            extra["other"] = rest
    return {role: n for role, n in extra.items() if n > 0}


def _l3_extra_sim_calls(record: ManipulationRecord) -> dict[str, int]:
    """L3's trials outside its harness loop (robustness, held out, confirmation), by role: one per simulated row."""
    extra: dict[str, int] = {}
    for trial in record.attempts:
        role = trial.role or "other"
        if trial.labels and not trial.labels.get("plan_failed") and role != LOOP_ROLE:
            extra[role] = extra.get(role, 0) + 1
    return extra


def _targets(record: dict[str, Any]) -> tuple[TargetBehaviour, dict[str, float]] | None:
    if not record.get("targets") or not isinstance(record.get("metrics"), dict):
        return None
    try:
        return TargetBehaviour.model_validate(record["targets"]), record["metrics"]
    except ValueError:
        return None


def _unmet(record: dict[str, Any]) -> list[str]:
    """Target bands the record's kept candidate was measured outside of (a target not measured is no miss)."""
    found = _targets(record)
    return found[0].unmet(found[1]) if found else []


def _not_measured(record: dict[str, Any]) -> dict[str, str]:
    """Target bands not measured on the record's kept candidate -> why (the record's words, else derived from its
    metrics: an older record has no not_measured)."""
    found = _targets(record)
    if not found:
        return {}
    said = record.get("not_measured") or {}
    return {m: str(said.get(m) or not_measured_reason(m, found[1])) for m in found[0].not_measured(found[1])}


def _loop(attempts: list[Attempt], outcome: StageOutcome | None, recorded: int) -> tuple[int, int]:
    """(harness attempts, simulations in the harness loop): from the attempt lines, else the outcome, else the
    attempts the record counts (no loop simulations known)."""
    if attempts:
        return len(attempts), sum(a.evidence.sim_calls for a in attempts)
    if outcome is not None:
        return outcome.attempts_used, outcome.sim_calls
    return recorded, 0


def _tally(stage: StageName, attempts: list[Attempt], outcome: StageOutcome | None,
           record: dict[str, Any] | None) -> StageTally | None:
    """L0's, L1's or L2's tally (L3: _l3_tally)."""
    if not attempts and outcome is None and record is None:
        return None
    if stage == "L0" and record is not None:  # no harness: one geometry pass (an LLM Designer's retries inside it)
        passed = bool(record.get("passed"))
        return StageTally(stage="L0", status="passed" if passed else "failed", passed=passed,
                          attempts=int(record.get("attempts", 1)), loop_sim_calls=0,
                          message=", ".join(record.get("failed_gates") or []))
    n, loop = _loop(attempts, outcome, int((record or {}).get("harness_attempts", (record or {}).get("attempts", 0))
                                            or 0))
    status = outcome.status if outcome is not None else str((record or {}).get("status", "unknown"))
    passed = bool(record["passed"]) if record is not None and "passed" in record else (
        outcome.passed if outcome is not None else False)
    message = (outcome.message if outcome is not None else "") or str((record or {}).get("message") or "")
    if record is not None and record.get("reason") and not passed:
        message = str(record["reason"])
    return StageTally(stage=stage, status=status, passed=passed, attempts=n, loop_sim_calls=loop,
                      extra_sim_calls=_extra_sim_calls(stage, record, loop) if record else {},
                      unmet_targets=_unmet(record) if record and status != "accepted" else [],
                      not_measured=_not_measured(record) if record else {}, message=message)


def _l3_tally(attempts: list[Attempt], outcome: StageOutcome | None,
              record: ManipulationRecord | None) -> StageTally | None:
    """L3's tally, from its typed record (manipulation.json: no target bands of its own)."""
    if not attempts and outcome is None and record is None:
        return None
    n, loop = _loop(attempts, outcome, record.harness_attempts if record is not None else 0)
    if record is not None and record.attempts:
        # L3 counts trials, one simulated pick-and-place each (tasks.record.trials): the console's 'L3 trial k', the
        # rows of manipulation.json and the card count them, not the harness iterations that asked for some of them
        n = len(record.attempts)
    status = outcome.status if outcome is not None else (record.status if record is not None else "unknown")
    passed = record.passed if record is not None else (outcome.passed if outcome is not None else False)
    message = (outcome.message if outcome is not None else "") or (record.message if record is not None else "")
    if record is not None and record.reason and not passed:
        message = record.reason
    return StageTally(stage="L3", status=status, passed=passed, attempts=n, loop_sim_calls=loop,
                      extra_sim_calls=_l3_extra_sim_calls(record) if record is not None else {}, message=message)


def stage_tallies(root: str | Path, attempts: list[Attempt] | None = None) -> list[StageTally]:
    """The stages found under root (an asset directory, or the folder holding evidence/), in order L0..L3.

    attempts: the attempt records when already read (else evidence/attempts.jsonl under root)."""
    root = Path(root)
    if attempts is None:
        path = root / ATTEMPTS_FILE
        attempts = read_attempts(path) if path.is_file() else []
    out = []
    for stage, record_name in STAGE_RECORDS.items():
        lines, outcome = [a for a in attempts if a.stage == stage], _outcome(root / "evidence" / f"{stage}_outcome.json")
        if stage == "L3":
            # lazy: AssetDir, contracts.manipulation's models (~0.2 s; `evidence` and --help import this module)
            from tasks.record.trials import read_record

            tally = _l3_tally(lines, outcome, read_record(root))
        else:
            tally = _tally(stage, lines, outcome, _json(root / record_name))
        if tally is not None:
            out.append(tally)
    return out
