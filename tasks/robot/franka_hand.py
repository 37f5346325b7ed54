"""The Franka Hand's geometry, measured from pybullet_data's Panda collision meshes: the finger pads and the boxes
that cover the palm and fingers (tasks/robot/panda.py mounts it; tasks/robot/gripper.py turns it into a Gripper)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
import pybullet_data


@dataclass(frozen=True)
class PadGeometry:
    """A finger pad as a box in its finger link's frame: centre [m] and half extents [m] (x, y, z of the link)."""

    center_left_m: tuple[float, float, float]
    center_right_m: tuple[float, float, float]
    half_extents_m: tuple[float, float, float]
    finger_origin_in_hand_m: float
    tip_beyond_center_m: float

    @property
    def depth_in_hand_m(self) -> float:
        """Distance of the pad centres from the hand frame along the approach axis [m]."""
        return self.finger_origin_in_hand_m + self.center_left_m[2]


def data_path() -> Path:
    """Folder of pybullet_data."""
    return Path(pybullet_data.getDataPath())


@lru_cache(maxsize=1)
def pad_geometry(half_thickness_m: float = 0.004) -> PadGeometry:
    """Measure the finger pad from the Panda's finger collision mesh: the flat inner face at the fingertip.

    The inner (gripping) face is the set of collision vertices on the plane y ~ 0 of the finger link; its x and z
    ranges give the pad's face, and the box extends ``half_thickness_m * 2`` outward (+y of the left finger link).
    The face is put on the finger joint's plane y = 0 (the mesh overhangs it by 0.13 mm), so the distance between the
    two gripping faces equals the commanded opening.
    """
    import trimesh

    mesh = trimesh.load(data_path() / "franka_panda/meshes/collision/finger.obj", force="mesh")
    v = np.asarray(mesh.vertices)
    face = v[np.abs(v[:, 1] - v[:, 1].min()) < 5e-4]
    face = face[face[:, 2] > 0.5 * v[:, 2].max()]  # the fingertip half, where the inner face is flat
    lo, hi = face.min(axis=0), face.max(axis=0)
    cx, cz = 0.5 * (lo[0] + hi[0]), 0.5 * (lo[2] + hi[2])
    half = (0.5 * (hi[0] - lo[0]), half_thickness_m, 0.5 * (hi[2] - lo[2]))
    y0 = 0.0
    # the right finger's collision mesh is the left one turned by pi about z
    return PadGeometry(
        center_left_m=(float(cx), y0 + half_thickness_m, float(cz)),
        center_right_m=(float(-cx), -(y0 + half_thickness_m), float(cz)),
        half_extents_m=(float(half[0]), float(half[1]), float(half[2])),
        finger_origin_in_hand_m=0.0584,
        tip_beyond_center_m=float(v[:, 2].max() - cz),
    )


@lru_cache(maxsize=8)
def hand_boxes_in_hand_frame(opening_m: float) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """Axis-aligned boxes (lo, hi) [m] in the hand frame that cover the palm and both fingers at an opening [m].

    From the collision meshes' bounds: the palm, and each finger (conservative: the box also covers the recess of
    the finger's inner face above the pad), the right finger mirrored in x and y.
    """
    import trimesh

    root = data_path() / "franka_panda/meshes/collision"
    palm = np.asarray(trimesh.load(root / "hand.obj", force="mesh").bounds)
    lo, hi = np.asarray(trimesh.load(root / "finger.obj", force="mesh").bounds)
    z0 = pad_geometry().finger_origin_in_hand_m
    left_lo = np.array([lo[0], opening_m / 2.0, lo[2] + z0])
    left_hi = np.array([hi[0], hi[1] + opening_m / 2.0, hi[2] + z0])
    right_lo = np.array([-left_hi[0], -left_hi[1], left_lo[2]])
    right_hi = np.array([-left_lo[0], -left_lo[1], left_hi[2]])
    return ((palm[0], palm[1]), (left_lo, left_hi), (right_lo, right_hi))
