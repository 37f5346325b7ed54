"""`deformsmith cache stats|verify|gc`: figures, JSON, and one clear line on bad input."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cache import CacheStore, content_key
from flows.cli import cache_cmds  # noqa: F401  (registers the commands)
from flows.cli.apps import app
from tasks.report.units import parse_duration, parse_size

REPO = Path(__file__).resolve().parents[2]


def _invoke(*args: str) -> tuple[int, str, str]:
    res = CliRunner().invoke(app, list(args))
    return res.exit_code, res.stdout, res.stderr


@pytest.fixture
def filled(tmp_path: Path) -> CacheStore:
    store = CacheStore(tmp_path / "filled")
    for i in range(3):
        store.put(content_key("cli", i), {"a": np.full(50_000, i + 1, dtype=np.float64)})
    return store


def test_stats_json(filled: CacheStore) -> None:
    code, out, _ = _invoke("cache", "stats", "--cache", str(filled.root), "--json")
    data = json.loads(out)
    assert code == 0 and data["entries"] == 3 and data["bytes"] >= 3 * 400_000 and data["root"] == str(filled.root)


def test_stats_uses_env_root(filled: CacheStore, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DEFORMSMITH_CACHE", str(filled.root))
    code, out, _ = _invoke("cache", "stats", "--json")
    assert code == 0 and json.loads(out)["entries"] == 3


def test_verify_clean_and_json(filled: CacheStore) -> None:
    code, out, _ = _invoke("cache", "verify", "--cache", str(filled.root), "--json")
    assert code == 0 and json.loads(out) == {"root": str(filled.root), "checked": 3, "removed": False, "corrupt": []}


def test_verify_remove_corrupt(filled: CacheStore) -> None:
    key = filled.keys()[0]
    (filled.entry_dir(key) / "zarr.json").write_text("{not json")
    code, out, _ = _invoke("cache", "verify", "--cache", str(filled.root), "--json", "--remove")
    assert code == 1 and json.loads(out)["corrupt"][0]["key"] == key
    assert key not in filled.keys() and _invoke("cache", "verify", "--cache", str(filled.root))[0] == 0


def test_gc_by_size_and_age(filled: CacheStore) -> None:
    old = time.time() - 10 * 86400
    os.utime(filled.entry_dir(filled.keys()[0]), (old, old))
    code, out, _ = _invoke("cache", "gc", "--cache", str(filled.root), "--older-than", "7d", "--json")
    assert code == 0 and len(json.loads(out)["removed"]) == 1
    code, out, _ = _invoke("cache", "gc", "--cache", str(filled.root), "--max-size", "0", "--json")
    assert code == 0 and json.loads(out)["remaining_entries"] == 0 and filled.keys() == []


@pytest.mark.parametrize("args", [
    ["cache", "verify", "--cache", "/nonexistent/deformsmith-cache"],
    ["cache", "stats", "--cache", "/nonexistent/deformsmith-cache"],
    ["cache", "gc", "--cache", "/nonexistent/deformsmith-cache", "--older-than", "1d"],
    ["cache", "gc", "--older-than", "soon"],
    ["cache", "gc", "--max-size", "-5GB"],
])
def test_bad_input_one_line_nonzero(args: list[str]) -> None:
    code, out, err = _invoke(*args)
    assert code != 0 and out == ""
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: ")


def test_not_a_cache_dir_is_refused(tmp_path: Path) -> None:
    (tmp_path / "precious.txt").write_text("keep me")
    code, _, err = _invoke("cache", "gc", "--cache", str(tmp_path), "--max-size", "0")
    assert code != 0 and "not a DeformSmith cache" in err and (tmp_path / "precious.txt").exists()


def test_parsers() -> None:
    assert parse_duration("90") == 90 and parse_duration("30m") == 1800 and parse_duration("7d") == 7 * 86400
    assert parse_size("1000") == 1000 and parse_size("2KB") == 2048 and parse_size("1.5GiB") == int(1.5 * 2**30)


def test_console_script_bad_root_exit_code(tmp_path: Path) -> None:
    res = subprocess.run([sys.executable, "-m", "flows.cli.main", "cache", "verify", "--cache", str(tmp_path / "no")],
                         cwd=REPO, capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(REPO)))
    assert res.returncode != 0 and res.stderr.strip().count("\n") == 0 and "does not exist" in res.stderr
