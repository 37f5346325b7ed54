"""generate: bad input leaves nothing; a killed run resumes from the cache and yields the same asset."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tasks.record.fingerprint import content_fingerprint
from tests.cli_in_process import cli_run

REPO = Path(__file__).resolve().parents[2]
# The default asset is also the cheapest to simulate at draft: draft fixes ~20 cells along the longest extent, so a
# large flat object gets a coarse grid (large dt, ~1k particles) while a small cube gets a fine one.
SMALL = "a soft plush turtle toy, about 25 cm long"


def _generate(out: Path, cache: Path, *args: str, wait: bool = True,
              env: dict[str, str] | None = None) -> subprocess.Popen[str] | subprocess.CompletedProcess[str]:
    """`deformsmith generate ARGS --out OUT --cache CACHE`; env: the command's environment (conftest's `cli_env`: the
    session's Prefect server), else this process's (the command starts its own server)."""
    cmd = [sys.executable, "-m", "flows.cli.main", "generate", *args, "--out", str(out), "--cache", str(cache)]
    env = env or dict(os.environ, PYTHONPATH=str(REPO))
    if wait:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=1800, env=env, cwd=REPO)
    return subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env, cwd=REPO)


@pytest.mark.parametrize("args, message", [
    (["--image", "/nonexistent/photo.png"], "image file not found"),
    (["--mesh", "/nonexistent/m.obj"], "mesh file not found"),
    (["a sponge", "--quality", "ultra"], "--quality must be"),
    (["a sponge", "--device", "tpu"], "--device must be"),
    (["a sponge", "--cpu-threads", "0"], "--cpu-threads must be"),
    (["a steel ball"], "'steel' is a rigid material"),
    (["a sponge", "--require-l3", "--no-l3"], "--require-l3 needs L3"),
])
def test_bad_input_is_one_line_and_leaves_nothing(tmp_path: Path, args: list[str], message: str,
                                                  cli_env: dict[str, str]) -> None:
    out = _generate(tmp_path / "asset", tmp_path / "cache", *args, env=cli_env)
    assert out.returncode != 0
    assert out.stderr.startswith("error:") and message in out.stderr and out.stderr.count("\n") == 1
    assert not (tmp_path / "asset").exists()


def test_unusable_file_found_inside_a_flow_ends_in_its_error_line(tmp_path: Path, cli_env: dict[str, str]) -> None:
    """A mesh file that exists but holds no triangles fails in L0's first task: the user gets its one-line error last,
    no Prefect tracebacks, no failure stored in the cache, nothing published."""
    empty = tmp_path / "empty.obj"
    empty.write_text("# no faces\n")
    out = _generate(tmp_path / "asset", tmp_path / "cache", "--mesh", str(empty), "--no-l3", env=cli_env)
    assert out.returncode == 2, out.stderr[-2000:]
    assert out.stderr.rstrip().splitlines()[-1] == "error: empty.obj holds no triangles"
    for noise in ("Traceback", "Failed to write result", "Still processing items"):
        assert noise not in out.stderr
    assert not (tmp_path / "asset").exists()
    assert not list((tmp_path / "cache").glob("entries/*"))


def test_cuda_without_a_gpu_is_refused_before_any_layer(tmp_path: Path, cli_env: dict[str, str]) -> None:
    import tasks.mpm  # noqa: F401
    import warp as wp

    if wp.is_cuda_available():
        pytest.skip("this machine has a CUDA device")
    out = _generate(tmp_path / "asset", tmp_path / "cache", "a sponge", "--device", "cuda", env=cli_env)
    assert out.returncode == 2
    assert out.stderr.rstrip().splitlines()[-1].startswith("error: --device cuda: no CUDA device is available")
    assert "L0" not in out.stderr and not (tmp_path / "asset").exists()


def test_ctrl_c_stops_at_once_says_so_and_publishes_nothing(tmp_path: Path, tmp_path_factory: pytest.TempPathFactory,
                                                           cli_env: dict[str, str]) -> None:
    """SIGINT once L0 has run (its result is in the cache): exit 130 within seconds, a last line telling the user that
    a rerun resumes, no asset and no partial directory; the progress log holds our lines, not Prefect's INFO
    records. (A sponge-sized box mesh: L0's first task is a mesh import, not a text's design. Against the session's
    server; a stop signal to a command with its own server, the process group's as a terminal sends it:
    tests/generate/test_unix_manners.py.)"""
    import trimesh

    sponge = tmp_path_factory.mktemp("mesh") / "sponge.obj"  # (outside tmp_path: it must hold the cache alone)
    trimesh.creation.box(extents=(0.10, 0.07, 0.03)).export(sponge)
    cache = tmp_path / "cache"
    cmd = [sys.executable, "-m", "flows.cli.main", "generate", "--mesh", str(sponge), "--no-l3",
           "--out", str(tmp_path / "asset"), "--cache", str(cache)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=REPO,
                            env=cli_env, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    events = cache / "events.jsonl"
    deadline = time.time() + 300
    while not (events.exists() and '"task": "l0.' in events.read_text()):
        assert proc.poll() is None and time.time() < deadline, "generate ended before it could be interrupted"
        time.sleep(0.2)
    t0 = time.time()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and time.time() - t0 < 60
    assert err.rstrip().splitlines()[-1].startswith("interrupted; finished tasks are cached")
    assert "L0" in err and "Running hook" not in err and "Beginning flow run" not in err  # no Prefect INFO records
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache"]  # no asset, no partial working directory


def test_out_dir_that_is_not_an_asset_is_refused(tmp_path: Path, cli_env: dict[str, str]) -> None:
    (tmp_path / "asset").mkdir()
    (tmp_path / "asset" / "notes.txt").write_text("mine")
    out = _generate(tmp_path / "asset", tmp_path / "cache", SMALL, env=cli_env)
    assert out.returncode != 0 and "not an asset directory" in out.stderr
    assert sorted(p.name for p in (tmp_path / "asset").iterdir()) == ["notes.txt"]


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_killed_generate_resumes_and_yields_the_same_asset(tmp_path: Path) -> None:
    reference = _generate(tmp_path / "reference", tmp_path / "cache_ref", SMALL)
    assert reference.returncode == 0, reference.stderr[-2000:]

    cache = tmp_path / "cache"
    proc = _generate(tmp_path / "asset", cache, SMALL, wait=False)
    deadline = time.time() + 1200
    events = cache / "events.jsonl"
    while time.time() < deadline:  # kill once L2 has started executing probes
        if events.exists() and '"task": "l2.' in events.read_text():
            break
        assert proc.poll() is None, "generate finished before it could be killed"
        time.sleep(0.5)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=60)
    assert not (tmp_path / "asset").exists()  # nothing that looks complete

    resumed = _generate(tmp_path / "asset", cache, SMALL)
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    import json
    from collections import Counter

    log = [json.loads(ln) for ln in events.read_text().splitlines()]
    executions = Counter(e["key"] for e in log if e["outcome"] == "miss")
    assert executions and max(executions.values()) == 1, "a finished task executed again after the kill"
    assert any(e["outcome"] == "hit" for e in log), "the rerun found nothing finished in the cache"
    assert content_fingerprint(tmp_path / "asset") == content_fingerprint(tmp_path / "reference")
    assert not [p for p in tmp_path.iterdir() if ".partial-" in p.name]


def test_view_names_the_recordings_and_fails_clearly_without_a_display(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """(In this process, tests/cli_in_process.py: `view` and `inspect` run no flows.)"""
    (tmp_path / "recordings").mkdir()
    for name in ("L1_place.rrd", "L2_drop.rrd"):
        (tmp_path / "recordings" / name).write_bytes(b"")
    code, out, _ = cli_run("view", str(tmp_path), "--dry-run", api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 0 and "L1_place.rrd" in out and "L2_drop.rrd" in out
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    code, _, err = cli_run("view", str(tmp_path), api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code != 0 and err.startswith("error:")
    code, _, err = cli_run("view", str(tmp_path / "nothing"), api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code != 0 and "no recordings" in err


def test_inspect_a_non_asset_is_one_clear_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = cli_run("inspect", str(tmp_path), api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code != 0 and err.startswith("error:") and "asset.json" in err


def test_stale_working_directories_of_dead_processes_are_removed(tmp_path: Path) -> None:
    import socket

    from tasks.publish import remove_stale_partials

    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    host = socket.gethostname()
    stale = tmp_path / f".asset.partial-{host}~{int(dead.stdout)}~abc"
    mine = tmp_path / f".asset.partial-{host}~{os.getpid()}~def"
    other_host = tmp_path / f".asset.partial-elsewhere~{int(dead.stdout)}~ghi"
    for d in (stale, mine, other_host):
        d.mkdir()
    assert remove_stale_partials(tmp_path / "asset") == [stale]
    assert mine.exists() and other_host.exists() and not stale.exists()


def test_prefect_log_level_is_ours_unless_the_user_set_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """Commands quiet Prefect's INFO records, but a PREFECT_LOGGING_LEVEL the user set is kept."""
    from flows.cli import apps

    monkeypatch.setattr(apps, "_USER_PREFECT_LEVEL", False)
    monkeypatch.setenv("PREFECT_LOGGING_LEVEL", "WARNING")
    apps.prefect_log_level("CRITICAL")
    assert os.environ["PREFECT_LOGGING_LEVEL"] == "CRITICAL"
    monkeypatch.setattr(apps, "_USER_PREFECT_LEVEL", True)
    monkeypatch.setenv("PREFECT_LOGGING_LEVEL", "INFO")
    apps.prefect_log_level("CRITICAL")
    assert os.environ["PREFECT_LOGGING_LEVEL"] == "INFO"


def test_view_also_opens_the_probe_recordings_the_records_name_in_the_cache(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """A default asset leaves its L1 and L2 probe recordings in the cache (#38 item 5): `view` opens them from there
    beside the asset's own, and names those the cache no longer holds."""
    import json

    asset, cache = tmp_path / "asset", tmp_path / "cache"
    (asset / "recordings").mkdir(parents=True)
    (asset / "recordings" / "L3_pick_and_place.rrd").write_bytes(b"")
    (cache / "recordings").mkdir(parents=True)
    (cache / "recordings" / "L2_drop-0123456789abcdef.rrd").write_bytes(b"")
    (asset / "material.json").write_text(json.dumps({"cached_recordings": {
        "recordings/L2_drop.rrd": "recordings/L2_drop-0123456789abcdef.rrd",
        "recordings/L2_lift.rrd": "recordings/L2_lift-fedcba9876543210.rrd"}}))
    monkeypatch.setenv("DEFORMSMITH_CACHE", str(cache))
    code, out, err = cli_run("view", str(asset), "--dry-run", api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 0, err
    assert "L3_pick_and_place.rrd" in out and str(cache / "recordings" / "L2_drop-0123456789abcdef.rrd") in out
    assert "L2_lift" not in out and "recordings/L2_lift.rrd: not in the asset" in err
