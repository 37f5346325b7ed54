"""The real layer reruns (#27): `deformsmith physical DIR` and `deformsmith material DIR` SIGKILL'd as soon as they
start writing, or failing at their very last write (a full disk), leave the asset directory byte-identical, and
`deformsmith evidence` still agrees with physical.json / material.json. Slow: one asset is built through the CLI
(geometry, physical, material: a few minutes on 2 cores), then each rerun hits the cache.
`pytest -m slow tests/hardening/test_layer_publish_real.py`
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest
from test_layer_publish import partials, tree_digest

REPO = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.slow


def _env(cache: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(REPO), "DEFORMSMITH_CACHE": str(cache)}


def _cli(cache: Path, *args: str, check: bool = True, timeout_s: float = 900) -> subprocess.CompletedProcess[str]:
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=timeout_s, env=_env(cache))
    if check:
        assert proc.returncode == 0, proc.stderr[-3000:]
    return proc


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A kitchen sponge through L0, L1 and L2 (layer by layer), and the cache that holds its probes."""
    root = tmp_path_factory.mktemp("layers")
    asset, cache = root / "sponge", root / "cache"
    _cli(cache, "geometry", "a kitchen sponge 10 x 7 x 3 cm", "--out", str(asset))
    _cli(cache, "physical", str(asset))
    _cli(cache, "material", str(asset))
    return asset, cache


@pytest.fixture
def asset(built: tuple[Path, Path], tmp_path: Path) -> tuple[Path, Path]:
    """A private copy of the built asset (the cache is shared: every rerun below is a hit)."""
    dest = tmp_path / "assets" / "sponge"
    shutil.copytree(built[0], dest, symlinks=True)
    return dest, built[1]


def evidence_agrees(asset: Path, cache: Path) -> None:
    """`deformsmith evidence` reads every stage's lines, as many as physical.json and material.json count."""
    rows = json.loads(_cli(cache, "evidence", str(asset), "--json").stdout)
    per_stage = Counter(r["stage"] for r in rows)
    physical = json.loads((asset / "physical.json").read_text())
    material = json.loads((asset / "material.json").read_text())
    assert per_stage["L1"] == physical["attempts"] >= 1, per_stage
    assert per_stage["L2"] == material["selection"]["attempts"] >= 1, per_stage
    l2_lines = (asset / "evidence" / "L2_attempts.jsonl").read_text().splitlines()
    assert len(l2_lines) == per_stage["L2"]
    for stage, doc in (("L1", physical), ("L2", material)):
        verdicts = {r["verdict"] for r in rows if r["stage"] == stage}
        assert doc["passed"] == bool(verdicts & {"accepted", "best_so_far"}), (stage, verdicts)


def _first_write(asset: Path, since: float) -> bool:
    """True once the rerun has written evidence (in the asset itself, or in its working copy beside it)."""
    for folder in [asset, *[asset.parent / n for n in partials(asset.parent)]]:
        try:
            if any(p.stat().st_mtime >= since for p in (folder / "evidence").iterdir()):
                return True
        except OSError:
            continue
    return False


@pytest.mark.parametrize("command", ["physical", "material"])
def test_a_sigkilled_layer_rerun_leaves_the_asset_and_its_evidence(command: str, asset: tuple[Path, Path]) -> None:
    path, cache = asset
    before = tree_digest(path)
    since = time.time() - 0.01
    proc = subprocess.Popen([sys.executable, "-m", "flows.cli.main", command, str(path)], cwd=REPO,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=_env(cache))
    deadline = time.monotonic() + 600
    while proc.poll() is None and not _first_write(path, since) and time.monotonic() < deadline:
        time.sleep(0.002)
    assert proc.poll() is None, "the rerun ended before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=60)
    assert tree_digest(path) == before
    evidence_agrees(path, cache)
    _cli(cache, command, str(path))  # the next rerun cleans the dead one's working copy and publishes the same
    assert partials(path.parent) == []
    evidence_agrees(path, cache)


_FULL_AT_THE_LAST_WRITE = """
import errno, sys
from tasks.asset_dir import AssetDir

def full(self, record):
    raise OSError(errno.ENOSPC, "No space left on device", str(self.file("{doc}")))

AssetDir.write_{doc} = full
from flows.cli.main import main
sys.argv = ["deformsmith", "{command}", sys.argv[1]]
main()
"""


@pytest.mark.parametrize("command, doc", [("physical", "physical"), ("material", "material")])
def test_a_layer_rerun_failing_at_its_last_write_leaves_the_asset(command: str, doc: str,
                                                                  asset: tuple[Path, Path]) -> None:
    path, cache = asset
    before = tree_digest(path)
    proc = subprocess.run([sys.executable, "-c", _FULL_AT_THE_LAST_WRITE.format(doc=doc, command=command), str(path)],
                          cwd=REPO, capture_output=True, text=True, timeout=900, env=_env(cache))
    assert proc.returncode == 2, proc.stderr[-3000:]
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert lines[-1] == f"error: cannot use {path / (doc + '.json')}: no space left on the device", proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr
    assert tree_digest(path) == before
    assert partials(path.parent) == []
    evidence_agrees(path, cache)


def _mount_tmpfs(where: Path, size: str) -> None:
    where.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)], capture_output=True)
    if proc.returncode != 0:
        pytest.skip("cannot mount a tmpfs here (needs root)")


def _one_error_line(proc: subprocess.CompletedProcess[str]) -> str:
    assert proc.returncode == 2, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    errors = [ln for ln in lines if ln.startswith("error: ")]  # (Prefect's one-line 'Task run ... Failed' may precede)
    assert len(errors) == 1 and lines[-1] == errors[0], proc.stderr[-3000:]
    return errors[0]


@pytest.mark.parametrize("command", ["physical", "material", "manipulate"])
def test_a_rerun_on_a_read_only_asset_is_one_error_line(command: str, built: tuple[Path, Path],
                                                         tmp_path: Path) -> None:
    holder = tmp_path / "ro"
    _mount_tmpfs(holder, "256m")
    try:
        shutil.copytree(built[0], holder / "sponge", symlinks=True)
        subprocess.run(["mount", "-o", "remount,ro", str(holder)], check=True)
        before = tree_digest(holder / "sponge")
        line = _one_error_line(_cli(built[1], command, str(holder / "sponge"), check=False))
        assert line == f"error: asset directory: cannot use {holder / 'sponge'}: read-only file system"
        assert tree_digest(holder / "sponge") == before
    finally:
        subprocess.run(["umount", "-l", str(holder)], capture_output=True)


@pytest.mark.parametrize("command", ["physical", "material"])
def test_a_rerun_with_its_cache_under_proc_is_one_error_line(command: str, asset: tuple[Path, Path]) -> None:
    path, _ = asset
    before = tree_digest(path)
    line = _one_error_line(_cli(Path("/proc/deformsmith-test/cache"), command, str(path), check=False))
    assert line.startswith("error: cache root: cannot use /proc/deformsmith-test/cache")
    assert tree_digest(path) == before


def test_a_full_disk_under_the_cache_recordings_is_one_error_line(asset: tuple[Path, Path], tmp_path: Path) -> None:
    """L1's probes run (a fresh cache) and the recording of the first one meets a full disk: one `error:` line naming
    the .rrd, no .rrd or temporary left, no stored probe result without its recording, the asset as it was."""
    from cache import CacheStore

    path, _ = asset
    cache = tmp_path / "fresh-cache"
    _mount_tmpfs(cache / "recordings", "64k")
    try:
        before = tree_digest(path)
        line = _one_error_line(_cli(cache, "physical", str(path), check=False, timeout_s=180))  # (it used to hang)
        assert line.startswith(f"error: cannot use {cache / 'recordings'}/L1_") and line.endswith(
            ".rrd: no space left on the device"), line
        assert list((cache / "recordings").iterdir()) == []
        assert tree_digest(path) == before and partials(path.parent) == []
        if any((cache / "entries").glob("*")):  # what was stored is intact and names no missing recording
            store = CacheStore(cache)
            assert store.verify() == []
            for key in store.keys():
                recording = getattr(store.get(key), "recording", None)
                assert recording is None or (cache / recording).is_file(), recording
    finally:
        subprocess.run(["umount", "-l", str(cache / "recordings")], capture_output=True)
