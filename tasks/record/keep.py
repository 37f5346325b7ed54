"""Where a layer's chosen probe recordings go (L1's and L2's; L3's trials: tasks.manipulation.keep): copied into the
asset's recordings/ folder under keep 'all', else left in the cache (keep 'adopted', the default, #38: an asset a
fleet can store) under the name the layer's record gives them (its cached_recordings)."""

from __future__ import annotations

from pathlib import Path

from cache import cache_relative, cache_resolve
from contracts.asset_dir import KeepTrials
from tasks.publish import copy_file_atomic


def keep_recording(src: str | None, asset_dir: Path, name: str, keep: KeepTrials,
                   cached: dict[str, str]) -> str | None:
    """The cached recording `src` as the asset's recordings/<name>: under keep 'all' copied there, its path relative
    to the asset returned; else an earlier copy removed and cached['recordings/<name>'] set to its cache path (None
    returned). None, and nothing done, when `src` names no file in the cache."""
    path = cache_resolve(src) if src else None
    if path is None or not path.is_file():
        return None
    dest = asset_dir / "recordings" / name
    rel = str(Path("recordings") / name)
    if keep != "all":
        dest.unlink(missing_ok=True)  # (an earlier run's copy, on a rerun of the layer)
        cached[rel] = cache_relative(path)
        return None
    copy_file_atomic(path, dest)  # a new file: a hard link of a working copy (tasks.publish) is never rewritten
    return rel
