"""Every L3 trial as a probe recording in the asset: recordings/L3_trial_NN.rrd, named by the trial's one number
(from 1, as the console, manipulation.json, evidence and the card count trials: tasks.record.trials); its states are in
interaction/attempt_NNN (the row's `attempt`).

The recording of a trial (tasks.manipulation.replay.write_rrd: robot links, pads, particles, Gaussians, per-finger
force curves) is made once per trial cache key into the cache's recordings folder, like L1's and L2's probe
recordings, and copied into the asset; both files appear only when complete (written to a temporary name, then
renamed). What it shows depends on the trial alone (its id and log name the trial's key, not the attempt number), so a
cached trial stored as another attempt reuses it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from cache import cache_root
from tasks.manipulation import replay
from tasks.publish import copy_file_atomic

RECORDING_VERSION = "3"  # bump when write_rrd changes what a trial's recording shows (3: MAX_OBJECT_FRAMES)
# what a trial's recording keeps (a deterministic stride). At 3000 particles and 2000 Gaussians the adopted trial's
# recording was 6.2 MB of the draft turtle's 19.6 MB asset and 8.1 MB of the rubber duck's 21.2 MB on an H200 (#38
# asks at most 20 MB per default asset); the preview keeps the object's shape at these counts.
MAX_PARTICLES = 2000     # particles per frame
MAX_GAUSSIANS = 1200     # Gaussians per frame ...
GAUSSIAN_EVERY = 2       # ... at every second recorded frame (15 fps)
MAX_OBJECT_FRAMES = 90   # the object at most at 90 frames of a trial (a long one strided: the loaf's recording was
# 9.0 MB of its 23.6 MB asset, the cat bed's 7.9 MB of 25.8 MB on an H200; the robot moves at every frame)


def _write(arrays: dict[str, np.ndarray], attrs: dict[str, Any], path: Path) -> Path:
    """A trial's recording at what it keeps (the limits above)."""
    return replay.write_rrd(arrays, attrs, path, MAX_PARTICLES, MAX_GAUSSIANS, GAUSSIAN_EVERY, MAX_OBJECT_FRAMES)


def trial_recording_name(trial: int) -> str:
    """The asset-relative path of trial `trial`'s recording (1-based)."""
    return f"recordings/L3_trial_{trial:02d}.rrd"


def cached_recording_path(trial_key: str) -> Path:
    """Where the recording of the trial with cache key `trial_key` lives in the cache."""
    return cache_root() / "recordings" / f"L3_trial-{trial_key[:16]}-r{RECORDING_VERSION}.rrd"


def cached_recording(arrays: dict[str, np.ndarray], attrs: dict[str, Any], trial_key: str) -> Path:
    """The trial's recording in the cache (written there on first use, atomically)."""
    path = cached_recording_path(trial_key)
    if not path.is_file():
        shown = {"labels": attrs.get("labels", {}), "role": f"trial {trial_key[:16]}", "plan": attrs.get("plan"),
                 "attempt": trial_key[:16]}
        _write(arrays, shown, path)
    return path


def record_attempt(asset_dir: Path, trial: int, arrays: dict[str, np.ndarray], attrs: dict[str, Any],
                   trial_key: str | None) -> str:
    """Put trial `trial`'s recording (1-based) into the asset as recordings/L3_trial_NN.rrd; returns that relative
    path (a trial without a cache key is recorded straight into the asset)."""
    rel = trial_recording_name(trial)
    if trial_key is None:
        _write(arrays, attrs, Path(asset_dir) / rel)
    else:
        copy_file_atomic(cached_recording(arrays, attrs, trial_key), Path(asset_dir) / rel)
    return rel
