"""One numbering of L3's trials (#36): a trial is one simulated pick-and-place, numbered from 1 in the order it ran,
which is its row's position in manipulation.json's `attempts`. The console's progress lines ('L3 trial 3: ...'),
manipulation.json (each row's `trial`, the reported `trial`), `deformsmith evidence` (the harness attempt's trial),
the card, the pick-and-place video, `deformsmith replay --trial N` and the trial recordings
(recordings/L3_trial_NN.rrd) all use this number. A row's `attempt` is not a trial number: it names the
interaction folder (interaction/attempt_NNN, from 0) that holds the trial's states."""

from __future__ import annotations

from typing import Any

from contracts.asset_dir import attempt_path


def trial_rows(record: dict[str, Any]) -> list[dict[str, Any]]:
    """manipulation.json's rows, each with its `trial` number (a record written before #36 lacks the key: its
    position then, which is what the console printed)."""
    return [{**row, "trial": int(row.get("trial") or i + 1)} for i, row in enumerate(record.get("attempts") or [])]


def trial_of_attempt(record: dict[str, Any], attempt: int | None) -> int | None:
    """The trial number of the row whose interaction folder is attempt_NNN (None: no such row)."""
    if attempt is None:
        return None
    return next((r["trial"] for r in trial_rows(record) if r.get("attempt") == attempt), None)


def trial_of_folder(record: dict[str, Any], folder: str) -> int | None:
    """The trial number of an interaction folder named in the evidence (e.g. 'interaction/attempt_000')."""
    return next((r["trial"] for r in trial_rows(record) if r.get("attempt") is not None
                 and attempt_path(int(r["attempt"])) == folder), None)


def attempt_of_trial(record: dict[str, Any], trial: int) -> int | None:
    """The interaction folder index (attempt_NNN) of trial `trial` (1-based); None when that trial stored no states
    (a plan that could not run) or there is no such trial."""
    row = next((r for r in trial_rows(record) if r["trial"] == trial), None)
    return None if row is None or row.get("attempt") is None else int(row["attempt"])


def reported_trial(record: dict[str, Any]) -> int | None:
    """The trial a record reports: the adopted one, else the best failed one, else the last that stored states."""
    for n in (record.get("trial"), (record.get("best_attempt") or {}).get("trial")):
        if n:
            return int(n)
    stored = [r["trial"] for r in trial_rows(record) if r.get("attempt") is not None]
    return stored[-1] if stored else None


def simulated_trials(record: dict[str, Any]) -> int:
    """How many trials simulated a pick-and-place (a plan that could not run simulated nothing)."""
    return sum(1 for r in record.get("attempts") or [] if r.get("labels") and not r["labels"].get("plan_failed"))


__all__ = ["attempt_of_trial", "reported_trial", "simulated_trials", "trial_of_attempt", "trial_of_folder",
           "trial_rows"]
