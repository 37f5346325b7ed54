"""Project-wide test setup: every test runs against temporary Prefect state and a temporary cache root.

Prefect reads its settings when imported, so the session-level environment is set here, before any test module
imports prefect. Per test, `DEFORMSMITH_CACHE` points at a fresh directory (the cache root is resolved at use).
Tests that run flows request the session-scoped `prefect_api` fixture (one temporary server per session); tests
that run a flow command as a subprocess pass it `cli_env` (the same server, so the command starts none of its own).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
_SESSION_DIR = Path(tempfile.mkdtemp(prefix="deformsmith-tests-"))
os.environ["PREFECT_HOME"] = str(_SESSION_DIR / "prefect-home")
os.environ["PREFECT_RESULTS_LOCAL_STORAGE_PATH"] = str(_SESSION_DIR / "prefect-results")
os.environ["DEFORMSMITH_CACHE"] = str(_SESSION_DIR / "cache")
os.environ["PREFECT_SERVER_ANALYTICS_ENABLED"] = "false"
os.environ["PREFECT_LOGGING_TO_API_WHEN_MISSING_FLOW"] = "ignore"
os.environ.pop("PREFECT_API_URL", None)  # never talk to a developer's own server from tests
os.environ.pop("PREFECT_PROFILES_PATH", None)
(_SESSION_DIR / "prefect-home").mkdir(parents=True, exist_ok=True)
# An image that sets PYTHONDONTWRITEBYTECODE makes every command a test starts (and each xdist worker) compile the
# project's modules again, ~1 s a process; their bytecode goes to the checkout's git-ignored __pycache__ folders.
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
sys.dont_write_bytecode = False


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """Remove the session's temporary Prefect home and caches."""
    shutil.rmtree(_SESSION_DIR, ignore_errors=True)


@pytest.fixture(autouse=True)
def _isolated_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh cache root per test (exported in DEFORMSMITH_CACHE)."""
    root = tmp_path / "cache"
    monkeypatch.setenv("DEFORMSMITH_CACHE", str(root))
    return root


@pytest.fixture
def cache_dir(_isolated_cache: Path) -> Path:
    """This test's cache root."""
    return _isolated_cache


@pytest.fixture(scope="session")
def prefect_api() -> Iterator[str]:
    """One temporary Prefect server + database for the session, heartbeats off; yields its API URL.

    Subprocesses get the URL in PREFECT_API_URL so they skip starting servers of their own.
    """
    from prefect.settings import PREFECT_API_URL, PREFECT_FLOWS_HEARTBEAT_FREQUENCY, temporary_settings
    from prefect.testing.utilities import prefect_test_harness

    with prefect_test_harness(server_startup_timeout=120):
        with temporary_settings({PREFECT_FLOWS_HEARTBEAT_FREQUENCY: None}):
            yield str(PREFECT_API_URL.value())


@pytest.fixture
def cli_env(prefect_api: str) -> dict[str, str]:
    """Environment for a `python -m flows.cli.main` subprocess: this process's environment (the session's Prefect
    home, this test's cache root), the repository on PYTHONPATH, and the session's Prefect server as a local server
    DeformSmith started (cache.runtime.local_api_env, as a batch hands its own to its workers). The command then
    starts no server of its own: under load on 2 cores that start is ~25 s of CPU beside the command, ~50 s with a
    new database, paid by every command. Tests of that start itself (tests/test_cache/test_prestart.py, the stop
    signals in tests/generate/test_unix_manners.py) run the command without it."""
    from cache.runtime import local_api_env

    return {**os.environ, "PYTHONPATH": str(REPO), **local_api_env(prefect_api)}


# The phrase sweeps of L0's tests (the class-regression files, one per blind or development set, the lexicon batches,
# the audits, the redraws, the grammar's and the goods' phrase tables) grow with every session. The default run keeps every test
# with the first, twenty-fifth, forty-ninth ... of its phrases; the others run with `-m slow` (the whole sweep). Files whose cases
# are distinct behaviours (bad inputs, backends, units, the phrase table) run whole; the photo, input and lexicon
# files choose their own fixed samples.
_SWEEP_FILES = re.compile(r"tests/geometry/test_(?:(?:dev|sealed)\d+\w*_classes|lexicon_s\d+\w*|audit\d+\w*|"
                          r"mass_classes|pouch_classes|goods|grammar|details_poses|material_dims|stable_pose|bend|seat|"
                          r"dev38_reading|redraw\d+\w*|levers\d+|crumple\d+|sleeved_goods\d+|mesh_sacks\d+|snacks\d+|"
                          r"(?:dev|sealed)\d+_(?:reading|lexicon|redraw\d+|[a-z]+)|packs\d+|cov\d+_c\d+|dev\d+_d\d+|folded_look\d+)\.py$")


SWEEP_SAMPLE = 48  # the default run keeps one phrase in this many of each sweep test (one in three until session 40,
# when CI's 15 minutes on 2 cores had ~35 s to spare; one in eight until session 41, when it had 41 s; one in twelve
# until session 42, when it had 37 s; one in 24 until session 52, when CI took 1,235 s)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark all but one phrase in SWEEP_SAMPLE of a sweep file's parametrized tests slow (deterministic: collection
    order)."""
    seen: dict[tuple[str, str], int] = {}
    for item in items:
        path = item.nodeid.split("::", 1)[0]
        if not _SWEEP_FILES.search(path) or not hasattr(item, "callspec"):
            continue
        key = (path, getattr(item, "originalname", item.name))
        k = seen.get(key, 0)
        seen[key] = k + 1
        if k % SWEEP_SAMPLE != 0:
            item.add_marker(pytest.mark.slow)
