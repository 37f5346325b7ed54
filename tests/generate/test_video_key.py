"""The pick-and-place video's cache key (tasks.manipulation.pick_place_video): made of the recorded attempt's bytes
and the renderer's sources, every one of which exists; a record that shows no recorded trial leaves no video."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import cast

from contracts.manipulation import ManipulationRecord
from tasks.manipulation.pick_place_video import (
    ROOT, pick_and_place_video_key, renderer_sources, write_pick_and_place_video,
)


def test_the_key_follows_the_attempt_and_names_existing_sources(tmp_path: Path) -> None:
    sources = renderer_sources()
    assert all(p.exists() for p in sources) and ROOT / "tasks" / "manipulation" / "replay.py" in sources
    assert Path(__file__).resolve().parents[2] == ROOT
    data = tmp_path / "interaction" / "attempt_002"
    data.mkdir(parents=True)
    (data / "x").write_bytes(b"\x00")
    key = pick_and_place_video_key(tmp_path, 2)
    assert pick_and_place_video_key(tmp_path, 2) == key
    (data / "x").write_bytes(b"\x01")
    assert pick_and_place_video_key(tmp_path, 2) != key


def test_no_recorded_trial_no_video(tmp_path: Path) -> None:
    stale = tmp_path / "renders" / "pick_and_place.mp4"
    stale.parent.mkdir()
    stale.write_bytes(b"old")
    record = cast(ManipulationRecord, SimpleNamespace(passed=False, attempt=None, best_attempt=None, attempts=[]))
    assert write_pick_and_place_video(tmp_path, record) is None and not stale.exists()
