"""The pick-and-place video's cache key (tasks.manipulation.pick_place_video): made of the recorded attempt's bytes,
the renderer's sources, every one of which exists, and the device that draws it; a record that shows no recorded
trial leaves no video; the run's device reaches the renderer."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any, cast

import pytest

from contracts.manipulation import ManipulationRecord
import tasks.manipulation.pick_place_video as ppv
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


def test_the_device_keys_the_video_apart_and_reaches_replay(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A GPU's video is cached apart from the CPU's (within a colour level, not the same bytes), and the run's device
    is what replay draws on."""
    data = tmp_path / "interaction" / "attempt_001"
    data.mkdir(parents=True)
    (data / "x").write_bytes(b"\x00")
    assert pick_and_place_video_key(tmp_path, 1) == pick_and_place_video_key(tmp_path, 1, "cpu")
    assert pick_and_place_video_key(tmp_path, 1, "cuda") != pick_and_place_video_key(tmp_path, 1, "cpu")
    drawn: list[str] = []

    def fake_replay(work: Path, attempt: int, video: Path, device: str = "cpu", **kw: Any) -> None:
        drawn.append(device)
        Path(video).write_bytes(device.encode())

    monkeypatch.setattr(ppv, "replay", fake_replay)
    record = cast(ManipulationRecord, SimpleNamespace(attempt=1, attempts=[]))
    for device in ("cuda", "cpu", "cuda"):  # the second cuda run: the cache's copy
        video = write_pick_and_place_video(tmp_path, record, device)
        assert video is not None and video.read_bytes() == device.encode()
    assert drawn == ["cuda", "cpu"]


def test_generate_draws_the_video_on_the_runs_device(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """flows.generate.run_manipulation (generate's L3 stage) hands its device to the video, as to the trials."""
    import flows.generate as generate

    record = SimpleNamespace(attempt=0)
    seen: dict[str, Any] = {}

    def run_l3(work: Path, options: Any, agents: Any, **kw: Any) -> tuple[Any, None]:
        seen["l3"] = options.device
        return record, None

    def video(work: Path, rec: Any, device: str = "cpu") -> None:
        seen["video"] = device

    monkeypatch.setattr(generate.l3_manipulation, "run_l3", run_l3)
    monkeypatch.setattr(generate, "write_pick_and_place_video", video)
    assert generate.run_manipulation(tmp_path, "cuda", "draft", None) is record
    assert seen == {"l3": "cuda", "video": "cuda"}


def test_a_video_drawn_early_from_the_cached_states_is_the_one_the_asset_copies(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """generate draws the video of L3's passed selection trial while later trials run (prerender_pick_and_place_video,
    from the trial's cache entry); at the end write_pick_and_place_video finds it under the same key and copies it,
    even when the asset's own copy of the states was thinned since (other bytes: the key follows the cached states)."""
    from cache.files import cached_file
    from contracts.manipulation import TrialRow

    def store_states(path: Path) -> None:
        path.mkdir(parents=True)
        (path / "particles_x_m").write_bytes(b"full-rate")

    data_key = "ab" * 32  # the trial row's key of its states
    work = tmp_path / "work"
    cached_file(data_key, work / "interaction" / "attempt_000", store_states)
    drawn: list[bytes] = []

    def draw(arrays: Any, attrs: Any, video: Path, device: str = "cpu") -> None:
        drawn.append(arrays)
        Path(video).write_bytes(b"mp4 of " + arrays)

    monkeypatch.setattr(ppv, "read_attempt_folder", lambda folder: ((Path(folder) / "particles_x_m").read_bytes(), {}))
    monkeypatch.setattr(ppv, "draw_attempt", draw)
    assert ppv.prerender_pick_and_place_video(data_key) and drawn == [b"full-rate"]
    assert not ppv.prerender_pick_and_place_video("cd" * 32)  # an entry the cache does not hold
    (work / "interaction" / "attempt_000" / "particles_x_m").write_bytes(b"thinned")  # keep_trials' thinning

    def no_replay(*args: Any, **kwargs: Any) -> None:
        raise AssertionError("the video was drawn again")

    monkeypatch.setattr(ppv, "replay", no_replay)
    row = TrialRow(attempt=0, role="selection", action="", labels={}, data_key=data_key)
    record = cast(ManipulationRecord, SimpleNamespace(attempt=0, attempts=[row]))
    video = write_pick_and_place_video(work, record)
    assert video is not None and video.read_bytes() == b"mp4 of full-rate" and drawn == [b"full-rate"]
