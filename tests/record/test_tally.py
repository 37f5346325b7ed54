"""`inspect` and `evidence` print one set of counts, derived from the attempt records (tasks.record.stage_tallies),
and fit 80 columns. The fixture holds the records of a real default-turtle asset (its L2 kept a candidate that met
every measured target, with sag_ratio not measured: the lift probe's pinch slipped, and the record, written before
#36, called that 'best_valid'; L2 and L3 ran simulations outside their harness loops)."""

from __future__ import annotations

import json
import re
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

from flows.cli.apps import results
from flows.cli.main import app
from tasks.record import stage_tallies

FIXTURE = Path(__file__).parent / "fixtures" / "plush_turtle"
ROW = re.compile(r"^│ (L[0-3]) +│ ([a-zA-Z ]+?) +│ +(\d+) │ +(\d+) │")


@pytest.fixture
def narrow() -> Iterator[None]:
    """The results console at 80 columns, as in a default terminal."""
    width = results.width
    results.width = 80
    yield
    results.width = width


def _run(*args: str) -> list[str]:
    res = CliRunner().invoke(app, list(args))
    assert res.exit_code == 0, res.output
    return res.output.splitlines()


def _counts(lines: list[str]) -> dict[str, tuple[str, int, int]]:
    """stage -> (passed, attempts, simulations) from a tally table."""
    return {m[1]: (m[2], int(m[3]), int(m[4])) for m in map(ROW.match, lines) if m}


def test_tallies_count_the_loop_and_the_simulations_outside_it() -> None:
    t = {x.stage: x for x in stage_tallies(FIXTURE)}
    # L3 counts its trials (one harness iteration asked for the selection trial; robustness and held-out added three),
    # as the console's 'L3 trial 1-4' and manipulation.json's rows do (#36: one numbering of trials)
    rows = json.loads((FIXTURE / "manipulation.json").read_text())["attempts"]
    assert [t[s].attempts for s in ("L0", "L1", "L2", "L3")] == [1, 1, 1, len(rows)] == [1, 1, 1, 4]
    assert (t["L1"].loop_sim_calls, t["L1"].sim_calls) == (4, 4)
    assert t["L2"].extra_sim_calls == {"screening": 2, "held_out": 4} and t["L2"].sim_calls == 12
    assert json.loads((FIXTURE / "material.json").read_text())["sim_calls"] == t["L2"].sim_calls
    assert t["L3"].extra_sim_calls == {"robustness": 2, "held_out": 1} and t["L3"].sim_calls == 4
    assert t["L2"].status == "best_valid" and t["L2"].passed and t["L2"].unmet_targets == []
    assert list(t["L2"].not_measured) == ["sag_ratio"] and "pinch did not hold" in t["L2"].not_measured["sag_ratio"]


def test_inspect_and_evidence_agree_and_fit_80_columns(narrow: None) -> None:
    shown = {cmd: _run(cmd, str(FIXTURE)) for cmd in ("inspect", "evidence")}
    counts = {cmd: _counts(lines) for cmd, lines in shown.items()}
    assert counts["inspect"] == counts["evidence"] == {
        "L0": ("yes", 1, 0), "L1": ("yes", 1, 4), "L2": ("yes", 1, 12), "L3": ("yes", 4, 4)}
    for lines in shown.values():  # the table fits 80 columns; a line of text is never broken (the terminal wraps it)
        assert max(len(line) for line in lines if line[:1] in "┏┃┡│└") <= 80
        assert not any("…" in line for line in lines)  # folded, never cut
        assert not any(line != line.rstrip() for line in lines if line[:1] not in "┏┃┡│└")  # no padding to a width
        assert not any(line.startswith("L2: best valid") for line in lines)  # not measured is no miss
        assert ("L2: sag_ratio not measured — the lift probe's pinch did not hold the object: the pinched part rose "
                "16 mm, so its sag under its own weight was not seen") in lines
        assert "L2: 12 simulations = 6 in the harness loop + 2 screening + 4 held-out" in lines


def test_a_failed_stage_is_no_in_both_with_its_reason_in_full(tmp_path: Path, narrow: None) -> None:
    asset = tmp_path / "asset"
    shutil.copytree(FIXTURE, asset)
    record = json.loads((asset / "manipulation.json").read_text())
    reason = "not lifted: mean finger force 1.2 N < m g / (2 mu) = 1.6 N over the whole hold, " * 2
    record.update(passed=False, status="best_invalid", reason=reason.strip())
    (asset / "manipulation.json").write_text(json.dumps(record))
    for cmd in ("inspect", "evidence"):
        lines = _run(cmd, str(asset))
        assert _counts(lines)["L3"] == ("NO", 4, 4)  # four trials, four simulations
        assert ("L3:NO—" + reason.strip()).replace(" ", "") in "".join(lines).replace(" ", "")  # wrapped, whole
