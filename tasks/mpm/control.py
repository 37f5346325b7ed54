"""Control: the inputs of a rollout — kinematic collider motion and per-scene gravity (SI units)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING
from collections.abc import Sequence

import numpy as np
import warp as wp

from contracts.errors import InputError

if TYPE_CHECKING:
    from tasks.mpm.model import Model

Vec = Sequence[float] | np.ndarray  # a vector [SI], list, tuple or array


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions stored (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    )


class Control:
    """Collider motion as (reference pose at a reference time, constant linear/angular velocity), gravity per scene.

    A collider's pose at time t is p(t) = p_ref + v (t - t_ref), q(t) = exp(w (t - t_ref)) q_ref (w in the world
    frame, rad/s); kernels evaluate it on the device each step, so a CUDA graph replays without host work.
    ``set_collider`` re-anchors the reference at the current simulation time (fields left out keep their current
    value). Quaternions are (x, y, z, w).
    """

    def __init__(self, model: Model) -> None:
        self.model = model
        n = model.n_colliders
        specs = model.collider_specs
        self.ref_pos = np.asarray([c.position_m for c in specs], dtype=np.float64).reshape(n, 3)
        self.ref_rot = np.asarray([c.rotation_xyzw for c in specs], dtype=np.float64).reshape(n, 4)
        norms = np.linalg.norm(self.ref_rot, axis=1) if n else np.zeros(0)
        if n and np.any(norms < 1e-9):
            raise InputError("collider rotation quaternion must be non-zero")
        if n:
            self.ref_rot /= norms[:, None]
        self.ref_time = np.zeros(n, dtype=np.float64)
        self.lin_vel = np.asarray([c.linear_velocity_m_per_s for c in specs], dtype=np.float64).reshape(n, 3)
        self.ang_vel = np.asarray([c.angular_velocity_rad_per_s for c in specs], dtype=np.float64).reshape(n, 3)
        self.gravity = np.array(model.gravity_np, dtype=np.float64)
        self._pending: dict[int, dict[str, np.ndarray]] = {}
        self._dirty = True
        d = model.device
        m = max(1, n)
        self.d_ref_pos = wp.zeros(m, dtype=wp.vec3, device=d)
        self.d_ref_rot = wp.zeros(m, dtype=wp.quat, device=d)
        self.d_ref_time = wp.zeros(m, dtype=wp.float64, device=d)
        self.d_lin_vel = wp.zeros(m, dtype=wp.vec3, device=d)
        self.d_ang_vel = wp.zeros(m, dtype=wp.vec3, device=d)
        self.d_gravity = wp.zeros(model.n_scenes, dtype=wp.vec3, device=d)
        # lattice motion per scene: offset [cells] at the reference time [s] and velocity [cells/s] (kernels.lattice_shift)
        B = model.n_scenes
        self.slide_ref = np.zeros((B, 3))
        self.slide_time = np.zeros(B)
        self.slide_vel = np.zeros((B, 3))
        self._slide_pending: dict[int, np.ndarray] = {}
        self._sliding = False
        self.d_grid_slide = wp.zeros(8 * B, dtype=wp.float64, device=d)

    # -- setters -------------------------------------------------------------------------------------------------
    def set_collider(
        self,
        scene: int,
        index: int,
        *,
        position_m: Vec | None = None,
        rotation_xyzw: Vec | None = None,
        linear_velocity_m_per_s: Vec | None = None,
        angular_velocity_rad_per_s: Vec | None = None,
    ) -> None:
        """Set a collider's pose [m] / velocity [m/s, rad/s] from the next step on (None = keep current)."""
        c = self.model.collider_index(scene, index)
        entry = self._pending.setdefault(c, {})
        for key, val, size in (
            ("pos", position_m, 3),
            ("rot", rotation_xyzw, 4),
            ("lin", linear_velocity_m_per_s, 3),
            ("ang", angular_velocity_rad_per_s, 3),
        ):
            if val is not None:
                arr = np.asarray(val, dtype=np.float64).reshape(size)
                if not np.all(np.isfinite(arr)):
                    raise InputError(f"collider {key} must be finite")
                entry[key] = arr
        self._dirty = True

    def set_grid_velocity(self, scene: int, velocity_m_per_s: Vec) -> None:
        """Move scene's grid lattice at this velocity [m/s] from the next step on (0: the lattice stays where it is).

        Grid contact sees a collider's surface only at nodes, so a collider that crosses lattice planes while it holds
        material (a gripper carrying an object) releases and re-grips a node layer at every crossing and its squeeze
        leaks away; a lattice moving with the gripper keeps the contact geometry fixed. MLS-MPM keeps no grid state
        between steps, so a moving lattice changes nothing else.
        """
        v = np.asarray(velocity_m_per_s, dtype=np.float64).reshape(3)
        if not np.all(np.isfinite(v)):
            raise InputError("grid velocity must be finite")
        if scene not in self._slide_pending and np.array_equal(v / self.model.dx, self.slide_vel[scene]):
            return  # unchanged: nothing to re-anchor or upload
        self._slide_pending[scene] = v
        self._dirty = True

    @property
    def grid_sliding(self) -> bool:
        """Whether any scene's lattice moves (as of the last sync: the solver syncs before it asks)."""
        return self._sliding

    def lattice_shift(self, scene: int, time_s: float) -> np.ndarray:
        """Host evaluation of a scene's lattice offset [cells] in [0, 1) at time t [s] (as the kernels compute it)."""
        a = self.slide_ref[scene] + self.slide_vel[scene] * (time_s - self.slide_time[scene])
        return a - np.floor(a)

    def set_gravity(self, scene: int, gravity_m_per_s2: Vec) -> None:
        """Set a scene's gravity vector [m/s^2] from the next step on."""
        g = np.asarray(gravity_m_per_s2, dtype=np.float64).reshape(3)
        if not np.all(np.isfinite(g)):
            raise InputError("gravity must be finite")
        self.gravity[scene] = g
        self._dirty = True

    # -- queries -------------------------------------------------------------------------------------------------
    def collider_pose(self, c: int, time_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Host evaluation of collider c's pose (position [m], quaternion xyzw) at time t [s]."""
        t = time_s - self.ref_time[c]
        pos = self.ref_pos[c] + self.lin_vel[c] * t
        w = self.ang_vel[c]
        wl = float(np.linalg.norm(w))
        q = self.ref_rot[c]
        if wl > 0:
            half = 0.5 * wl * t
            dq = np.concatenate([w / wl * math.sin(half), [math.cos(half)]])
            q = _quat_mul(dq, q)
            q = q / np.linalg.norm(q)
        return pos, q

    def max_collider_speed(self, reach_m: float) -> float:
        """Upper bound of collider surface speed [m/s] within reach_m of each collider's origin."""
        if self.model.n_colliders == 0:
            return 0.0
        lin = np.linalg.norm(self.lin_vel, axis=1)
        ang = np.linalg.norm(self.ang_vel, axis=1)
        return float(np.max(lin + ang * reach_m))

    # -- device sync ---------------------------------------------------------------------------------------------
    def sync(self, time_s: float) -> None:
        """Apply pending changes, anchored at simulation time time_s [s], and upload to the device."""
        if not self._dirty:
            return
        for c, entry in self._pending.items():
            pos, rot = self.collider_pose(c, time_s)
            self.ref_pos[c] = entry.get("pos", pos)
            q = entry.get("rot", rot)
            qn = float(np.linalg.norm(q))
            if qn < 1e-9:
                raise InputError("collider rotation quaternion must be non-zero")
            self.ref_rot[c] = q / qn
            self.ref_time[c] = time_s
            if "lin" in entry:
                self.lin_vel[c] = entry["lin"]
            if "ang" in entry:
                self.ang_vel[c] = entry["ang"]
        self._pending.clear()
        if self._slide_pending:
            for sc, v in self._slide_pending.items():
                self.slide_ref[sc] = self.lattice_shift(sc, time_s)
                self.slide_time[sc] = time_s
                self.slide_vel[sc] = v / self.model.dx
            self._slide_pending.clear()
            self._sliding = bool(np.any(self.slide_vel != 0.0))
            table = np.zeros((self.model.n_scenes, 8))
            table[:, :3], table[:, 3], table[:, 4:7] = self.slide_ref, self.slide_time, self.slide_vel
            self.d_grid_slide.assign(table.reshape(-1))
        n = self.model.n_colliders
        if n:
            self.d_ref_pos.assign(self.ref_pos.astype(np.float32))
            self.d_ref_rot.assign(self.ref_rot.astype(np.float32))
            self.d_ref_time.assign(self.ref_time)
            self.d_lin_vel.assign(self.lin_vel.astype(np.float32))
            self.d_ang_vel.assign(self.ang_vel.astype(np.float32))
        self.d_gravity.assign(self.gravity.astype(np.float32))
        self._dirty = False
