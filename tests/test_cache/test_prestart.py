"""Prefect's local API server started in the background by flow commands (cache.runtime.prestart_local_server)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import cache.runtime as runtime
from flows.cli import main as cli_main

REPO = Path(__file__).resolve().parents[2]

_SCRIPT = """
import json, os, sys, time
t0 = time.perf_counter()
from cache.runtime import prestart_local_server, prestarted_api_url, local_runtime
prestart_local_server()
from prefect import flow
from prefect.settings import PREFECT_API_URL

@flow
def double(x: int) -> int:
    return 2 * x

with local_runtime():
    used = str(PREFECT_API_URL.value())
    value = double(21)
print(json.dumps({"url": prestarted_api_url(), "used": used, "value": value,
                  "server_module_imported": "prefect.server.api.server" in sys.modules}))
"""


@pytest.fixture(scope="module")
def prefect_home(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A Prefect home of this module's own, apart from the session's: the first server started on it creates its
    database (~25 s of migrations under load on 2 cores), the module's later servers reuse it."""
    return tmp_path_factory.mktemp("prestart") / "prefect-home"


def test_a_flow_runs_against_the_prestarted_server_and_the_process_never_imports_the_server_module(
        prefect_home: Path) -> None:
    res = subprocess.run([sys.executable, "-c", _SCRIPT], cwd=REPO, env=_env(prefect_home), capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    out = json.loads(res.stdout.strip().splitlines()[-1])
    assert out["value"] == 42
    assert out["url"] and out["url"].startswith("http://127.0.0.1:") and out["url"].endswith("/api")
    assert out["used"] == out["url"]
    assert out["server_module_imported"] is False  # Prefect's own temporary server was never started


_KILLED = """
import sys, time
from cache.runtime import _PRESTART, prestart_local_server, prestarted_api_url
prestart_local_server()
assert prestarted_api_url()
print(_PRESTART.process.pid, flush=True)
time.sleep(600)
"""


def _env(prefect_home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PREFECT_API_URL"}
    env.update(PREFECT_HOME=str(prefect_home), PYTHONPATH=str(REPO))
    return env


def test_the_server_exits_when_its_command_is_killed(prefect_home: Path) -> None:
    proc = subprocess.Popen([sys.executable, "-c", _KILLED], cwd=REPO, env=_env(prefect_home), stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    try:
        server_pid = int(proc.stdout.readline())
        # its output goes to a log, not to the command's stderr (a server stopped mid-request printed a traceback
        # after the command's own last line)
        assert os.readlink(f"/proc/{server_pid}/fd/2") == str(prefect_home / runtime.SERVER_LOG_NAME)
    finally:
        proc.kill()  # SIGKILL: no atexit hook runs
        proc.wait(timeout=30)
    deadline = time.time() + 20
    while time.time() < deadline and Path(f"/proc/{server_pid}").exists():
        time.sleep(0.2)
    gone = not Path(f"/proc/{server_pid}").exists()
    if not gone:
        os.kill(server_pid, signal.SIGKILL)
    assert gone, "the server outlived its command"


def test_a_command_that_exits_at_once_is_not_held_open_by_the_server(prefect_home: Path) -> None:
    # a server started (or starting) after the command's exit must not outlive it, nor hold a caller's pipe open (a
    # CI hang before the atexit close, when the server shared the command's stderr)
    for _ in range(3):
        t0 = time.time()
        res = subprocess.run([sys.executable, "-m", "flows.cli.main", "generate", "a sponge", "--quality", "ultra"],
                             cwd=REPO, env=_env(prefect_home), capture_output=True, text=True, timeout=120)
        assert res.returncode != 0 and res.stderr.startswith("error:") and time.time() - t0 < 60


def test_no_prestart_when_prefect_is_pointed_at_a_server(monkeypatch: pytest.MonkeyPatch) -> None:
    fresh = runtime._Prestart()
    monkeypatch.setattr(runtime, "_PRESTART", fresh)
    monkeypatch.setenv("PREFECT_API_URL", "http://127.0.0.1:1/api")
    runtime.prestart_local_server()
    assert fresh.thread is None and runtime.prestarted_api_url() is None


def test_only_flow_commands_prestart(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[int] = []
    monkeypatch.setattr(runtime, "prestart_local_server", lambda: calls.append(1))
    for argv in (["material", "--asset", "x"], ["batch", "r.jsonl"], ["eval", "--suite", "s"], ["probe", "drop"]):
        cli_main._prestart_for(argv)
    assert len(calls) == 4
    for argv in ([], ["inspect", "d"], ["schema", "--list"], ["cache", "stats"], ["generate", "--help"],
                 ["verify", "physics"], ["generate"]):  # generate: once it knows the layers will run (tasks.asset_cache)
        cli_main._prestart_for(argv)
    assert len(calls) == 4
    assert cli_main.PRESTART_IN_COMMAND <= cli_main.FLOW_COMMANDS


def test_a_server_that_does_not_come_up_leaves_flows_on_prefects_own(monkeypatch: pytest.MonkeyPatch) -> None:
    fresh = runtime._Prestart()
    monkeypatch.setattr(runtime, "_PRESTART", fresh)
    monkeypatch.delenv("PREFECT_API_URL", raising=False)

    def broken(port: int) -> subprocess.Popen:
        return subprocess.Popen([sys.executable, "-c", "import sys; sys.exit(1)"])

    monkeypatch.setattr(runtime, "_start_server_process", broken)
    runtime.prestart_local_server()
    assert runtime.prestarted_api_url() is None
    assert fresh.process is None


def test_a_local_server_shared_by_a_parent_is_not_the_users_server(monkeypatch: pytest.MonkeyPatch) -> None:
    from prefect.settings import PREFECT_API_URL, temporary_settings

    url = "http://127.0.0.1:9/api"
    monkeypatch.setenv(runtime.LOCAL_API_ENV, url)
    with temporary_settings({PREFECT_API_URL: url}):
        assert not runtime.uses_remote_server()  # flows run without heartbeats, as against their own server
    with temporary_settings({PREFECT_API_URL: "http://10.0.0.7:4200/api"}):
        assert runtime.uses_remote_server()


def test_batch_children_share_the_prestarted_server_marked_local(monkeypatch: pytest.MonkeyPatch) -> None:
    from flows.batch import prefect_api_for_children

    fresh = runtime._Prestart()
    fresh.thread, fresh.api_url = _done_thread(), "http://127.0.0.1:9/api"
    monkeypatch.setattr(runtime, "_PRESTART", fresh)
    monkeypatch.delenv(runtime.LOCAL_API_ENV, raising=False)
    from prefect.settings import PREFECT_API_URL, temporary_settings

    with temporary_settings(restore_defaults={PREFECT_API_URL}):  # no server configured (whatever the session set)
        with prefect_api_for_children() as env:
            assert env == {"PREFECT_API_URL": fresh.api_url, runtime.LOCAL_API_ENV: fresh.api_url}
    with temporary_settings({PREFECT_API_URL: "http://10.0.0.7:4200/api"}):  # a user's server: theirs, unmarked
        with prefect_api_for_children() as env:
            assert env == {"PREFECT_API_URL": "http://10.0.0.7:4200/api"}


def _done_thread():
    import threading

    t = threading.Thread(target=lambda: None)
    t.start()
    t.join()
    return t


def test_spawned_workers_see_the_shared_server_as_local() -> None:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    from flows.evaluate import _set_env

    url = "http://127.0.0.1:9/api"
    for env, remote in ((runtime.local_api_env(url), False), ({"PREFECT_API_URL": url}, True)):
        with ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"), initializer=_set_env,
                                 initargs=(env,)) as pool:
            assert pool.submit(runtime.uses_remote_server).result(timeout=120) is remote
