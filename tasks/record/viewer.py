"""What `deformsmith view` opens: an asset's recordings (recordings/*.rrd), the L1 and L2 probe recordings its records
name in the cache, and the Rerun viewer command that shows them."""

from __future__ import annotations

import json
import os
import shutil
import sys
from pathlib import Path

from cache import cache_resolve


def cached_recordings(asset: Path) -> tuple[list[Path], list[str]]:
    """The L1 and L2 probe recordings an asset's records name in the cache (physical.json, material.json
    cached_recordings: a default asset leaves them there, #38): (the files the cache holds, the names it no longer
    holds)."""
    found: list[Path] = []
    gone: list[str] = []
    for doc in ("physical.json", "material.json"):
        try:
            named = json.loads((asset / doc).read_text(encoding="utf-8")).get("cached_recordings") or {}
        except (OSError, ValueError, AttributeError):
            continue
        for name, ref in sorted(named.items()):
            path = cache_resolve(ref)
            if path.is_file():
                found.append(path)
            else:
                gone.append(name)
    return found, gone


def asset_recordings(asset: Path) -> tuple[list[Path], list[str]]:
    """Every recording of an asset directory, its own first, then those the cache holds for it; and the names of
    those the cache no longer holds. None of either when `asset` is not a directory."""
    if not asset.is_dir():
        return [], []
    cached, gone = cached_recordings(asset)
    return sorted((asset / "recordings").glob("*.rrd")) + cached, gone


def viewer_command(recordings: list[Path]) -> tuple[str | None, list[str]]:
    """(the Rerun viewer found: next to the interpreter, where rerun-sdk installs it, else on PATH; None when there
    is none) and the command that opens the recordings in it."""
    beside = Path(sys.executable).parent / "rerun"
    viewer = str(beside) if beside.is_file() else shutil.which("rerun")
    return viewer, [viewer or "rerun", *map(str, recordings)]


def has_display() -> bool:
    """A viewer window can open: a display on POSIX (X11 or Wayland); elsewhere assumed."""
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")) or os.name != "posix"
