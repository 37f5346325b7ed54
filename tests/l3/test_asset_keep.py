"""Assets a fleet can store (#38 item 5): by default an asset keeps the reported L3 trial's states and recording alone;
every other trial's are left in the content-addressed cache, their rows in manipulation.json naming the key
(kept_in 'cache', data_key, recording_in_cache); `deformsmith replay --trial N` reads such a trial from the cache and
says in one line when the cache no longer has it; `--record all` keeps today's full copy."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contracts.errors import InputError
from contracts.manipulation import ManipulationRecord
from tests.asset_records import manipulation_record
from tests.l3.render_helpers import cube_context, short_attempt

REPO = Path(__file__).resolve().parents[2]
LIMIT_BYTES = 20 * 2**20  # an asset by default: at most 20 MB


@pytest.fixture(scope="module")
def attempt() -> tuple[dict[str, np.ndarray], dict]:
    """A short attempt (0.2 s of approach, then 0.5 s of closure and lift)."""
    return short_attempt(approach_s=0.2, length_s=0.5)


def _l3_asset(root: Path, attempt: tuple) -> ManipulationRecord:
    """Three stored trials (selection, robustness, held out) as L3's _store leaves them; the record reports trial 2."""
    from contracts.probes import ProbeResult, ProbeSpec
    from contracts.robot import ActionPlan

    arrays, attrs = attempt
    ctx = cube_context(root)
    plan = ActionPlan.model_validate(attrs["plan"])
    for i, role in enumerate(("selection", "robustness", "held_out")):
        labels = {"lifted": 1.0, "transported": 1.0, "released_in_target": 1.0, "settled": float(i != 2)}
        out = {"probe": ProbeResult(spec=ProbeSpec(kind="pick_and_place"), metrics=labels), "arrays": arrays,
               "info": {}}
        inputs = {"plan": plan, "settings": {"substeps": 1 + i}}
        ctx._store(out, plan, inputs, {"squeeze_depth_m": 0.003 + 0.001 * i}, role, "", None, 0.0)
    rows = [a.model_copy(update={"trial": i + 1}) for i, a in enumerate(ctx.attempts)]
    return manipulation_record(True, rows, attempt=1, trial=2, recordings=[r.recording for r in rows])


def _size(root: Path) -> int:
    return sum(p.stat().st_size for p in root.rglob("*") if p.is_file())


def test_a_default_asset_keeps_the_reported_trial_and_leaves_the_others_in_the_cache(
        attempt: tuple, tmp_path: Path, cache_dir: Path) -> None:
    from cache import CacheStore, cache_resolve
    from tasks.asset_dir import AssetDir
    from tasks.manipulation.data import attempt_indices, read_attempt, read_attempt_folder
    from tasks.manipulation.keep import keep_trials
    from tasks.record.trials import data_location

    asset = tmp_path / "asset"
    record = _l3_asset(asset, attempt)
    full = shutil.copytree(asset, tmp_path / "full")  # what --record all publishes
    assert attempt_indices(full) == [0, 1, 2] and len(list((full / "recordings").glob("L3_trial_*.rrd"))) == 3
    assert keep_trials(full, record, "all") is record  # --record all: every trial's states and recording

    kept = keep_trials(asset, record, "adopted")
    AssetDir(asset).write_manipulation(kept)
    assert attempt_indices(asset) == [1]  # only the reported trial's states
    assert sorted(p.name for p in (asset / "recordings").iterdir()) == ["L3_trial_02.rrd"]
    assert kept.recordings == ["recordings/L3_trial_02.rrd"] and AssetDir(asset).manipulation() == kept
    assert _size(asset) < LIMIT_BYTES and _size(asset) < _size(full)
    store = CacheStore(cache_dir)
    for row in kept.attempts:
        assert row.data_key and row.attempt is not None
        if row.attempt == 1:
            assert row.kept_in == "asset" and data_location(row, asset) == "interaction/attempt_001"
            continue
        # every metric stays; the states and recording are named in the cache by key, and really are there
        assert row.kept_in == "cache" and row.recording is None and row.labels == record.attempts[row.attempt].labels
        assert data_location(row, asset) == f"in the cache, key {row.data_key[:12]}"
        folder = store.get(row.data_key)
        got, attrs = read_attempt_folder(folder)
        want, want_attrs = read_attempt(full, row.attempt)
        assert attrs == want_attrs and got.keys() == want.keys()
        assert all(np.array_equal(got[k], want[k]) for k in want)
        assert row.recording_in_cache and cache_resolve(row.recording_in_cache).is_file()
    json_text = (asset / "manipulation.json").read_text()
    assert '"kept_in": "cache"' in json_text and '"data_key"' in json_text


def test_a_trial_whose_data_the_cache_lacks_stays_in_the_asset(attempt: tuple, tmp_path: Path,
                                                               cache_dir: Path) -> None:
    from cache import CacheStore
    from tasks.manipulation.data import attempt_indices
    from tasks.manipulation.keep import keep_trials

    asset = tmp_path / "asset"
    record = _l3_asset(asset, attempt)
    assert CacheStore(cache_dir).remove(record.attempts[0].data_key)
    kept = keep_trials(asset, record, "adopted")
    assert attempt_indices(asset) == [0, 1] and [r.kept_in for r in kept.attempts] == ["asset", "asset", "cache"]
    assert kept.recordings == ["recordings/L3_trial_01.rrd", "recordings/L3_trial_02.rrd"]


def test_replay_reads_a_trial_from_the_cache_and_says_in_one_line_when_it_is_gone(
        attempt: tuple, tmp_path: Path, cache_dir: Path) -> None:
    from cache import CacheStore
    from tasks.asset_dir import AssetDir
    from tasks.manipulation.keep import keep_trials
    from tasks.manipulation.replay import replay

    asset = tmp_path / "asset"
    record = _l3_asset(asset, attempt)
    full = shutil.copytree(asset, tmp_path / "full")
    AssetDir(full).write_manipulation(record)
    kept = keep_trials(asset, record, "adopted")
    AssetDir(asset).write_manipulation(kept)
    from_cache = replay(asset, trial=3, width=96, height=54, rrd=tmp_path / "t3.rrd")
    assert from_cache.trial == 3 and from_cache.digests == replay(full, trial=3, width=96, height=54).digests
    assert (tmp_path / "t3.rrd").is_file()
    assert CacheStore(cache_dir).remove(kept.attempts[2].data_key)
    with pytest.raises(InputError, match="trial 3's states are not in .* and the cache .* no longer holds them"):
        replay(asset, trial=3, width=96, height=54)
    r = subprocess.run([sys.executable, "-m", "flows.cli.main", "replay", str(asset), "--trial", "3"],
                       capture_output=True, text=True, cwd=REPO, timeout=600)
    assert r.returncode == 2 and r.stderr.startswith("error: trial 3's states") and r.stderr.count("\n") == 1


def test_a_reported_trial_over_the_budget_keeps_every_sth_frame_and_replay_reads_all_from_the_cache(
        attempt: tuple, tmp_path: Path, cache_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A large object's reported trial (a cat bed's: 122 MB of particle frames) would make the asset: its frames
    beyond the budget are thinned in time, the first and last kept, the rest of the trial (controls, forces) whole;
    the row says the stride, and replay reads every frame from the cache entry."""
    from cache import CacheStore
    from tasks.asset_dir import AssetDir
    from tasks.manipulation import keep
    from tasks.manipulation.data import frame_bytes, interaction_dir, read_attempt, read_attempt_folder
    from tasks.manipulation.replay import _read

    arrays, attrs = attempt
    n_frames, rng = len(arrays["frame_t_s"]), np.random.default_rng(0)
    x = np.cumsum(rng.normal(0.0, 1e-4, (n_frames, 4000, 3)), axis=0) + rng.uniform(-0.05, 0.05, (1, 4000, 3))
    f = np.eye(3) + np.cumsum(rng.normal(0.0, 1e-3, (n_frames, 4000, 3, 3)), axis=0)
    big = {**arrays, "particles_x_m": x.astype(np.float32), "particles_F": f.astype(np.float32)}  # a larger body's
    asset = tmp_path / "asset"
    record = _l3_asset(asset, (big, attrs))
    folder = interaction_dir(asset) / "attempt_001"
    full_bytes = frame_bytes(folder)
    budget = full_bytes // 3
    monkeypatch.setattr(keep, "KEPT_FRAMES_BYTES", budget)
    kept = keep.keep_trials(asset, record, "adopted")
    AssetDir(asset).write_manipulation(kept)
    row = next(r for r in kept.attempts if r.attempt == 1)
    assert row.frame_stride >= 3 and '"frame_stride"' in (asset / "manipulation.json").read_text()
    assert frame_bytes(folder) <= 1.2 * budget  # (one more frame: the last)
    got, attrs = read_attempt(asset, 1)
    want, _ = read_attempt_folder(CacheStore(cache_dir).get(row.data_key))
    n = len(want["frame_t_s"])
    assert attrs["frames_full"] == n and attrs["frame_stride"] == row.frame_stride
    idx = np.unique(np.r_[np.arange(0, n, row.frame_stride), n - 1])
    assert np.array_equal(got["frame_t_s"], want["frame_t_s"][idx])
    assert np.allclose(got["particles_x_m"], want["particles_x_m"][idx], atol=1e-5)
    assert np.allclose(got["particles_F"], want["particles_F"][idx], atol=1e-3)
    assert np.array_equal(got["finger_force_n"], want["finger_force_n"])  # the controls and forces whole
    full, _ = _read(asset, 1, 2)
    assert np.array_equal(full["frame_t_s"], want["frame_t_s"])  # replay: every frame, from the cache
    # a rerun keeps the stride it recorded
    again = keep.keep_trials(asset, AssetDir(asset).manipulation(), "adopted")
    assert next(r for r in again.attempts if r.attempt == 1).frame_stride == row.frame_stride


def test_a_long_trials_recording_shows_the_object_at_a_bounded_number_of_frames(attempt: tuple,
                                                                                 tmp_path: Path) -> None:
    """A trial's recording logs the object at most at max_object_frames evenly strided frames and the last (a long
    trial's recording kept its size: the loaf's was 9 MB of a 23.6 MB asset); without the cap, every frame."""
    from tasks.manipulation.replay import rrd_particle_frames, write_rrd

    arrays, attrs = attempt
    n = len(arrays["frame_t_s"])
    assert n >= 8
    every = rrd_particle_frames(write_rrd(arrays, attrs, tmp_path / "all.rrd", 500))
    capped = rrd_particle_frames(write_rrd(arrays, attrs, tmp_path / "capped.rrd", 500, max_object_frames=4))
    assert len(every) == n
    assert len(capped) <= 5 and np.allclose(capped[-1], every[-1]) and np.allclose(capped[0], every[0])
