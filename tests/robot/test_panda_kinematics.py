"""Panda kinematics: IK verified by FK across grasp poses, coupled fingers, measured pads, a clear unreachable error."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.robot.panda import Panda, UnreachableError, grasp_rotation, pad_geometry, rotation_error


@pytest.fixture(scope="module")
def panda():
    with Panda() as robot:
        yield robot


def _grasp_poses() -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Grasp centres over the table workspace with varied closing yaw and approach tilt (up to 30 deg)."""
    rng = np.random.default_rng(3)
    poses = []
    for x in (-0.15, 0.0, 0.15, 0.25):
        for y in (-0.25, 0.0, 0.25):
            for z in (0.015, 0.08, 0.2):
                yaw = rng.uniform(-np.pi / 2, np.pi / 2)
                tilt = rng.uniform(0.0, np.radians(30.0))
                u = np.array([np.cos(yaw) * np.cos(tilt), np.sin(yaw) * np.cos(tilt), np.sin(tilt)])
                a = np.array([0.0, 0.0, -1.0]) - u * (-u[2])
                poses.append((np.array([x, y, z]), u, a / np.linalg.norm(a)))
    return poses


def test_fk_of_ik_matches_grasp_frames_within_1mm_and_2deg(panda: Panda) -> None:
    for center, u, a in _grasp_poses():
        sol = panda.solve_grasp_ik(center, u, a)
        rot = grasp_rotation(u, a)
        p, r = panda.ee_pose(sol.q)  # independent FK at the returned angles
        assert np.linalg.norm(p - panda.ee_target_for_grasp(center, rot)) < 1e-3
        assert np.degrees(np.linalg.norm(rotation_error(rot, r))) < 2.0
        assert sol.position_error_m < 1e-3 and np.degrees(sol.rotation_error_rad) < 2.0
        assert np.all(sol.q >= panda.lower - 1e-9) and np.all(sol.q <= panda.upper + 1e-9)
        panda.set_joints(sol.q, 0.06)
        left, right = panda.pad_states()
        faces = [left[0] - left[1][:, 1] * pad_geometry().half_extents_m[1],
                 right[0] + right[1][:, 1] * pad_geometry().half_extents_m[1]]
        assert np.linalg.norm(0.5 * (faces[0] + faces[1]) - center) < 1e-3  # pads centred on the grasp centre


def test_fingers_are_coupled_and_faces_are_the_opening_apart(panda: Panda) -> None:
    sol = panda.solve_grasp_ik((0.05, 0.05, 0.05), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0))
    for opening in (0.0, 0.023, 0.05, 0.08):
        panda.set_joints(sol.q, opening)
        j9, j10 = panda.finger_positions()
        assert j9 == pytest.approx(opening / 2) and j10 == pytest.approx(opening / 2)
        left, right = panda.pad_states()
        h = pad_geometry().half_extents_m[1]
        gap = (right[0] + right[1][:, 1] * h) - (left[0] - left[1][:, 1] * h)
        assert float(-gap @ left[1][:, 1]) == pytest.approx(opening, abs=1e-6)  # along the closing axis
        assert np.linalg.norm(gap) == pytest.approx(opening, abs=1e-4)


def test_pad_box_measured_from_the_finger_mesh() -> None:
    pad = pad_geometry()
    assert pad.half_extents_m == pytest.approx((0.0087, 0.004, 0.0088), abs=5e-4)
    assert 0.1 < pad.depth_in_hand_m < 0.105  # pad centres sit just short of the grasp-target frame


def test_unreachable_target_gives_a_clear_error(panda: Panda) -> None:
    with pytest.raises(UnreachableError, match="cannot reach .* best residual"):
        panda.solve_grasp_ik((1.5, 0.0, 0.1), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0))


def test_thicker_pads_grow_outward_and_keep_the_gripping_faces() -> None:
    with Panda(pad_half_thickness_m=0.01) as robot:
        sol = robot.solve_grasp_ik((0.0, 0.1, 0.04), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0))
        robot.set_joints(sol.q, 0.05)
        left, right = robot.pad_states()
        assert robot.pads.half_extents_m[1] == 0.01
        faces = [left[0] - left[1][:, 1] * 0.01, right[0] + right[1][:, 1] * 0.01]
        assert float((faces[1] - faces[0]) @ -left[1][:, 1]) == pytest.approx(0.05, abs=1e-6)
        assert np.linalg.norm(0.5 * (faces[0] + faces[1]) - (0.0, 0.1, 0.04)) < 1e-3
