"""What the command line shows of results (tasks/report): the tally table and its notes, an attempt's lines, the
validation summary of an asset without its records, the layers' lines, the fleet commands' tables and the units
options are read and written in. Pure functions: checked on small records, no command run."""

from __future__ import annotations

import io
import time
from pathlib import Path

import pytest
from rich.console import Console

from contracts.agents import StageOutcome
from contracts.errors import InputError
from contracts.evidence import AgentSource, Attempt, EvidenceRecord, GateResult, StageTally
from contracts.manifest import AssetManifest, Provenance, StageSummary
from contracts.request import AssetRequest
from tasks.batch_requests import BatchReport, RequestResult
from tasks.report.evidence import attempt_block, passed_word, tally_notes, tally_table, validation_tallies
from tasks.report.layers import generate_summary, inspect_lines, mass_check_lines, physical_table, wall_time_line
from tasks.report.tables import batch_table, cache_stats_table, empty_cache_stats, eval_figure_lines, gc_line
from tasks.report.units import human_bytes, local_time, parse_duration, parse_size


def _text(renderable: object) -> str:
    console = Console(width=160, record=True, file=io.StringIO())
    console.print(renderable)
    return console.export_text()


def test_tally_table_and_notes_say_why_a_stage_did_not_simply_pass() -> None:
    tallies = [StageTally(stage="L1", status="accepted", passed=True, attempts=2, loop_sim_calls=6),
               StageTally(stage="L2", status="best_valid", passed=True, attempts=3, loop_sim_calls=9,
                          extra_sim_calls={"screening": 2, "held_out": 4}, unmet_targets=["rebound_ratio"],
                          not_measured={"sag_ratio": "the pinch slipped"}),
               StageTally(stage="L3", status="no_valid_candidate", passed=False, attempts=1, loop_sim_calls=0,
                          message="no grasp")]
    table = _text(tally_table(tallies, {"L1": "mass_kg=0.2"}, title="validation summary"))
    assert "validation summary" in table and "mass_kg=0.2" in table and "best valid" in table and "NO" in table
    assert tally_notes(tallies) == [
        "L2: 15 simulations = 9 in the harness loop + 2 screening + 4 held-out",
        "L2: best valid — the best valid candidate was kept; targets not met: rebound_ratio",
        "L2: sag_ratio not measured — the pinch slipped",
        "L3: NO — no grasp"]
    assert passed_word(tallies[0]) == "[green]yes[/green]"


def test_an_attempt_is_a_heading_and_one_line_per_detail() -> None:
    a = Attempt(stage="L3", iteration=2, action="revise_squeeze", proposal={"squeeze_depth_m": 0.004, "rank": 1},
                source=AgentSource(backend="litellm", model="m", retries=1), verdict="revise", diagnosis="action",
                critique="slipped [x]", evidence=EvidenceRecord(sim_calls=1),
                gates=[GateResult(gate="lifted", metric="lifted", value=0.0, passed=False)])
    head, values, gates, why, where = attempt_block(a, [3], "states: trial 3 interaction/attempt_002")
    assert head == ("[bold]L3 #2 = trial 3[/bold] revise_squeeze (litellm/m, 1 retries): [yellow]revise[/yellow], "
                    "1 simulation")
    assert (values, gates, why) == ("squeeze_depth_m=0.004, rank=1", "failed gates: lifted", r"\[action] slipped \[x]")
    assert where == "states: trial 3 interaction/attempt_002"


def test_the_validation_summary_of_a_manifest_without_its_records(tmp_path: Path) -> None:
    manifest = AssetManifest(request=AssetRequest(text="a cube"), provenance=Provenance(deformsmith_version="t"),
                             validation=[StageSummary(stage="L1", passed=True, attempts=1, sim_calls=3,
                                                      metrics={"mass_kg": 0.25, "other": 1.0}),
                                         StageSummary(stage="L3", passed=False, attempts=2, sim_calls=2,
                                                      failed_gates=["lifted"])])
    tallies, figures = validation_tallies(manifest, tmp_path)  # no evidence/ there: the manifest's lines
    assert [(t.stage, t.passed, t.attempts, t.sim_calls, t.message) for t in tallies] == [
        ("L1", True, 1, 3, ""), ("L3", False, 2, 2, "lifted")]
    assert figures == {"L1": "mass_kg=0.25", "L3": ""}
    assert inspect_lines(manifest) == ["L3 failed gates: lifted"]
    summary = generate_summary(tmp_path, manifest, {"L0": 1.0})
    assert summary["asset_dir"] == str(tmp_path) and summary["material"] is None
    assert summary["wall_time_s"] == {"L0": 1.0} and [s["stage"] for s in summary["validation"]] == ["L1", "L3"]
    assert wall_time_line({"L0": 1.04, "L1": 2.0}) == "wall time: L0 1.0 s, L1 2.0 s"


def test_l1_table_and_mass_check_lines() -> None:
    outcome = StageOutcome(stage="L1", status="accepted", metrics={"mass_kg": 0.3})
    text = _text(physical_table(outcome, None))
    assert "L1 physical model" in text and "accepted" in text and "mass_kg" in text
    assert mass_check_lines({"band_kg": [0.1, 0.4], "source": "concept", "notes": ["a", "b"]}) == [
        "mass check: 100-400 g from concept", "  a", "  b"]


def test_fleet_tables_and_lines() -> None:
    report = BatchReport.build([RequestResult(name="duck", line=1, status="ok", wall_s=3.0, tasks_executed=4,
                                              tasks_cached=2),
                                RequestResult(name="cow", line=2, status="failed", reason="x" * 150)], 3600.0,
                               requests_file="r.jsonl", out_root="out", device="cpu")
    text = _text(batch_table(report))
    assert "batch: 1 ok, 1 failed" in text and "4/2" in text and "x" * 101 not in text
    assert "entries" in _text(cache_stats_table(empty_cache_stats(Path("/c"))))
    assert gc_line({"removed": [1], "freed_bytes": 2048, "remaining_entries": 3, "remaining_bytes": 10},
                   {"removed": [], "freed_bytes": 0}) == ("removed 1 entries (2.0 KB); 3 remain (10 B); "
                                                         "0 temporaries of dead processes removed (0 B)")
    figures = {"harness": {"harness": {"physics_pass": {"value": 0.5, "n": 4, "unit": "rate"},
                                       "sim_calls": {"value": 12.25, "n": 4, "unit": "count"},
                                       "missing": {"value": None, "n": 0, "unit": "rate"}}}}
    assert eval_figure_lines(figures) == ["harness / harness: physics_pass=50% (N=4), sim_calls=12.2 (N=4)"]


def test_units_in_and_out() -> None:
    assert parse_duration("12h") == 43200 and parse_size("1.5KiB") == 1536
    with pytest.raises(InputError):
        parse_size("lots")
    assert [human_bytes(n) for n in (512, 1536, 3 * 1024 ** 5)] == ["512 B", "1.5 KB", "3072.0 TB"]
    assert local_time(None) == "-" and local_time(0.0) == time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(0.0))
