"""Interaction data in Zarr and replay without re-simulation: exact, deterministic frames and the .rrd."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from tasks.manipulation.data import attempt_indices, read_attempt, write_attempt
from tasks.manipulation.particle_frames import encode, max_error
from tasks.manipulation.replay import render_frames, replay, rrd_particle_frames
from tasks.manipulation.scene import attempt_timeline
from tasks.manipulation.trial import TrialResult


def test_attempts_are_stored_and_replayed_exactly(firm_trial: TrialResult, weak_trial: TrialResult,
                                                  tmp_path: Path) -> None:
    asset = tmp_path / "asset"
    n0 = write_attempt(asset, firm_trial.arrays, {"labels": firm_trial.metrics, "role": "selection"})
    n1 = write_attempt(asset, weak_trial.arrays, {"labels": weak_trial.metrics, "role": "selection"})
    assert (n0, n1) == (0, 1) and attempt_indices(asset) == [0, 1]
    arrays, attrs = read_attempt(asset, 1)
    assert attrs["labels"]["slipped"] == 1  # failed attempts are kept, labelled
    for name in ("particles_x_m", "particles_F"):  # 16-bit fixed point (tasks.manipulation.particle_frames)
        want = weak_trial.arrays[name]
        bound = max_error(name, encode(name, want), want)
        assert arrays[name].shape == want.shape and np.abs(arrays[name].astype(np.float64) - want).max() <= bound
    assert bound < 1e-5 and np.array_equal(arrays["frame_t_s"], weak_trial.arrays["frame_t_s"])  # the same frames

    out = replay(asset, 0, frames_dir=tmp_path / "frames", video=tmp_path / "v.mp4", rrd=tmp_path / "a.rrd",
                 width=320, height=180)
    arrays, attrs = read_attempt(asset, 0)
    # the video runs from the recorded approach (t = 0) through the last simulated frame, at 30 fps
    assert out.n_frames == len(attempt_timeline(arrays)) and len(out.frames) == out.n_frames
    assert out.n_frames > len(firm_trial.arrays["frame_t_s"]) + 20
    assert (tmp_path / "v.mp4").stat().st_size > 1000
    again = [hashlib.sha256(im.tobytes()).hexdigest() for im in render_frames(arrays, 320, 180, attrs)]
    assert again == out.digests  # byte-identical re-render
    assert len(set(out.digests)) > 5  # the frames show motion
    rrd = rrd_particle_frames(tmp_path / "a.rrd")
    stored = read_attempt(asset, 0)[0]["particles_x_m"]
    assert len(rrd) == len(stored) and all(np.array_equal(a, b) for a, b in zip(rrd, stored))
