"""Interaction data: one Zarr group per pick-and-place attempt under ``<asset>/interaction/attempt_NNN``.

Arrays (SI units, float32 particle states at >= 30 fps, float64 otherwise):
  control_t_s (K,)  control_dt_s (K,)  phase (K,) index into tasks.robot.PHASES
  command_q_rad (K, 7)  command_qdot_rad_per_s (K, 7)  command_opening_m (K, 2): opening [m] and its rate [m/s]
  finger_position_m (K, 2, 3)  finger_quat_xyzw (K, 2, 4)  finger_velocity_m_per_s (K, 2, 3)  finger_half_extents_m (3,)
  finger_force_n (K, 2, 3): mean reaction force ON each finger over the interval (eq. 3); finger_impulse_n_s (K, 2, 3)
  ground_force_n (K, 3)  object_com_m (K + 1, 3)  closing_axis_world (3,)
  frame_t_s (T,)  frame_control_index (T,)  particles_x_m (T, N, 3) f32  particles_F (T, N, 3, 3) f32: stored as
  16-bit fixed point (tasks.manipulation.particle_frames: particles_x_center_m (T, 3), particles_x_offset_steps and
  particles_F_offset_steps, int16, each with its step; within 3.8 um for an object within 25 cm of its centre, 1.9 um
  for the draft turtle),
  decoded by read_attempt; time-last, byte-shuffled and zstd-compressed (Blosc)
  rest_particles_m (N, 3)  particle_volumes_m3 (N,)  gaussian_* (rest Gaussians in the world frame at t = 0, bound to the trial particles)
  approach_t_s (A,)  approach_q_rad (A, 7)  approach_opening_m (A,)  approach_finger_position_m (A, 2, 3)
  approach_finger_quat_xyzw (A, 2, 4): the commanded robot from t = 0 until the simulation starts (the object at rest),
  at the recording rate, so that a replay shows the whole attempt (absent in attempts recorded before them)
Attributes: ``labels`` (the outcome metrics, failed attempts included), ``plan`` (ActionPlan JSON), ``info`` (numerics,
particles, steps, wall time), ``role`` (selection | held_out | confirmation) and anything the caller adds. Each attempt
is written to a temporary folder and renamed into place, so a reader never sees half an attempt.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import zarr
from zarr.codecs import BloscCodec, TransposeCodec

from cache import CacheMiss, CacheStore, cache_root
from contracts.errors import InputError
from tasks.manipulation import particle_frames

INTERACTION = "interaction"
_NAME = re.compile(r"^attempt_(\d{3,})$")
FLOAT32_ARRAYS = ("particles_x_m", "particles_F")
# the rest Gaussians an attempt is drawn with, stored at gaussians.ply's precision (float32: the asset's own Gaussians
# are float32 there), not float64: 60k Gaussians' covariances were 2.6 MB of a 21 MB asset (session 42)
GAUSSIAN_FLOAT32 = ("gaussian_positions_m", "gaussian_covariances_m2", "gaussian_colors")
# the (T, N, ...) particle frames as stored: compressed along time, in chunks of whole particle histories
FRAME_ARRAYS = (*FLOAT32_ARRAYS, particle_frames.X_OFFSET, particle_frames.F_OFFSET)
FRAME_CHUNK_BYTES = 16 * 2**20
CHUNK_KEYS = {"name": "default", "separator": "."}  # c.0.0: one file per chunk, no folder per dimension


THIN_TRIES, THIN_SLACK = 3, 1.1  # thin_frames: strides tried, and the budget's slack (the last frame kept) [-]
FRAME_INDEXED = ("frame_t_s", "frame_control_index", particle_frames.X, particle_frames.F)  # (T, ...) as decoded


def frame_bytes(folder: Path) -> int:
    """Bytes an attempt's particle frames take on disk (their chunk files, not the arrays' metadata)."""
    names = (*FRAME_ARRAYS, particle_frames.X_CENTER)
    return sum(f.stat().st_size for n in names if (folder / n).is_dir() for f in (folder / n).rglob("*")
               if f.is_file() and f.name != "zarr.json")


def thin_frames(asset_dir: Path, index: int, budget_bytes: int) -> int:
    """Keep every s-th particle frame of a stored attempt (its first and last kept), s the smallest stride that
    brings its frames within budget_bytes; the attempt is rewritten atomically and its attributes say frame_stride s
    and frames_full T. Returns the attempt's stride (an attempt thinned before, or within the budget: as it is)."""
    folder = interaction_dir(asset_dir) / f"attempt_{index:03d}"
    done = zarr.open_group(str(folder), mode="r").attrs.get("frame_stride")
    size = frame_bytes(folder)
    if done is not None or size <= budget_bytes:  # thinned once already (a rerun), or within the budget
        return int(done or 1)
    arrays, attrs = read_attempt_folder(folder)
    n = len(arrays.get("frame_t_s", ()))
    stride = int(math.ceil(size / budget_bytes))
    if n < 3 or stride < 2:
        return 1
    attrs = {k: v for k, v in attrs.items() if k != "attempt"}
    for _ in range(THIN_TRIES):  # compression is not linear in the frames kept: a coarser stride while over
        keep = np.unique(np.r_[np.arange(0, n, stride), n - 1])
        thinned = {k: (v[keep] if k in FRAME_INDEXED and v.ndim and len(v) == n else v) for k, v in arrays.items()}
        write_attempt(asset_dir, thinned, {**attrs, "frame_stride": stride, "frames_full": n}, index=index)
        now = frame_bytes(folder)
        if now <= THIN_SLACK * budget_bytes or len(keep) <= 2:
            break
        stride = int(math.ceil(stride * now / budget_bytes))
    return stride


def interaction_dir(asset_dir: Path) -> Path:
    """The asset's interaction/ Zarr root."""
    return Path(asset_dir) / INTERACTION


def attempt_indices(asset_dir: Path) -> list[int]:
    """Indices of the attempts stored for an asset, ascending."""
    root = interaction_dir(asset_dir)
    if not root.is_dir():
        return []
    return sorted(int(m.group(1)) for p in root.iterdir() if (m := _NAME.match(p.name)))


def approach_track(trajectory: Any, t_end_s: float, fps: float) -> dict[str, np.ndarray]:
    """The commanded robot of a tasks.robot.Trajectory on [0, t_end_s) at fps: times [s], arm angles [rad], finger
    opening [m] and the pad boxes' poses (what a replay draws before the simulated part of a trial)."""
    t = np.arange(int(np.ceil(max(0.0, t_end_s) * fps - 1e-9))) / fps
    states = [trajectory.state_at(float(tk)) for tk in t]
    pads = trajectory.pads_at(t)
    return {"approach_t_s": t, "approach_q_rad": np.asarray([s.q for s in states], dtype=np.float64).reshape(-1, 7),
            "approach_opening_m": np.asarray([s.finger_opening_m for s in states], dtype=np.float64),
            "approach_finger_position_m": np.asarray(pads.position_m, dtype=np.float64).reshape(-1, 2, 3),
            "approach_finger_quat_xyzw": np.asarray(pads.quat_xyzw, dtype=np.float64).reshape(-1, 2, 4)}


def _jsonable(value: Any) -> Any:
    """Attributes as plain JSON (numpy scalars and arrays converted)."""
    return json.loads(json.dumps(value, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))


def storage(name: str, data: np.ndarray) -> dict[str, Any]:
    """zarr create_array settings of an interaction array: the particle frames time-last (a particle's history is
    contiguous), byte-shuffled and zstd-compressed (Blosc) in chunks of at most FRAME_CHUNK_BYTES; any other array
    zarr's default (zstd)."""
    if name not in FRAME_ARRAYS or data.ndim < 3 or data.size == 0:
        return {}
    per_particle = data.shape[0] * int(np.prod(data.shape[2:])) * data.itemsize
    n = max(1, min(data.shape[1], FRAME_CHUNK_BYTES // per_particle))
    return {"chunks": (data.shape[0], n, *data.shape[2:]),
            "filters": [TransposeCodec(order=(*range(1, data.ndim), 0))],
            "compressors": BloscCodec(cname="zstd", clevel=5, shuffle="shuffle", typesize=data.itemsize)}


def interaction_root(asset_dir: Path) -> Path:
    """The asset's interaction/ Zarr group, created when missing (the attempts are its subgroups)."""
    root = interaction_dir(asset_dir)
    root.mkdir(parents=True, exist_ok=True)
    if not (root / "zarr.json").is_file():
        zarr.open_group(str(root), mode="a").attrs.update({"units": "SI", "layout": "attempt_NNN groups"})
    return root


def write_attempt(asset_dir: Path, arrays: dict[str, np.ndarray], attrs: dict[str, Any],
                  index: int | None = None) -> int:
    """Store one attempt (atomically); returns its index (the next free one unless given)."""
    root = interaction_root(asset_dir)
    n = index if index is not None else (max(attempt_indices(asset_dir), default=-1) + 1)
    dest = root / f"attempt_{n:03d}"
    tmp = Path(tempfile.mkdtemp(prefix=f".attempt_{n:03d}.tmp-", dir=root))
    try:
        g = zarr.open_group(str(tmp), mode="w")
        for name, a in arrays.items():
            a = np.asarray(a)
            dtype = np.float32 if name in (*FLOAT32_ARRAYS, *GAUSSIAN_FLOAT32) else (
                np.float64 if a.dtype.kind == "f" else a.dtype)
            for s in particle_frames.encode(name, np.asarray(a, dtype=dtype)):
                data = np.ascontiguousarray(s.data)
                g.create_array(s.name, data=data, attributes=s.attrs or None, chunk_key_encoding=CHUNK_KEYS,
                               **storage(s.name, data))
        g.attrs.update(_jsonable({**attrs, "attempt": n}))
        if dest.exists():
            shutil.rmtree(dest)
        os.replace(tmp, dest)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    return n


def read_attempt(asset_dir: Path, index: int | None = None) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Arrays and attributes of one attempt (default: the last one)."""
    indices = attempt_indices(asset_dir)
    if not indices:
        raise InputError(f"{asset_dir} has no interaction data: run `deformsmith manipulate {asset_dir}` first")
    n = indices[-1] if index is None else index
    if n not in indices:
        raise InputError(f"{asset_dir} has no attempt {n}; stored attempts: {indices}")
    return read_attempt_folder(interaction_dir(asset_dir) / f"attempt_{n:03d}")


def cached_attempt_folder(data_key: str | None) -> Path | None:
    """The attempt folder the cache holds under a trial row's data_key (checked by key, digests included), else None."""
    if not data_key:
        return None
    try:
        found = CacheStore(cache_root()).get(data_key)
    except CacheMiss:
        return None
    return found if isinstance(found, Path) and found.is_dir() else None


def read_attempt_folder(folder: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Arrays and attributes of the attempt stored in one attempt_NNN Zarr group (an asset's, or the cache entry a
    trial row's data_key names)."""
    g = zarr.open_group(str(folder), mode="r")
    stored = dict(g.arrays())
    arrays = {name: np.asarray(a[...]) for name, a in stored.items()}
    encoded = {name: dict(stored[name].attrs) for name in particle_frames.ENCODED if name in stored}
    return particle_frames.decode(arrays, encoded), dict(g.attrs)
