"""One numbering of L3's trials (#36): a trial is one simulated pick-and-place, numbered from 1 in the order it ran,
which is its row's position in manipulation.json's `attempts`. The console's progress lines ('L3 trial 3: ...'),
manipulation.json (each row's `trial`, the reported `trial`), `deformsmith evidence` (the harness attempt's trial),
the card, the pick-and-place video, `deformsmith replay --trial N` and the trial recordings
(recordings/L3_trial_NN.rrd) all use this number. A row's `attempt` is not a trial number: it names the
interaction folder (interaction/attempt_NNN, from 0) that holds the trial's states.

Every function reads the typed record (contracts.manipulation.ManipulationRecord, as AssetDir.manipulation loads it);
a record written before #36 lacks the rows' `trial`: a row's number is then its position, which is what the console
printed.
"""

from __future__ import annotations

from pathlib import Path

from contracts.asset_dir import attempt_path
from contracts.errors import InputError
from contracts.manipulation import ManipulationRecord, TrialRow
from tasks.asset_dir import AssetDir


def read_record(asset_dir: Path) -> ManipulationRecord | None:
    """manipulation.json of an asset directory (or a run's folder), typed; None when there is none or it is not a
    valid record (the readers that only count or number trials go on without it)."""
    adir = AssetDir(asset_dir)
    if not adir.has("manipulation"):
        return None
    try:
        return adir.manipulation()
    except InputError:
        return None


def _numbered(record: ManipulationRecord) -> list[tuple[int, TrialRow]]:
    """(trial number, row) of each of manipulation.json's rows."""
    return [(row.trial or i + 1, row) for i, row in enumerate(record.attempts)]


def trial_rows(record: ManipulationRecord) -> list[TrialRow]:
    """manipulation.json's rows, each with its `trial` number (a record written before #36 lacks it: its position)."""
    return [row if row.trial == n else row.model_copy(update={"trial": n}) for n, row in _numbered(record)]


def trial_of_attempt(record: ManipulationRecord, attempt: int | None) -> int | None:
    """The trial number of the row whose interaction folder is attempt_NNN (None: no such row)."""
    return record.trial_of_attempt(attempt)


def trial_of_folder(record: ManipulationRecord, folder: str) -> int | None:
    """The trial number of an interaction folder named in the evidence (e.g. 'interaction/attempt_000')."""
    return next((n for n, row in _numbered(record) if row.attempt is not None and attempt_path(row.attempt) == folder),
                None)


def attempt_of_trial(record: ManipulationRecord, trial: int) -> int | None:
    """The interaction folder index (attempt_NNN) of trial `trial` (1-based); None when that trial stored no states
    (a plan that could not run) or there is no such trial."""
    return next((row.attempt for n, row in _numbered(record) if n == trial), None)


def recorded_trials(record: ManipulationRecord) -> list[int]:
    """The numbers of the trials that stored states (an interaction folder), in the order run."""
    return [n for n, row in _numbered(record) if row.attempt is not None]


def reported_trial(record: ManipulationRecord) -> int | None:
    """The trial a record reports: the adopted one, else the best failed one, else the last that stored states."""
    for n in (record.trial, record.best_attempt.trial if record.best_attempt else None):
        if n:
            return n
    stored = recorded_trials(record)
    return stored[-1] if stored else None


def simulated_trials(record: ManipulationRecord) -> int:
    """How many trials simulated a pick-and-place (a plan that could not run simulated nothing)."""
    return record.simulated_trials()


def reported_attempt(record: ManipulationRecord) -> int | None:
    """The interaction folder (attempt_NNN) of the trial the asset reports and shows: the adopted one, else the one
    the manifest reports (the best under the asset's own material), else the last trial that stored states."""
    if record.attempt is not None:
        return record.attempt
    if record.best_attempt is not None and record.best_attempt.attempt is not None:
        return record.best_attempt.attempt
    runs = [a.attempt for a in record.attempts if a.attempt is not None]
    return runs[-1] if runs else None


def data_location(row: TrialRow, asset_dir: Path | None = None) -> str:
    """Where a trial's states are, in words: 'interaction/attempt_NNN' (in the asset) or 'in the cache, key
    <first 12 hex digits>' (never a path the asset does not hold; asset_dir, when given, is checked)."""
    if row.attempt is None:
        return "no states stored (the plan could not run)"
    rel = attempt_path(row.attempt)
    if row.kept_in == "asset" and (asset_dir is None or (Path(asset_dir) / rel).is_dir()):
        return rel
    return f"in the cache, key {row.data_key[:12]}" if row.data_key else "not stored in this asset"


__all__ = ["attempt_of_trial", "data_location", "read_record", "recorded_trials", "reported_attempt", "reported_trial",
           "simulated_trials", "trial_of_attempt", "trial_of_folder", "trial_rows"]
