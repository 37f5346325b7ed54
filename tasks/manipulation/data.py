"""Interaction data: one Zarr group per pick-and-place attempt under ``<asset>/interaction/attempt_NNN``.

Arrays (SI units, float32 particle states at >= 30 fps, float64 otherwise):
  control_t_s (K,)  control_dt_s (K,)  phase (K,) index into tasks.robot.PHASES
  command_q_rad (K, 7)  command_qdot_rad_per_s (K, 7)  command_opening_m (K, 2): opening [m] and its rate [m/s]
  finger_position_m (K, 2, 3)  finger_quat_xyzw (K, 2, 4)  finger_velocity_m_per_s (K, 2, 3)  finger_half_extents_m (3,)
  finger_force_n (K, 2, 3): mean reaction force ON each finger over the interval (eq. 3); finger_impulse_n_s (K, 2, 3)
  ground_force_n (K, 3)  object_com_m (K + 1, 3)  closing_axis_world (3,)
  frame_t_s (T,)  frame_control_index (T,)  particles_x_m (T, N, 3) f32  particles_F (T, N, 3, 3) f32
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
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import zarr

from contracts.errors import InputError

INTERACTION = "interaction"
_NAME = re.compile(r"^attempt_(\d{3,})$")
FLOAT32_ARRAYS = ("particles_x_m", "particles_F")


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


def write_attempt(asset_dir: Path, arrays: dict[str, np.ndarray], attrs: dict[str, Any],
                  index: int | None = None) -> int:
    """Store one attempt (atomically); returns its index (the next free one unless given)."""
    root = interaction_dir(asset_dir)
    root.mkdir(parents=True, exist_ok=True)
    if not (root / "zarr.json").is_file():
        zarr.open_group(str(root), mode="a").attrs.update({"units": "SI", "layout": "attempt_NNN groups"})
    n = index if index is not None else (max(attempt_indices(asset_dir), default=-1) + 1)
    dest = root / f"attempt_{n:03d}"
    tmp = Path(tempfile.mkdtemp(prefix=f".attempt_{n:03d}.tmp-", dir=root))
    try:
        g = zarr.open_group(str(tmp), mode="w")
        for name, a in arrays.items():
            a = np.asarray(a)
            dtype = np.float32 if name in FLOAT32_ARRAYS else (np.float64 if a.dtype.kind == "f" else a.dtype)
            g.create_array(name, data=np.ascontiguousarray(a, dtype=dtype))
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
    g = zarr.open_group(str(interaction_dir(asset_dir) / f"attempt_{n:03d}"), mode="r")
    arrays = {name: np.asarray(a[...]) for name, a in g.arrays()}
    return arrays, dict(g.attrs)
