"""Every attempt is recorded to JSONL and the Rerun harness/log, reloads into the models, and prints as a table."""

from __future__ import annotations

import json
from pathlib import Path

from harness_fakes import FakeL2Probes, l2_targets
from typer.testing import CliRunner

from contracts.agents import StageOutcome
from contracts.evidence import Attempt
from flows.cli.main import app
from tasks.agents.orchestrator import run_stage
from tasks.agents.records import AttemptRecorder, read_attempts
from tasks.record import HARNESS_LOG, read_recording


def _run(l2, root: Path, modulus_pa: float = 5e4) -> StageOutcome:  # noqa: ANN001
    rec = AttemptRecorder(root, "L2")
    out = run_stage(l2, FakeL2Probes(), l2_targets(modulus_pa), recorder=rec)
    rec.close(out)
    return out


def test_records_are_complete_and_reload(l2, tmp_path: Path) -> None:
    out = _run(l2, tmp_path)
    lines = (tmp_path / "evidence" / "attempts.jsonl").read_text().splitlines()
    reloaded = read_attempts(tmp_path / "evidence" / "attempts.jsonl")
    assert reloaded == out.attempts and len(lines) == out.attempts_used
    for a in reloaded:
        assert isinstance(a, Attempt) and a.stage == "L2" and a.source.backend == "rule"
        assert a.action in l2.permitted_actions and a.proposal and a.rationale
        assert set(a.evidence.metrics) >= set(l2.required_observations)
        assert [g.gate for g in a.gates] == [g.name for g in l2.hard_gates]
        assert a.verdict in ("accepted", "best_so_far", "rolled_back", "revise") and a.score is not None
        assert a.critic_source is not None and a.planner_source is not None
    assert [a.parent_iteration for a in reloaded][0] is None
    assert all(a.parent_iteration is not None for a in reloaded[1:])  # the revision history links every attempt
    summary = StageOutcome.model_validate_json((tmp_path / "evidence" / "L2_outcome.json").read_text())
    assert summary.status == out.status == "accepted" and summary.values == out.values
    rrd = read_recording(tmp_path / "recordings" / "harness_L2.rrd")
    assert HARNESS_LOG in rrd.entity_paths and rrd.rows_per_entity[HARNESS_LOG] == out.attempts_used + 1


def test_rerun_of_a_stage_replaces_its_lines_and_keeps_other_stages(l2, tmp_path: Path) -> None:
    other = Attempt(stage="L1", iteration=0, action="propose_density", proposal={"density_kg_per_m3": 100.0},
                    source={"backend": "rule"}, verdict="accepted")
    (tmp_path / "evidence").mkdir()
    (tmp_path / "evidence" / "attempts.jsonl").write_text(other.model_dump_json() + "\n")
    first = _run(l2, tmp_path)
    second = _run(l2, tmp_path)
    reloaded = read_attempts(tmp_path / "evidence" / "attempts.jsonl")
    assert reloaded[0] == other and reloaded[1:] == second.attempts == first.attempts


def test_evidence_command_table_and_json(l2, tmp_path: Path) -> None:
    out = _run(l2, tmp_path / "asset")
    runner = CliRunner()
    res = runner.invoke(app, ["evidence", str(tmp_path / "asset"), "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert [d["verdict"] for d in data] == [a.verdict for a in out.attempts]
    res = runner.invoke(app, ["evidence", str(tmp_path)], env={"COLUMNS": "250"})  # a run dir: searched recursively
    assert res.exit_code == 0
    assert "propose_material" in res.output and "accepted" in res.output
    res = runner.invoke(app, ["evidence", str(tmp_path / "missing")])
    assert res.exit_code != 0 and "no such file" in res.output
    (tmp_path / "bad.jsonl").write_text("{not json}\n")
    res = runner.invoke(app, ["evidence", str(tmp_path / "bad.jsonl")])
    assert res.exit_code != 0 and "bad.jsonl:1" in res.output


def test_a_nan_metric_survives_the_round_trip(tmp_path: Path) -> None:
    """A trial whose object slipped has no hold force (NaN, written as JSON null): the line reloads with NaN instead
    of failing, so a rerun of the stage can read the file it wrote."""
    import math

    from contracts.evidence import EvidenceRecord

    a = Attempt(stage="L3", iteration=0, action="revise_squeeze", proposal={"squeeze_depth_m": 0.004},
                source={"backend": "rule"}, verdict="revise",
                evidence=EvidenceRecord(metrics={"lifted": 0.0, "hold_normal_force_n": math.nan}))
    path = tmp_path / "attempts.jsonl"
    path.write_text(a.model_dump_json() + "\n")
    assert '"hold_normal_force_n":null' in path.read_text()
    (back,) = read_attempts(path)
    assert back.evidence.metrics["lifted"] == 0.0 and math.isnan(back.evidence.metrics["hold_normal_force_n"])
