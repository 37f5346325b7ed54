"""`deformsmith bench throughput`: the samplers (fed a fake nvidia-smi and a fake /proc), the figures, the resume
records, GPU pinning through the batch runner and the command's checks. No layer runs: the requests are the cheap
jobs of tests/deployments/jobs.py in real child processes."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from contextlib import nullcontext
from pathlib import Path

import pytest
from typer.testing import CliRunner

import flows.batch
from contracts.errors import InputError
from contracts.request import AssetRequest
from flows.throughput import run_throughput
from tasks.batch_requests import BatchItem, parse_requests
from tasks.throughput.ledger import DIR, RECORDS, Ledger, benchmark_items, gpu_slots, request_digest
from tasks.throughput.report import (
    REPORT_JSON, RequestRecord, RunConfig, Session, ThroughputReport, build_report, reason_key, summary_lines,
)
from tasks.throughput.samplers import (
    MIB, GpuSampler, GpuStats, GpuUse, HostMemorySampler, parse_gpu_query, process_table, worker_rss,
)
from tests.deployments.jobs import RUNS_ENV

REPO = Path(__file__).resolve().parents[2]
TIMED = "tests.deployments.jobs:timed_job"
CPU = RunConfig(device="cpu", workers=1, l3=True)


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.fixture
def no_prefect(monkeypatch: pytest.MonkeyPatch) -> None:
    """The batch's children get no Prefect server (the test jobs run no flow) and import this checkout."""
    monkeypatch.setattr(flows.batch, "prefect_api_for_children", lambda: nullcontext({}))
    monkeypatch.setenv("PYTHONPATH", str(REPO))


# ---- samplers ---------------------------------------------------------------------------------------


def test_gpu_sampler_reads_nvidia_smi_output() -> None:
    """Two GPUs over three samples (one field unreadable): per-GPU mean and peak, the mean over all, memory in bytes."""
    assert parse_gpu_query("87, 40000\n[N/A], 512\n\n") == [(87.0, 40000.0), (None, 512.0)]
    outputs = iter(["10, 1000\n50, 2000\n", "30, 3000\n[N/A], 2500\n", "20, 500\n70, [N/A]\n"])
    sampler = GpuSampler(["2", "5"], interval_s=1.0, query=lambda: next(outputs))
    for _ in range(3):
        sampler.sample()
    stats = sampler.stats()
    assert stats is not None and stats.samples == 3
    g2, g5 = stats.gpus
    assert (g2.gpu, g2.samples, g2.util_percent_mean, g2.util_percent_max) == ("2", 3, 20.0, 30.0)
    assert g2.peak_memory_bytes == 3000 * MIB and g5.peak_memory_bytes == 2500 * MIB
    assert (g5.samples, g5.util_percent_mean) == (2, 60.0)
    assert stats.util_percent_mean == 36.0 and stats.peak_memory_bytes == 3000 * MIB  # (10+30+20+50+70)/5
    assert GpuSampler(query=lambda: "").stats() is None  # nothing read: null in the report


def test_gpu_sampler_thread_samples_until_stopped() -> None:
    """Started and stopped as the run does: it samples in the background and a failing query is a missed sample."""
    calls = {"n": 0}

    def query() -> str:
        calls["n"] += 1
        if calls["n"] == 2:
            raise subprocess.CalledProcessError(1, "nvidia-smi")
        return "5, 100\n"

    sampler = GpuSampler(interval_s=0.01, query=query)
    sampler.start()
    time.sleep(0.3)
    sampler.stop()
    stats = sampler.stats()
    assert stats is not None and stats.samples >= 3 and stats.samples == calls["n"] - 1
    assert stats.gpus[0].gpu == "0"


def _proc(root: Path, pid: int, ppid: int, cmd: str, rss_pages: int, name: str = "python") -> None:
    d = root / str(pid)
    d.mkdir(parents=True)
    (d / "stat").write_text(f"{pid} ({name}) S {ppid} {pid} {pid} 0 -1 4194304 100 0 0 0\n")
    (d / "statm").write_text(f"100000 {rss_pages} 500 10 0 900 0\n")
    (d / "cmdline").write_bytes(cmd.replace(" ", "\0").encode() + b"\0")


def test_host_memory_counts_the_workers_and_their_children(tmp_path: Path) -> None:
    """From a fake /proc: the request processes under the benchmark and what they started are summed; the local
    Prefect server (a child too), the benchmark itself and strangers are not; a process name with ') (' parses."""
    proc = tmp_path / "proc"
    _proc(proc, 100, 1, "python -m flows.cli.main bench throughput r.jsonl", 50)
    _proc(proc, 101, 100, "python -m uvicorn prefect.server.api.server:create_app", 70)
    _proc(proc, 102, 100, "python -P -m flows.batch_job --request a.json --out x", 300)
    _proc(proc, 103, 102, "ffmpeg -i - out.mp4", 20, name="ffmpeg) (x")
    _proc(proc, 104, 100, "python -P -m flows.batch_job --request b.json --out y", 200)
    _proc(proc, 105, 1, "python -P -m flows.batch_job --request c.json --out z", 999)  # another benchmark's
    (proc / "self").mkdir()
    (proc / "meminfo").write_text("MemTotal:       1000 kB\nMemFree:         100 kB\nMemAvailable:    400 kB\n")
    table = process_table(proc, page_bytes=4096)
    assert table[103].ppid == 102 and set(table) == {100, 101, 102, 103, 104, 105}
    assert worker_rss(table, 100) == ((300 + 20 + 200) * 4096, 300 * 4096)
    sampler = HostMemorySampler(100, proc_root=proc, page_bytes=4096)
    sampler.sample()
    (proc / "104" / "statm").write_text("100000 600 500 10 0 900 0\n")
    sampler.sample()
    stats = sampler.stats()
    assert stats is not None and stats.samples == 2
    assert stats.peak_workers_rss_bytes == (300 + 20 + 600) * 4096 and stats.peak_worker_rss_bytes == 600 * 4096
    assert stats.peak_host_used_bytes == 600 * 1024
    assert HostMemorySampler(100, proc_root=proc).stats() is None


# ---- the figures ------------------------------------------------------------------------------------


def _rec(name: str, line: int, status: str = "ok", wall: float | None = 100.0, stages: dict | None = None,
         size: int | None = 1000, l3: bool | None = True, reason: str | None = None, session: int = 0,
         at: float = 0.0) -> RequestRecord:
    return RequestRecord(name=name, line=line, request_digest=name, status=status, reason=reason, wall_s=wall,
                         stage_s=stages or {}, asset_bytes=size if status == "ok" else None, l3_passed=l3,
                         tasks_executed=10, tasks_cached=1, session=session, finished_at=at)


def test_reasons_group_without_their_particulars() -> None:
    assert reason_key("StageFailure: L2 failed: no material passed the gates") == "StageFailure L2"
    assert reason_key("InputError: 'a steel wrench' is a rigid object") == "InputError"
    assert reason_key("process died from signal SIGKILL; last log line: x") == "process died from signal SIGKILL"
    assert reason_key("timed out after 600 s; last log line: L3 trial 2") == "timed out"
    assert reason_key("interrupted after 3.0 s") == "interrupted"
    assert reason_key("SimulationError: NaN in the rollout") == "SimulationError"
    assert reason_key(None) == "unknown"


def test_report_figures() -> None:
    """Assets per hour over the sessions' wall time (a killed session's up to its last beat or record), stage shares of the
    published requests' time with 'other' the rest, bytes per asset, L3 passes, failures grouped, pending counted,
    GPU samples merged over sessions."""
    stages = {"L0": 10.0, "L1": 5.0, "L2": 40.0, "renders": 10.0, "L3": 20.0, "card": 5.0}
    records = [
        _rec("a", 1, stages=stages, size=1000, session=0, at=1800.0),
        _rec("b", 2, stages=stages, size=3000, l3=False, session=1, at=5000.0),
        _rec("c", 3, wall=None, size=2000, session=1, at=5000.0),  # recovered: no time record
        _rec("d", 4, status="failed", reason="StageFailure: L2 failed: no material", session=1, at=4000.0),
        _rec("e", 5, status="failed", reason="StageFailure: L2 failed: budget spent", session=1, at=4500.0),
    ]
    def gpu(util: float, mem: int, n: int) -> GpuStats:
        use = GpuUse(gpu="0", samples=n, util_percent_mean=util, util_percent_max=util, peak_memory_bytes=mem)
        return GpuStats(samples=n, interval_s=1.0, util_percent_mean=util, peak_memory_bytes=mem, gpus=[use])

    sessions = [Session(index=0, started_at=0.0, ended_at=None, config=CPU, gpu=gpu(90.0, 5, 100)),  # killed
                Session(index=1, started_at=4000.0, ended_at=5800.0, config=CPU, gpu=gpu(30.0, 9, 300))]
    report = build_report(records, sessions, requested=6, requests_file="r", out_root="o", cache_root="c")
    assert report.wall_s == 1800.0 + 1800.0
    beat = [sessions[0].model_copy(update={"alive_at": 1900.0}), sessions[1]]  # it ran on after its last record
    assert build_report(records, beat, 6, requests_file="r", out_root="o", cache_root="c").wall_s == 1900.0 + 1800.0
    assert (report.ok, report.failed, report.pending, report.l3_passed) == (3, 2, 1, 2)
    assert report.assets_per_hour == 3.0 and report.l3_passed_per_hour == 2.0
    assert report.stage_s_per_asset == {"L0": 10.0, "L1": 5.0, "L2": 40.0, "renders": 10.0, "L3": 20.0, "card": 5.0,
                                        "other": 10.0}
    assert list(report.stage_share) == ["L0", "L1", "L2", "renders", "L3", "card", "other"]
    assert report.stage_share["L2"] == 0.4 and abs(sum(report.stage_share.values()) - 1.0) < 1e-3
    assert report.bytes_per_asset is not None
    assert (report.bytes_per_asset.mean, report.bytes_per_asset.max, report.bytes_per_asset.total) == (2000.0, 3000,
                                                                                                      6000)
    assert report.failures["StageFailure L2"].count == 2 and report.failures["StageFailure L2"].names == ["d", "e"]
    assert report.gpu is not None and report.gpu.util_percent_mean == 45.0 and report.gpu.peak_memory_bytes == 9
    assert report.cache == {"tasks_executed": 50, "tasks_cached": 5}
    assert report.host_memory is None
    text = "\n".join(summary_lines(report))
    assert "3.0 distinct assets per hour" in text and "L2 40.0 s (40 %)" in text and "StageFailure L2" in text
    assert ThroughputReport.model_validate_json(report.model_dump_json()) == report


# ---- the run on disk: resuming ----------------------------------------------------------------------


def _items(tmp_path: Path, texts: list[str]) -> list[BatchItem]:
    return benchmark_items(_write(tmp_path / "r.jsonl", [json.dumps({"name": f"r{i}", "text": t})
                                                          for i, t in enumerate(texts)]))


def _publish(out: Path, name: str, text: str) -> None:
    (out / name).mkdir(parents=True)
    (out / name / "asset.json").write_text(json.dumps({"request": AssetRequest(text=text).model_dump(mode="json")}))


def test_resume_plan(tmp_path: Path) -> None:
    """Done: published with its record, failed for a reason of its own, published with no record (recovered, recorded
    now). Run again: interrupted, published record whose asset is gone, record of another request under the name,
    a published asset of another request, never started."""
    texts = [f"object {i}" for i in range(8)]
    items = _items(tmp_path, texts)
    out = tmp_path / "out"
    ledger = Ledger(out)
    digest = {i.name: request_digest(i.request) for i in items if i.request is not None}

    def rec(name: str, **kw: str) -> RequestRecord:
        return RequestRecord(name=name, line=0, request_digest=digest[name], session=0, finished_at=1.0,
                             **{"status": "ok", **kw})

    ledger.append(rec("r0"))
    _publish(out, "r0", texts[0])
    ledger.append(rec("r1", status="failed", reason="StageFailure: L2 failed: x"))
    _publish(out, "r2", texts[2])  # killed between its publish and its record
    ledger.append(rec("r3", status="failed", reason="interrupted after 2.0 s"))
    ledger.append(rec("r4"))  # its asset was removed since
    ledger.append(rec("r5").model_copy(update={"request_digest": "another"}))
    _publish(out, "r6", "something else")
    todo, done = ledger.plan(items, session=1)
    assert [i.name for i in todo] == ["r3", "r4", "r5", "r6", "r7"]
    assert [(r.name, r.status, r.recovered) for r in done] == [("r0", "ok", False), ("r1", "failed", False),
                                                                ("r2", "ok", True)]
    assert ledger.records()["r2"].recovered and ledger.records()["r2"].asset_bytes
    assert [r.name for r in ledger.current(items)] == ["r0", "r1", "r2"]  # r3's interruption: pending, not failed
    with (out / DIR / RECORDS).open("a") as fh:
        fh.write('{"name": "r7", "cut sho')  # a line a kill cut short is skipped
    assert "r7" not in ledger.records()


def test_sessions_and_request_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A resumed run of another configuration is refused; a session's request file keeps each request's name and
    request; gpu_slots pins K workers to each GPU, round robin."""
    ledger = Ledger(tmp_path / "out")
    s0 = ledger.start_session(CPU)
    ledger.end_session(s0)
    with pytest.raises(InputError, match="a throughput run with other options"):
        ledger.start_session(CPU.model_copy(update={"workers": 2}))
    s1 = ledger.start_session(CPU)
    assert [s.index for s in ledger.sessions()] == [0, 1] and ledger.sessions()[0].ended_at is not None
    halt = ledger.heartbeat(s1, interval_s=0.01)
    time.sleep(0.2)
    halt()
    alive = ledger.sessions()[1].alive_at
    assert alive is not None and s1.started_at < alive <= time.time() and ledger.sessions()[1].ended_at is None
    ledger.end_session(s1)
    assert ledger.sessions()[1].alive_at == alive and ledger.sessions()[1].ended_at is not None  # the beat kept
    items = _items(tmp_path, ["a plush koala", "a kitchen sponge 10 x 7 x 3 cm"])
    again = parse_requests(ledger.write_requests(items[1:], s1.index))
    assert items[1].request is not None
    assert [(i.name, request_digest(i.request)) for i in again if i.request] == [
        (items[1].name, request_digest(items[1].request))]
    monkeypatch.delenv("CUDA_DEVICE_ORDER", raising=False)
    slots = gpu_slots(["0", "1"], 2)
    assert [s["CUDA_VISIBLE_DEVICES"] for s in slots] == ["0", "1", "0", "1"]
    assert all(s["CUDA_DEVICE_ORDER"] == "PCI_BUS_ID" for s in slots)


def test_benchmark_requests_are_valid_and_distinct(tmp_path: Path) -> None:
    assert len(benchmark_items(_write(tmp_path / "a.jsonl", ['{"text": "a"}', '{"text": "b"}', '{"text": "c"}']),
                               limit=2)) == 2
    with pytest.raises(InputError, match="line 2: malformed JSON"):
        benchmark_items(_write(tmp_path / "b.jsonl", ['{"text": "a"}', "{oops"]))
    with pytest.raises(InputError, match="line 3 repeats line 1"):
        benchmark_items(_write(tmp_path / "c.jsonl", ['{"text": "a"}', '{"text": "b"}', '{"name": "x", "text": "a"}']))


# ---- end to end with cheap jobs ---------------------------------------------------------------------


def test_gpu_workers_are_pinned_and_a_rerun_resumes(tmp_path: Path, no_prefect: None,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """--gpus 2 --workers-per-gpu 2 through the batch runner: four workers at once, each request process pinned to
    one GPU, both GPUs used; the report has every figure; a rerun runs nothing again and adds a session."""
    runs = tmp_path / "runs.txt"
    monkeypatch.setenv(RUNS_ENV, str(runs))
    monkeypatch.setattr("flows.throughput.nvidia_smi_available", lambda: False)
    texts = [f"sleep 0.{i}" for i in range(1, 7)] + ["stage-fail"]
    reqs = _write(tmp_path / "r.jsonl", [json.dumps({"name": f"r{i}", "text": t}) for i, t in enumerate(texts)])
    out = tmp_path / "out"
    report = run_throughput(reqs, out, gpus=["0", "1"], workers_per_gpu=2, job=TIMED)
    assert (report.ok, report.failed, report.pending) == (6, 1, 0)
    assert report.config.workers == 4 and report.config.device == "cuda"
    pinned = [json.loads((out / f"r{i}" / "asset.json").read_text())["gpu"] for i in range(6)]
    assert set(pinned) == {"0", "1"}
    assert report.failures["StageFailure L2"].names == ["r6"]
    assert report.stage_share and set(report.stage_s_per_asset) == {"L0", "L2", "other"}
    assert report.bytes_per_asset is not None and report.bytes_per_asset.min > 1000
    assert report.l3_passed == 6 and report.assets_per_hour > 0 and report.gpu is None
    assert report.host_memory is not None and report.host_memory.samples >= 1
    assert ThroughputReport.model_validate_json((out / REPORT_JSON).read_text()) == report
    assert len(runs.read_text().splitlines()) == 7
    again = run_throughput(reqs, out, gpus=["0", "1"], workers_per_gpu=2, job=TIMED)
    assert len(runs.read_text().splitlines()) == 7  # nothing ran twice
    assert (again.ok, again.failed, len(again.sessions)) == (6, 1, 2)


def test_a_killed_run_resumes_where_it_left_off(tmp_path: Path) -> None:
    """SIGKILL of the benchmark while its second request runs: the rerun does the second and third requests only, the
    first (finished before the kill) is not run again, and the report covers both sessions."""
    runs = tmp_path / "runs.txt"
    reqs = _write(tmp_path / "r.jsonl", [json.dumps({"name": f"r{i}", "text": t})
                                         for i, t in enumerate(["sleep 0.1", "sleep 60", "sleep 0.2"])])
    out = tmp_path / "out"
    code = ("import sys, contextlib; from pathlib import Path; import flows.batch; "
            "flows.batch.prefect_api_for_children = lambda: contextlib.nullcontext({}); "
            "from flows.throughput import run_throughput; "
            f"run_throughput(Path(sys.argv[1]), Path(sys.argv[2]), job={TIMED!r})")
    env = dict(os.environ, PYTHONPATH=str(REPO), **{RUNS_ENV: str(runs)})
    proc = subprocess.Popen([sys.executable, "-c", code, str(reqs), str(out)], cwd=REPO, env=env,
                            stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while not (runs.is_file() and "sleep 60" in runs.read_text()):
        assert proc.poll() is None and time.time() < deadline
        time.sleep(0.2)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    assert (out / "r0" / "asset.json").is_file() and not (out / "r1").exists()
    assert not (out / REPORT_JSON).exists()  # the kill left no report: the records are what the rerun reads
    reqs.write_text(reqs.read_text().replace("sleep 60", "sleep 0.3"))  # (the killed request runs again, quicker)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(flows.batch, "prefect_api_for_children", lambda: nullcontext({}))
        mp.setenv("PYTHONPATH", str(REPO))
        mp.setenv(RUNS_ENV, str(runs))
        report = run_throughput(reqs, out, job=TIMED)
    assert runs.read_text().splitlines() == ["sleep 0.1", "sleep 60", "sleep 0.3", "sleep 0.2"]
    assert (report.ok, report.pending, len(report.sessions)) == (3, 0, 2)
    assert [r.session for r in report.records] == [0, 1, 1]
    assert report.sessions[0].ended_at is None and report.wall_s > 0


def _fake_nvidia_smi(tmp_path: Path) -> tuple[Path, Path]:
    """A directory with an `nvidia-smi` that notes each call in a file and reports one GPU at 37 % and 2048 MiB."""
    bin_dir, calls = tmp_path / "bin", tmp_path / "smi-calls.txt"
    bin_dir.mkdir()
    smi = bin_dir / "nvidia-smi"
    smi.write_text(f"#!/bin/sh\necho x >> '{calls}'\necho '37, 2048'\n", encoding="utf-8")
    smi.chmod(0o755)
    return bin_dir, calls


def _throughput_process(tmp_path: Path, texts: list[str], beat_s: float, cli_stop: bool) -> tuple[
        subprocess.Popen[bytes], Path, Path]:
    """The benchmark in a child process with a fake nvidia-smi, sampling every 0.05 s and beating every beat_s
    (cli_stop: SIGTERM and SIGINT taken as the command line takes them, flows.cli.stop: the process ends ~1.3 s
    after the signal whether or not its requests have stopped); returns (it, the output root, the nvidia-smi calls)."""
    bin_dir, calls = _fake_nvidia_smi(tmp_path)
    reqs = _write(tmp_path / "r.jsonl", [json.dumps({"name": f"r{i}", "text": t}) for i, t in enumerate(texts)])
    out = tmp_path / "out"
    code = ("import sys, contextlib; from pathlib import Path; import flows.batch, flows.throughput; "
            "from flows.cli import stop; "
            "flows.batch.prefect_api_for_children = lambda: contextlib.nullcontext({}); "
            f"flows.throughput.SAMPLE_S = 0.05; flows.throughput.BEAT_S = {beat_s!r}\n"
            + ("stop.install(sys.argv, resumes=True)\n" if cli_stop else "")
            + "try:\n"
            f"    flows.throughput.run_throughput(Path(sys.argv[1]), Path(sys.argv[2]), job={TIMED!r})\n"
            "except BaseException:\n"
            "    if stop.stopped() is None:\n"
            "        raise\n"
            "    stop.leave(stop.stopped() or 130)\n")
    env = dict(os.environ, PYTHONPATH=str(REPO), PATH=f"{bin_dir}{os.pathsep}{os.environ['PATH']}",
               **{RUNS_ENV: str(tmp_path / "runs.txt")})
    proc = subprocess.Popen([sys.executable, "-c", code, str(reqs), str(out)], cwd=REPO, env=env,
                            stderr=subprocess.DEVNULL)
    return proc, out, calls


def _wait_for(proc: subprocess.Popen[bytes], ready: Callable[[], bool], timeout_s: float = 60.0) -> None:
    """Until ready(); the process killed (its requests end when orphaned) if it ends or the time runs out first."""
    deadline = time.time() + timeout_s
    while not ready():
        if proc.poll() is not None or time.time() > deadline:
            proc.kill()
            proc.wait()
            pytest.fail(f"not ready after {time.time() - deadline + timeout_s:.1f} s (rc {proc.returncode})")
        time.sleep(0.1)


def _sampled(session: Session) -> None:
    """The fake nvidia-smi's figures and the host sampler's, as the session keeps them."""
    assert session.gpu is not None and session.gpu.samples >= 1, session
    assert session.gpu.util_percent_mean == 37.0 and session.gpu.peak_memory_bytes == 2048 * MIB
    assert session.host_memory is not None and session.host_memory.samples >= 1


def test_a_sigterm_stopped_run_keeps_its_end_and_samples(tmp_path: Path) -> None:
    """SIGTERM as the command line takes it while a request slow to stop runs (it ignores SIGINT: the command line's
    backstop ends the benchmark before its children have stopped and its `finally` has run), with no heartbeat
    written yet: the session keeps its end and what the samplers saw (s25's first session kept neither), and the
    report is written (s30's 2-GPU run of 24 workers left none)."""
    proc, out, calls = _throughput_process(tmp_path, ["sleep 300 stubborn"], beat_s=600.0, cli_stop=True)
    runs = tmp_path / "runs.txt"
    _wait_for(proc, lambda: runs.is_file() and "stubborn" in runs.read_text()
              and calls.is_file() and len(calls.read_text().split()) >= 2)
    t_signal = time.time()
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=30) == 143
    session = Ledger(out).sessions()[0]
    assert session.ended_at is not None and t_signal <= session.ended_at <= t_signal + 1.3
    _sampled(session)
    report = ThroughputReport.model_validate_json((out / REPORT_JSON).read_text())  # written before the backstop
    assert (report.ok, report.pending) == (0, 1) and report.sessions[0].ended_at == session.ended_at


def test_a_killed_run_keeps_the_samples_of_its_last_beat(tmp_path: Path) -> None:
    """SIGKILL: nothing runs at the end, and the session keeps what its last heartbeat wrote: its time and the
    samples so far, which the report takes."""
    proc, out, calls = _throughput_process(tmp_path, ["sleep 300"], beat_s=0.1, cli_stop=False)
    ledger, runs = Ledger(out), tmp_path / "runs.txt"
    # (the request running first: a request orphaned before it watches its parent would not stop)
    _wait_for(proc, lambda: runs.is_file() and bool(ledger.sessions()) and ledger.sessions()[0].gpu is not None)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    session = ledger.sessions()[0]
    assert session.ended_at is None and session.alive_at is not None
    _sampled(session)
    report = build_report([], ledger.sessions(), 1, requests_file="r", out_root=str(out), cache_root="c")
    assert report.gpu is not None and report.gpu.util_percent_mean == 37.0 and report.host_memory is not None


# ---- the command --------------------------------------------------------------------------------------


def test_cli_checks_its_input(tmp_path: Path) -> None:
    """A missing or bad requests file and impossible worker options: one `error:` line, exit 2, nothing run."""
    from flows.cli.main import app  # (the app with every command registered, as test_batch imports it)

    runner = CliRunner()
    good = _write(tmp_path / "r.jsonl", ['{"text": "a kitchen sponge"}'])
    cases = {
        (str(tmp_path / "missing.jsonl"),): "requests file not found",
        (str(_write(tmp_path / "bad.jsonl", ['{"text": "a kitchen sponge"}', "{oops"])),): "line 2: malformed JSON",
        (str(good), "--gpus", "0"): "--gpus must be >= 1, got 0",
        (str(good), "--gpus", "-2"): "--gpus must be >= 1, got -2",
        (str(good), "--workers-per-gpu", "2"): "--workers-per-gpu needs --gpus",
        (str(good), "--gpus", "1", "--workers-per-gpu", "0"): "--workers-per-gpu must be >= 1",
        (str(good), "--gpus", "1", "--concurrency", "2"): "--concurrency is for the CPU",
        (str(good), "--concurrency", "0"): "--concurrency must be >= 1",
        (str(good), "--limit", "0"): "--limit must be >= 1",
    }
    for args, message in cases.items():
        res = runner.invoke(app, ["bench", "throughput", *args, "--out", str(tmp_path / "out")])
        lines = [ln for ln in res.output.splitlines() if ln.strip()]
        assert res.exit_code == 2 and lines == [f"error: {lines[0].removeprefix('error: ')}"], (args, res.output)
        assert message in lines[0], (args, res.output)
    res = runner.invoke(app, ["bench", "throughput", str(good), "--gpus", "3", "--out", str(tmp_path / "out")],
                        env={"CUDA_VISIBLE_DEVICES": "0"})
    assert res.exit_code == 2 and "--gpus 3: only 1 GPU(s) here (0)" in res.output
    assert not (tmp_path / "out").exists()


def test_cli_runs_and_prints_json(tmp_path: Path, no_prefect: None, monkeypatch: pytest.MonkeyPatch) -> None:
    """The command end to end on the CPU with cheap jobs (--no-l3 names the job): JSON on stdout, the report and the
    default cache root (OUT/_cache) in it."""
    from flows.cli.main import app  # (the app with every command registered, as test_batch imports it)

    monkeypatch.setattr("flows.throughput.NO_L3_JOB", TIMED)
    reqs = _write(tmp_path / "r.jsonl", ['{"text": "sleep 0.1 no-l3"}', '{"text": "sleep 0.2 no-l3"}'])
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["bench", "throughput", str(reqs), "--no-l3", "--limit", "1", "--out", str(out),
                                   "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert (data["requested"], data["ok"], data["l3_passed"]) == (1, 1, None)
    assert data["cache_root"] == str((out / "_cache").absolute()) and data["config"]["l3"] is False
    if shutil.which("nvidia-smi") is None:
        assert data["gpu"] is None
    assert (out / REPORT_JSON).is_file() and (out / "sleep_0_1_no_l3" / "asset.json").is_file()
