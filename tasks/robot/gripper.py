"""A gripper on the Panda's flange as geometry: its pads and collision boxes in the TCP frame (SI units).

The TCP frame is the midpoint of the two pad faces: z along the approach, y towards finger 0 (the left finger), x = y
cross z. The Franka Hand (``urdf_hand``) is measured from the pybullet_data URDF's collision meshes
(``tasks.robot.franka_hand.pad_geometry`` / ``hand_boxes_in_hand_frame``); any other gripper comes from its record in
contracts/grippers/*.yaml.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from contracts.robot import DEFAULT_GRIPPER, GripperSpec, load_gripper
from tasks.robot.franka_hand import hand_boxes_in_hand_frame, pad_geometry

Box = tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Gripper:
    """A gripper's spec with its pad face and collision boxes in the TCP frame."""

    spec: GripperSpec
    pad_half_extents_m: tuple[float, float, float]  # face half width (x), half thickness (y), face half height (z)
    tip_beyond_center_m: float                       # fingertip past the pad-face centre along the approach [m]
    tcp_beyond_pad_center_m: float                   # URDF grasp target past the pad centres (0 for data grippers)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def stroke_m(self) -> float:
        """Largest opening between the pad faces [m]."""
        return self.spec.stroke_m

    @property
    def pad_face_m(self) -> float:
        """Smaller side of the pad face [m] (what the MPM grid must resolve)."""
        return 2.0 * min(self.pad_half_extents_m[0], self.pad_half_extents_m[2])

    @property
    def pad_area_m2(self) -> float:
        """Area of one pad face [m^2]."""
        return 4.0 * self.pad_half_extents_m[0] * self.pad_half_extents_m[2]

    def boxes(self, opening_m: float) -> tuple[Box, ...]:
        """(lo, hi) boxes [m] in the TCP frame covering the body (palm) and both fingers at an opening [m]."""
        return _boxes(self.name, round(float(opening_m), 6))


def _franka_boxes(opening_m: float) -> tuple[Box, ...]:
    """The Franka Hand's boxes from its meshes, moved from the hand frame to the TCP (pad-centre) frame."""
    dz = np.array([0.0, 0.0, pad_geometry().depth_in_hand_m])
    return tuple((lo - dz, hi - dz) for lo, hi in hand_boxes_in_hand_frame(opening_m))


@lru_cache(maxsize=32)
def _boxes(name: str, opening_m: float) -> tuple[Box, ...]:
    """Collision boxes of a gripper at an opening (cached per name and opening)."""
    g = gripper(name)
    s = g.spec
    if s.urdf_hand:
        return _franka_boxes(opening_m)
    assert s.palm_box and s.finger_half_width_m and s.finger_thickness_m and s.finger_top_m is not None
    palm = (np.asarray(s.palm_box.lo_m, dtype=float), np.asarray(s.palm_box.hi_m, dtype=float))
    half, tip = s.finger_half_width_m, g.tip_beyond_center_m
    left = (np.array([-half, opening_m / 2.0, s.finger_top_m]),
            np.array([half, opening_m / 2.0 + s.finger_thickness_m, tip]))
    right = (np.array([-half, -opening_m / 2.0 - s.finger_thickness_m, s.finger_top_m]),
             np.array([half, -opening_m / 2.0, tip]))
    return (palm, left, right)


@lru_cache(maxsize=8)
def gripper(name: str = DEFAULT_GRIPPER) -> Gripper:
    """The packaged gripper ``name`` with its geometry (InputError for an unknown name)."""
    spec = load_gripper(name)
    if spec.urdf_hand:
        pad = pad_geometry()
        return Gripper(spec, tuple(pad.half_extents_m), pad.tip_beyond_center_m,  # type: ignore[arg-type]
                       spec.tcp_offset_m - pad.depth_in_hand_m)
    assert spec.pad is not None
    return Gripper(spec, (spec.pad.width_m / 2.0, 0.004, spec.pad.height_m / 2.0), spec.pad.tip_beyond_center_m, 0.0)


def lowest_box_point(boxes: tuple[Box, ...], position_m: np.ndarray, rotation: np.ndarray) -> float:
    """Lowest world z [m] of boxes given in a frame at ``position_m`` with ``rotation`` (columns = frame axes)."""
    low = np.inf
    for lo, hi in boxes:
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        low = min(low, float(np.min((corners @ rotation.T)[:, 2])))
    return float(position_m[2]) + low


__all__ = ["Gripper", "gripper", "lowest_box_point"]
