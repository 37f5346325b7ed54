"""`deformsmith batch`: parsing, per-request isolation in real child processes, the report, the CLI."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from flows.batch import NO_L3_JOB, run_batch
from tasks.batch_requests import REPORT_JSON, BatchReport, parse_requests

REPO = Path(__file__).resolve().parents[2]
QUICK = "tests.deployments.jobs:quick_job"


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_parse_flags_each_bad_line_alone(tmp_path: Path) -> None:
    """Malformed JSON, non-objects, invalid requests, bad and duplicate names fail with reasons; the rest parse."""
    items = parse_requests(_write(tmp_path / "r.jsonl", [
        '{"name": "a", "text": "a sponge"}', "{not json", "[1, 2]", "# a comment", "",
        '{"name": "b", "quality": "draft"}', '{"name": "../evil", "text": "x"}', '{"name": "a", "text": "again"}',
        '{"text": "a sponge"}', '{"text": "a sponge"}', '{"text": "x", "quality": "ultra"}']))
    by_line = {i.line: i for i in items}
    assert sorted(by_line) == [1, 2, 3, 6, 7, 8, 9, 10, 11]
    assert by_line[1].request is not None and by_line[1].name == "a"
    assert "malformed JSON" in (by_line[2].error or "")
    assert "JSON object" in (by_line[3].error or "")
    assert "give one input" in (by_line[6].error or "")
    assert "invalid name" in (by_line[7].error or "")
    assert "duplicate name" in (by_line[8].error or "")
    assert by_line[9].name == "a_sponge" and by_line[10].name == "a_sponge-10"
    assert "quality" in (by_line[11].error or "")


def test_batch_isolates_crashes_and_failures(tmp_path: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A SIGKILLed process, a StageFailure and a malformed line each fail alone; the others publish; report complete."""
    monkeypatch.setenv("PYTHONPATH", str(REPO))
    reqs = _write(tmp_path / "r.jsonl", [
        '{"name": "ok1", "text": "sleep 0.5"}', '{"name": "boom", "text": "crash"}', "{oops",
        '{"name": "nogo", "text": "stage-fail"}', '{"name": "ok2", "text": "fine"}'])
    seen: list[str] = []
    report = run_batch(reqs, tmp_path / "out", concurrency=2, job=QUICK, on_result=lambda r: seen.append(r.name))
    status = {r.name: r.status for r in report.results}
    assert status == {"ok1": "ok", "boom": "failed", "line-3": "failed", "nogo": "failed", "ok2": "ok"}
    reasons = {r.name: r.reason or "" for r in report.results}
    assert "SIGKILL" in reasons["boom"]
    assert "StageFailure" in reasons["nogo"] and "no material" in reasons["nogo"]
    assert "malformed JSON" in reasons["line-3"]
    assert (report.requested, report.ok, report.failed) == (5, 2, 3)
    assert report.assets_per_hour > 0 and report.wall_s > 0 and sorted(seen) == sorted(status)
    for name in ("ok1", "ok2"):
        assert (tmp_path / "out" / name / "asset.json").is_file()
    saved = BatchReport.model_validate_json((tmp_path / "out" / REPORT_JSON).read_text(encoding="utf-8"))
    assert saved == report


@pytest.mark.slow  # minutes on 2 cores: the default run keeps a fast sample of the same flow
def test_batch_generates_two_tiny_assets(tmp_path: Path, cache_dir: Path, prefect_api: str) -> None:
    """Two real draft generations (same request, two names) next to a bad line: both publish; every key runs once."""
    reqs = _write(tmp_path / "r.jsonl", [
        '{"name": "sponge-a", "text": "a kitchen sponge 10 x 7 x 3 cm", "quality": "draft"}', "{bad",
        '{"name": "sponge-b", "text": "a kitchen sponge 10 x 7 x 3 cm", "quality": "draft"}'])
    report = run_batch(reqs, tmp_path / "out", concurrency=2, job=NO_L3_JOB)  # L3 of a sponge: minutes per trial
    res = {r.name: r for r in report.results}
    assert res["sponge-a"].status == "ok" and res["sponge-b"].status == "ok", report.results
    assert res["line-2"].status == "failed"
    for name in ("sponge-a", "sponge-b"):
        manifest = json.loads((tmp_path / "out" / name / "asset.json").read_text(encoding="utf-8"))
        assert manifest["request"]["text"] == "a kitchen sponge 10 x 7 x 3 cm"
        assert res[name].wall_s > 0 and res[name].tasks_executed is not None
    events = [json.loads(x) for x in (cache_dir / "events.jsonl").read_text(encoding="utf-8").splitlines()]
    misses = Counter(e["key"] for e in events if e["outcome"] == "miss")
    assert max(misses.values()) == 1  # the second request took every shared result from the cache
    assert res["sponge-a"].tasks_cached + res["sponge-b"].tasks_cached >= len(misses)  # type: ignore[operator]


def test_cli_reports_and_exits_nonzero(tmp_path: Path) -> None:
    """`deformsmith batch` writes the report and exits 1 when a request failed; bad options exit 2."""
    from flows.cli.main import app

    reqs = _write(tmp_path / "r.jsonl", ["{bad", '{"name": "x"}'])
    runner = CliRunner()
    res = runner.invoke(app, ["batch", str(reqs), "--out", str(tmp_path / "out"), "--json"])
    assert res.exit_code == 1, res.output
    data = json.loads(res.stdout)
    assert data["failed"] == 2 and (tmp_path / "out" / REPORT_JSON).is_file()
    assert runner.invoke(app, ["batch", str(reqs), "--concurrency", "0"]).exit_code == 2
    assert runner.invoke(app, ["batch", str(tmp_path / "missing.jsonl")]).exit_code == 2


def test_children_ignore_folders_in_the_working_directory(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                         prefect_api: str) -> None:
    """Run from a folder holding a user's own `cache/` and `tasks/` (no PYTHONPATH: the package comes from the install),
    a child still imports DeformSmith's packages and fails for the request's own reason. Under an editable install,
    a child run with the working directory on sys.path failed every request with "ImportError: cannot import name
    'cached_task' from 'cache' (unknown location)". (Against the session's Prefect server: the batch starts none.)"""
    for name in ("cache", "tasks", "flows", "contracts"):
        (tmp_path / name).mkdir()
    monkeypatch.delenv("PYTHONPATH", raising=False)
    monkeypatch.chdir(tmp_path)
    reqs = _write(tmp_path / "r.jsonl", ['{"name": "wrench", "text": "a steel wrench"}'])
    report = run_batch(reqs, tmp_path / "out", concurrency=1, job=NO_L3_JOB)
    (result,) = report.results
    assert result.status == "failed" and "is a rigid" in (result.reason or ""), result.reason  # material or object


# SIGINT under -m slow (~14 s of CI's 15 minutes): one handler takes both signals (flows/cli/stop.py), SIGTERM runs by
# default, and Ctrl-C itself in tests/generate/test_generate.py (test_ctrl_c_stops_at_once_says_so_and_publishes_nothing)
@pytest.mark.parametrize("signame", [pytest.param("SIGINT", marks=pytest.mark.slow), "SIGTERM"])
def test_ctrl_c_stops_the_batch_at_once_and_reports(tmp_path: Path, signame: str) -> None:
    """SIGINT (Ctrl-C) or SIGTERM while the first of three 60 s requests runs: the batch returns within seconds (it
    used to run every request to its end first, and SIGTERM left its child running), its child is gone, none of the
    others starts, and the report says each was interrupted."""
    proc = _start_batch(tmp_path, 3, stderr=subprocess.PIPE, text=True,
                        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    log = tmp_path / "out" / "_logs" / "r0.log"
    deadline = time.time() + 120
    while not (log.is_file() and str(tmp_path) in _running_batch_jobs()):
        assert proc.poll() is None and time.time() < deadline, proc.stderr.read() if proc.poll() is not None else ""
        time.sleep(0.2)
    t0 = time.time()
    proc.send_signal(getattr(signal, signame))
    proc.communicate(timeout=60)
    assert proc.returncode != 0 and time.time() - t0 < 30
    assert str(tmp_path) not in _running_batch_jobs()
    report = BatchReport.model_validate_json((tmp_path / "out" / REPORT_JSON).read_text(encoding="utf-8"))
    assert sorted((r.name, r.status) for r in report.results) == [("r0", "failed"), ("r1", "failed"), ("r2", "failed")]
    assert all((r.reason or "").startswith("interrupted") for r in report.results)
    assert [r.attempts for r in sorted(report.results, key=lambda r: r.name)] == [1, 0, 0]


def _start_batch(tmp_path: Path, n: int, **popen: Any) -> subprocess.Popen[Any]:
    """run_batch in a process of its own over n requests of 60 s each (r0, r1, ...), out into tmp_path/out."""
    reqs = _write(tmp_path / "r.jsonl", [f'{{"name": "r{i}", "text": "sleep 60"}}' for i in range(n)])
    code = ("import sys; from pathlib import Path; from flows.batch import run_batch; "
            f"run_batch(Path(sys.argv[1]), Path(sys.argv[2]), concurrency=1, job={QUICK!r})")
    return subprocess.Popen([sys.executable, "-c", code, str(reqs), str(tmp_path / "out")], cwd=REPO,
                            env=dict(os.environ, PYTHONPATH=str(REPO)), **popen)


def _running_batch_jobs() -> str:
    return subprocess.run(["pgrep", "-af", "flows.batch_job"], capture_output=True, text=True).stdout


def test_requests_stop_when_the_batch_is_killed(tmp_path: Path) -> None:
    """SIGKILL of the batch (an OOM kill, a crash) while a 60 s request runs: the request, in a session of its own,
    stops within seconds instead of running on with no batch to report to."""
    proc = _start_batch(tmp_path, 1, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while str(tmp_path) not in _running_batch_jobs():
        assert proc.poll() is None and time.time() < deadline
        time.sleep(0.2)
    time.sleep(2.0)  # the request is past its start-up and sleeping
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    deadline = time.time() + 15
    try:
        while str(tmp_path) in _running_batch_jobs():
            assert time.time() < deadline, "the request outlived its batch by 15 s"
            time.sleep(0.2)
    finally:
        subprocess.run(["pkill", "-KILL", "-f", f"flows.batch_job.*{tmp_path}"], check=False)
