"""One numbering of L3's trials (#36): a trial is one simulated pick-and-place, numbered from 1 in the order it ran,
which is its row's position in manipulation.json's `attempts`. The console's progress lines ('L3 trial 3: ...'),
manipulation.json (each row's `trial`, the reported `trial`), `deformsmith evidence` (the harness attempt's trial),
the card and the pick-and-place video all use this number. A row's `attempt` is not a trial number: it names the
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


def simulated_trials(record: dict[str, Any]) -> int:
    """How many trials simulated a pick-and-place (a plan that could not run simulated nothing)."""
    return sum(1 for r in record.get("attempts") or [] if r.get("labels") and not r["labels"].get("plan_failed"))


__all__ = ["simulated_trials", "trial_of_attempt", "trial_of_folder", "trial_rows"]
