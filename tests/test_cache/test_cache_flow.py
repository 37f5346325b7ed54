"""Proofs a-f of issue 2 on a three-stage demonstration flow (sample -> deform -> summarize)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import cache_demo_flow as demo
from cache import CacheStore, cache_root, content_key
from contracts.errors import CacheError

REPO = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent


@pytest.fixture
def counter(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Execution counter file shared with subprocesses."""
    path = tmp_path / "executions.txt"
    monkeypatch.setenv("DEMO_COUNTER", str(path))
    return path


def _new(counter: Path, before: list[str]) -> list[str]:
    return demo.executions(counter)[len(before):]


def _sub_env(prefect_api: str, **extra: str) -> dict[str, str]:
    env = dict(os.environ, PREFECT_API_URL=prefect_api, PYTHONPATH=os.pathsep.join([str(REPO), str(HERE)]))
    env.update(extra)
    return env


def _spawn(prefect_api: str, code: str, **extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-c", code], cwd=REPO, env=_sub_env(prefect_api, **extra),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def test_a_b_c_rerun_change_middle_restore(prefect_api: str, counter: Path) -> None:
    first = demo.run(stiffness=10.0)
    assert demo.executions(counter) == ["sample", "deform", "summarize"]
    assert isinstance(first, demo.DemoSummary)

    before = demo.executions(counter)  # a. unchanged: nothing executes, same result
    assert demo.run(stiffness=10.0) == first
    assert _new(counter, before) == []

    before = demo.executions(counter)  # b. middle stage parameter: that stage and what follows
    changed = demo.run(stiffness=20.0)
    assert _new(counter, before) == ["deform", "summarize"]
    assert changed != first

    before = demo.executions(counter)  # c. restore: nothing executes
    assert demo.run(stiffness=10.0) == first
    assert _new(counter, before) == []

    events = CacheStore(cache_root()).events()  # the execution log tells the same story
    assert [(e["task"], e["outcome"]) for e in events[-3:]] == [
        ("demo.sample", "hit"), ("demo.deform", "hit"), ("demo.summarize", "hit")]
    assert sum(e["outcome"] == "miss" for e in events) == 5


def test_hits_show_as_cached_in_prefect(prefect_api: str, counter: Path) -> None:
    from prefect import flow

    @flow
    def states() -> list[str]:
        pts = demo.sample(100, 1)
        return [demo.sample(100, 1, return_state=True).name, demo.deform(pts, 5.0, return_state=True).name,
                demo.deform(pts, 5.0, return_state=True).name]

    with demo.local_runtime():
        assert states() == ["Cached", "Completed", "Cached"]
    assert demo.executions(counter) == ["sample", "deform"]


def test_same_key_submitted_concurrently_in_one_flow(prefect_api: str, counter: Path) -> None:
    from prefect import flow

    @flow
    def twice() -> list[str]:
        futures = [demo.sample.submit(300, 9) for _ in range(2)]
        return sorted(f.wait() or f.state.name for f in futures)

    with demo.local_runtime():
        assert twice() == ["Cached", "Completed"]
    assert demo.executions(counter) == ["sample"]


def test_cached_task_outside_a_flow(prefect_api: str, counter: Path) -> None:
    s1 = demo.sample(50, 3, return_state=True)
    s2 = demo.sample(50, 3, return_state=True)
    assert (s1.name, s2.name) == ("Completed", "Cached")
    np.testing.assert_array_equal(s1.result(), s2.result())
    assert demo.executions(counter) == ["sample"]


def test_d_sigkill_in_middle_stage_then_rerun(prefect_api: str, counter: Path, tmp_path: Path) -> None:
    pause = tmp_path / "deform-started"
    proc = _spawn(prefect_api, "import cache_demo_flow as m; m.cli(['10.0'])", DEMO_PAUSE_FILE=str(pause))
    deadline = time.monotonic() + 120
    while not pause.exists():
        assert proc.poll() is None, proc.stdout.read() if proc.stdout else ""
        assert time.monotonic() < deadline, "middle stage never started"
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(30)
    assert demo.executions(counter) == ["sample", "deform"]
    store = CacheStore(cache_root())
    assert len(store.keys()) == 1 and store.verify() == []  # only the finished stage was published

    before = demo.executions(counter)
    resumed = demo.run(stiffness=10.0)
    assert _new(counter, before) == ["deform", "summarize"]  # finished stage 1 is a hit
    assert [e["outcome"] for e in store.events()[-3:]] == ["hit", "miss", "miss"]

    os.environ["DEFORMSMITH_CACHE"] = str(tmp_path / "clean-cache")  # uninterrupted reference run
    assert demo.run(stiffness=10.0) == resumed


def test_e_two_processes_race_on_one_key(prefect_api: str, counter: Path, tmp_path: Path) -> None:
    code = ("import time, cache_demo_flow as m; from cache import cached_task\n"
            "@cached_task(version='1', name='demo.slow')\n"
            "def slow(x: int) -> dict:\n"
            "    m._count('slow'); time.sleep(1.5); return {'x': x, 'arr': m.np.arange(100_000.0)}\n"
            "s = slow(7, return_state=True); print('STATE', s.name, float(s.result()['arr'].sum()))\n")
    barrier = tmp_path / "go"
    gate = (f"import os, time, prefect, cache.prefect_task\nopen(os.path.join({str(tmp_path)!r}, f'ready-{{os.getpid()}}'), 'w').close()\n"
            f"while not os.path.exists({str(barrier)!r}): time.sleep(0.005)\n")
    procs = [_spawn(prefect_api, gate + code) for _ in range(2)]
    deadline = time.monotonic() + 120
    while len(list(tmp_path.glob("ready-*"))) < 2:  # both imported, then released together
        assert time.monotonic() < deadline and all(p.poll() is None for p in procs)
        time.sleep(0.02)
    barrier.touch()
    outs = [p.communicate(timeout=180)[0] for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    states = sorted(line.split()[1] for o in outs for line in o.splitlines() if line.startswith("STATE"))
    assert states == ["Cached", "Completed"], outs
    assert demo.executions(counter) == ["slow"]
    store = CacheStore(cache_root())
    assert len(store.keys()) == 1 and store.verify() == []
    assert all(f"{float(np.arange(100_000.0).sum())}" in o for o in outs)


def test_f_corrupt_entry_is_a_miss_and_never_returned(prefect_api: str, counter: Path) -> None:
    from typer.testing import CliRunner

    from flows.cli import cache_cmds  # noqa: F401  (registers the commands)
    from flows.cli.apps import app

    first = demo.run(n=500, stiffness=10.0)
    store = CacheStore(cache_root())
    deform_key = next(e["key"] for e in store.events() if e["task"] == "demo.deform")
    chunk = next(p for p in (store.entry_dir(deform_key) / "a0").rglob("*") if p.is_file() and p.name != "zarr.json")
    data = bytearray(chunk.read_bytes())
    data[7] ^= 0x01
    chunk.write_bytes(bytes(data))

    res = CliRunner().invoke(app, ["cache", "verify", "--cache", str(store.root)])
    assert res.exit_code == 1 and deform_key in res.stdout + res.stderr  # the report is a result (stdout)

    before = demo.executions(counter)
    assert demo.run(n=500, stiffness=10.0) == first  # corrupt entry recomputed, the rest are hits
    assert _new(counter, before) == ["deform"]
    assert CliRunner().invoke(app, ["cache", "verify", "--cache", str(store.root)]).exit_code == 0


def test_unhashable_input_fails_the_task(prefect_api: str, tmp_path: Path) -> None:
    from cache import cached_task

    @cached_task(version="1", name="demo.needs_file")
    def read_size(path: Path) -> int:
        return path.stat().st_size

    f = tmp_path / "in.bin"
    f.write_bytes(b"1234")
    assert read_size(f) == 4
    with pytest.raises(CacheError, match="cache key"):
        read_size(tmp_path / "missing.bin")
    assert content_key(f) != content_key(tmp_path)
