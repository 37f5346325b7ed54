"""The simulation frame of a trial: the world turned about the vertical so that the gripper's closing axis makes a
chosen angle with the MPM grid's x axis.

The MPM grid is axis-aligned, and its node contact sees a pad face parallel to a node layer differently from a face
that cuts the layers at a slant: at draft resolution (a 17 mm pad spans about two nodes) the same grasp could lift or
slip depending only on the object's yaw. A turn about the vertical changes no physics here (isotropic material,
horizontal ground, gravity along -z), so the trial is simulated in a frame where every grasp meets the grid the same
way and everything it reports is turned back into the world frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tasks.robot.trajectory import quat_mul


@dataclass(frozen=True)
class SimFrame:
    """A turn of the world by ``yaw_rad`` about the vertical axis through the origin (world -> simulation)."""

    yaw_rad: float = 0.0

    @classmethod
    def aligned(cls, closing_axis_world: np.ndarray, closing_axis_to_grid_deg: float | None) -> SimFrame:
        """The frame where the closing axis' horizontal part makes ``closing_axis_to_grid_deg`` with the grid's x
        axis; None (or a vertical closing axis) keeps the world frame."""
        c = np.asarray(closing_axis_world, dtype=float)
        if closing_axis_to_grid_deg is None or math.hypot(c[0], c[1]) < 1e-9:
            return cls(0.0)
        return cls(math.radians(closing_axis_to_grid_deg) - math.atan2(c[1], c[0]))

    @property
    def rotation(self) -> np.ndarray:
        """The 3x3 rotation world -> simulation."""
        cz, sz = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])

    @property
    def is_identity(self) -> bool:
        return self.yaw_rad == 0.0

    def to_sim(self, v: np.ndarray) -> np.ndarray:
        """Points or vectors (..., 3), world -> simulation."""
        v = np.asarray(v, dtype=float)
        return v if self.is_identity else v @ self.rotation.T

    def to_world(self, v: np.ndarray) -> np.ndarray:
        """Points or vectors (..., 3), simulation -> world (keeps the dtype)."""
        v = np.asarray(v)
        return v if self.is_identity else (v @ self.rotation.astype(v.dtype))

    def tensor_to_world(self, m: np.ndarray) -> np.ndarray:
        """Second-order tensors (..., 3, 3) such as the deformation gradient, simulation -> world: R^T M R."""
        m = np.asarray(m)
        if self.is_identity:
            return m
        r = self.rotation.astype(m.dtype)
        return np.einsum("ji,...jk,kl->...il", r, m, r)

    def quat_to_sim(self, q_xyzw: np.ndarray) -> np.ndarray:
        """Orientations (..., 4) as (x, y, z, w) quaternions, world -> simulation."""
        if self.is_identity:
            return np.asarray(q_xyzw, dtype=float)
        h = 0.5 * self.yaw_rad
        return quat_mul(np.array([0.0, 0.0, math.sin(h), math.cos(h)]), np.asarray(q_xyzw, dtype=float))


__all__ = ["SimFrame"]
