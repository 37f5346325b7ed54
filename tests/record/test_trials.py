"""L3's trial numbers read from the typed record (contracts.manipulation.ManipulationRecord): a record written before
#36 has no `trial` on its rows and numbers them by position; `replay --trial N` finds trial N's interaction folder."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from contracts.errors import InputError
from tasks.asset_dir import AssetDir
from tasks.manipulation.replay import _which
from tasks.record.trials import (attempt_of_trial, read_record, recorded_trials, reported_trial, trial_of_attempt,
                                 trial_of_folder, trial_rows)

OLD = Path(__file__).parent / "fixtures" / "plush_turtle" / "manipulation.json"  # written before #36: no `trial`


def _asset(tmp_path: Path, **update: object) -> Path:
    root = tmp_path / "asset"
    root.mkdir()
    record = json.loads(OLD.read_text(encoding="utf-8"))
    record.update(update)
    (root / "manipulation.json").write_text(json.dumps(record), encoding="utf-8")
    return root


def test_an_old_record_numbers_its_trials_by_position(tmp_path: Path) -> None:
    root = _asset(tmp_path)
    record = AssetDir(root).manipulation()
    assert all(row.trial is None for row in record.attempts)
    assert [r.trial for r in trial_rows(record)] == [1, 2, 3, 4] == recorded_trials(record)
    assert [trial_of_attempt(record, a) for a in (0, 3, 7, None)] == [1, 4, None, None]
    assert trial_of_folder(record, "interaction/attempt_002") == 3 and attempt_of_trial(record, 2) == 1
    assert reported_trial(record) == 4  # neither the record nor its best attempt names one: the last stored
    assert _which(root, None, 2) == (1, 2) and _which(root, 0, None) == (0, 1)
    with pytest.raises(InputError, match=r"no recorded trial 9; recorded trials: \[1, 2, 3, 4\]"):
        _which(root, None, 9)


def test_a_numbered_record_reports_its_trial(tmp_path: Path) -> None:
    raw = json.loads(OLD.read_text(encoding="utf-8"))
    rows = [{**row, "trial": i + 1} for i, row in enumerate(raw["attempts"])]
    rows[1]["attempt"] = None  # a plan that could not run stored nothing
    root = _asset(tmp_path, attempts=rows, trial=3, attempt=2)
    record = read_record(root)
    assert record is not None and reported_trial(record) == 3 and recorded_trials(record) == [1, 3, 4]
    assert attempt_of_trial(record, 2) is None and _which(root, None, None) == (2, 3)


def test_read_record_is_none_without_a_valid_record(tmp_path: Path) -> None:
    assert read_record(tmp_path) is None
    (tmp_path / "manipulation.json").write_text('{"passed": tr', encoding="utf-8")
    assert read_record(tmp_path) is None
    shutil.copyfile(OLD, tmp_path / "manipulation.json")
    assert read_record(tmp_path) is not None
