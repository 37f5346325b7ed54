"""A layer's chosen probe recordings kept in the asset or left in the cache (tasks.record.keep), and what `view`
opens (tasks.record.viewer): the asset's recordings and those its records name in the cache."""

from __future__ import annotations

import json
from pathlib import Path

from cache import cache_relative, cache_root
from tasks.record.keep import keep_recording
from tasks.record.viewer import asset_recordings, has_display, viewer_command


def _cached(name: str) -> str:
    path = cache_root() / "recordings" / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"rrd")
    return cache_relative(path)


def test_a_recording_is_copied_under_all_and_named_in_the_cache_otherwise(tmp_path: Path) -> None:
    src = _cached("x.rrd")
    cached: dict[str, str] = {}
    assert keep_recording(src, tmp_path, "L2_drop.rrd", "all", cached) == "recordings/L2_drop.rrd"
    assert (tmp_path / "recordings" / "L2_drop.rrd").read_bytes() == b"rrd" and cached == {}
    assert keep_recording(src, tmp_path, "L2_drop.rrd", "adopted", cached) is None  # the earlier copy goes
    assert cached == {"recordings/L2_drop.rrd": src} and not (tmp_path / "recordings" / "L2_drop.rrd").exists()
    assert keep_recording(None, tmp_path, "a.rrd", "all", cached) is None
    assert keep_recording("recordings/gone.rrd", tmp_path, "a.rrd", "all", cached) is None


def test_view_opens_the_asset_s_recordings_and_those_the_cache_holds(tmp_path: Path) -> None:
    (tmp_path / "recordings").mkdir()
    (tmp_path / "recordings" / "L3_pick_and_place.rrd").write_bytes(b"")
    src = _cached("L1_drop.rrd")
    (tmp_path / "physical.json").write_text(json.dumps({"cached_recordings": {
        "recordings/L1_drop.rrd": src, "recordings/L1_slide.rrd": "recordings/gone.rrd"}}))
    (tmp_path / "material.json").write_text("not json")
    found, gone = asset_recordings(tmp_path)
    assert found == [tmp_path / "recordings" / "L3_pick_and_place.rrd", cache_root() / src]
    assert gone == ["recordings/L1_slide.rrd"] and asset_recordings(tmp_path / "none") == ([], [])
    viewer, command = viewer_command(found)
    assert command == [viewer or "rerun", *map(str, found)]
    assert isinstance(has_display(), bool)
