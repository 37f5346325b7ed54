"""Temporaries of dead processes (SIGKILL, Ctrl-C, full disk) are removed by `cache gc` and by the next run; those of
live processes, of other hosts, and finished files are kept."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from cache.store import CacheStore
from cache.tempfiles import dead_cache_temporaries, pid_alive
from tasks import preflight

REPO = Path(__file__).resolve().parents[2]


def dead_pid() -> int:
    """The id of a process that has exited (and been reaped)."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    assert not pid_alive(proc.pid)
    return proc.pid


def _old(path: Path, age_s: float = 3600.0) -> Path:
    t = time.time() - age_s
    os.utime(path, (t, t))
    return path


def _leftovers(root: Path, outputs: Path) -> tuple[list[Path], list[Path]]:
    """(what must go, what must stay) in a cache root and an outputs folder."""
    dead, me, host = dead_pid(), os.getpid(), socket.gethostname()
    CacheStore(root).put("ab" * 32, {"x": 1.0})  # a real cache with one entry
    rec = root / "recordings"
    rec.mkdir(parents=True)
    key = "cd" * 32
    fresh = rec / f"L1_drop-89ab.rrd.{dead}.tmp"  # fresh: it could be another host's live writer
    go = [rec / f"L1_drop-0123.rrd.{dead}.tmp", rec / f"L2_compress-4567.rrd.{dead}.tmp"]
    stay = [fresh, rec / f"L1_lift-cdef.rrd.{me}.tmp", rec / "L1_drop-0123.rrd"]
    for p in go + stay:
        p.write_bytes(b"x" * 1000)
        if p != fresh:
            _old(p)
    entry_tmp = root / "tmp" / f"{key}.{dead}.0badc0de"
    (entry_tmp / "a0").mkdir(parents=True)
    (entry_tmp / "a0" / "c").write_bytes(b"y" * 500)
    _old(entry_tmp)
    go.append(entry_tmp)
    outputs.mkdir()
    for name, kept in ((f".duck.partial-{host}~{dead}~k2j3", False), (f".duck.partial-{host}~{me}~a1b2", True),
                       (f".duck.partial-elsewhere~{dead}~zz", True), ("duck", True)):
        (outputs / name).mkdir()
        (outputs / name / "geometry.json").write_text("{}")
        (stay if kept else go).append(outputs / name)
    return go, stay


def test_cache_gc_removes_what_dead_processes_left(tmp_path: Path) -> None:
    root, outputs = tmp_path / "cache", tmp_path / "assets"
    go, stay = _leftovers(root, outputs)
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "cache", "gc", "--cache", str(root), "--outputs",
                           str(outputs), "--json"], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout)
    assert sorted(result["dead_temporaries_removed"]) == sorted(str(p) for p in go)
    assert result["dead_temporaries_bytes"] >= 2500
    assert not any(p.exists() for p in go)
    assert all(p.exists() for p in stay)
    assert CacheStore(root).get("ab" * 32) == {"x": 1.0}  # the entry itself is untouched


def test_the_next_run_removes_the_cache_temporaries(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    root, outputs = tmp_path / "cache", tmp_path / "assets"
    go, stay = _leftovers(root, outputs)
    monkeypatch.setenv("DEFORMSMITH_CACHE", str(root))
    assert set(dead_cache_temporaries(root)) == {p for p in go if p.parent.name != "assets"}
    preflight.check_locations(outputs / "duck", cache=True)  # what every run does before its first layer
    assert not any(p.exists() for p in go if p.parent.name != "assets")
    assert all(p.exists() for p in stay)


def test_gc_refuses_a_folder_that_is_not_a_cache(tmp_path: Path) -> None:
    victim = tmp_path / "not_a_cache"
    (victim / "recordings").mkdir(parents=True)
    keep = victim / "recordings" / f"x.rrd.{dead_pid()}.tmp"
    keep.write_bytes(b"x")
    _old(keep)
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "cache", "gc", "--cache", str(victim)], cwd=REPO,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0 and "not a DeformSmith cache" in proc.stderr
    assert keep.exists()


def test_l0_and_publish_working_dirs_name_their_owner_and_a_dead_ones_go(tmp_path: Path) -> None:
    """L0's `.NAME.tmp-*` and publish's `.NAME.old-*` carry host and pid; the next L0 publish of NAME removes the
    dead ones of NAME (and only those), a live owner's and another name's stay."""
    from cache.tempfiles import dead_partials, owner_tag
    from tasks.geometry.outputs import publish_dir

    host = socket.gethostname()
    dead_tmp = tmp_path / f".geo.tmp-{host}~{dead_pid()}~abc"
    dead_old = tmp_path / f".geo.old-{host}~{dead_pid()}~def"
    live = tmp_path / f".geo.tmp-{owner_tag()}ghi"
    other = tmp_path / f".other.tmp-{host}~{dead_pid()}~jkl"
    for d in (dead_tmp, dead_old, live, other):
        d.mkdir()
    assert dead_partials(tmp_path, "geo") == sorted([dead_old, dead_tmp])

    def build(tmp: Path) -> None:
        assert tmp.name.startswith(f".geo.tmp-{owner_tag()}")
        (tmp / "geometry.json").write_text("{}", encoding="utf-8")

    publish_dir(build, tmp_path / "geo")
    assert not dead_tmp.exists() and not dead_old.exists() and live.exists() and other.exists()
    assert (tmp_path / "geo" / "geometry.json").is_file()
