"""Cached tasks that return files: the scratch folder they are written to goes away once the files are stored, and
the caller gets the stored copies on a miss as on a hit (the drop-protocol videos used to leave a folder per run)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest

from cache import CacheStore, cache_root, cached_task, scratch_dir


@pytest.fixture
def private_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """tempfile's folder for this test only, so leftovers can be counted."""
    d = tmp_path / "tmp"
    d.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(d))
    return d


def _inside(path: Path, root: Path) -> bool:
    return root.resolve() in path.resolve().parents


def test_file_outputs_come_back_from_the_store_and_scratch_is_removed(prefect_api: str, private_tmp: Path) -> None:
    runs: list[int] = []

    @cached_task(version="1", name="test.write_files")
    def write_files(n: int) -> dict[str, Path]:
        runs.append(n)
        folder = scratch_dir(prefix="ds-test-scratch-")
        out = {}
        for name in ("a", "b"):
            out[name] = folder / f"{name}.txt"
            out[name].write_text(f"{name}{n}")
        return out

    first = write_files(3)  # miss
    assert sorted(p.name for p in private_tmp.iterdir()) == []
    assert all(_inside(p, cache_root()) for p in first.values())
    assert {k: p.read_text() for k, p in first.items()} == {"a": "a3", "b": "b3"}

    second = write_files(3)  # hit: the same stored files
    assert runs == [3]
    assert second == first
    assert CacheStore(cache_root()).verify() == []


def test_paths_outside_scratch_are_returned_untouched(prefect_api: str, tmp_path: Path) -> None:
    keep = tmp_path / "mine.txt"
    keep.write_text("x")

    @cached_task(version="1", name="test.return_own_file")
    def own(tag: str) -> Path:
        return keep

    got = own("t")
    assert got == keep and keep.is_file()  # a caller's own file is never moved or deleted


def test_drop_videos_leave_no_temp_folder(prefect_api: str, private_tmp: Path) -> None:
    from flows.renders import drop_videos_task

    rng = np.random.default_rng(0)
    rest = rng.random((20, 3)) * 0.03
    x = np.stack([rest, rest + [0.0, 0.0, -0.002]])
    F = np.tile(np.eye(3), (2, 20, 1, 1))
    idx = rng.integers(0, 20, (30, 4))
    gaussians = {"positions_m": rest[idx[:, 0]], "colors": rng.random((30, 3)), "particle_index": idx,
                 "particle_weight": np.full((30, 4), 0.25)}
    cov = np.tile(np.eye(3) * 1e-6, (30, 1, 1))
    videos = drop_videos_task(gaussians, cov, rest, x, F, "", 128, 72)  # (renderer code, a small frame)
    assert list(private_tmp.glob("ds-drop-video-*")) == []
    assert all(_inside(p, cache_root()) and p.stat().st_size > 0 for p in videos.values())
    assert drop_videos_task(gaussians, cov, rest, x, F, "", 128, 72) == videos  # a hit returns the same stored files
