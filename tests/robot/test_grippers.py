"""Grippers as data (contracts/grippers): their records, their kinematics on the Panda's flange, and the Planner's
choice from the object's width, mass and stiffness."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from contracts.errors import InputError
from contracts.robot import gripper_names, load_gripper
from tasks.robot.choice import choose_gripper
from tasks.robot.grasp import GraspSettings, select_grasps
from tasks.robot.gripper import gripper
from tasks.robot.panda import Panda, pad_geometry
from tasks.robot.squeeze import pad_stiffness_n_per_m, squeeze_plan

PLUSH = dict(youngs_modulus_pa=1e4, poisson_ratio=0.3)


def _box(x: float, y: float, z: float, n: int = 1500) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Surface points, outward normals and centre of a box resting on the table."""
    mesh = trimesh.creation.box((x, y, z))
    mesh.apply_translation((0.0, 0.0, z / 2.0))
    pts, faces = trimesh.sample.sample_surface_even(mesh, n, seed=0)
    return pts, mesh.face_normals[faces], np.array([0.0, 0.0, z / 2.0])


def test_the_packaged_grippers_and_their_strokes() -> None:
    assert {"franka_hand", "robotiq_2f85", "robotiq_2f140"} <= set(gripper_names())
    assert [load_gripper(n).stroke_m for n in ("franka_hand", "robotiq_2f85", "robotiq_2f140")] == [0.08, 0.085, 0.14]
    franka = gripper("franka_hand")  # its pads are the URDF's, measured from the finger mesh as before
    assert franka.pad_half_extents_m == pytest.approx(pad_geometry().half_extents_m)
    for name in gripper_names():
        g = gripper(name)
        assert g.spec.max_grip_force_n > 0 and g.spec.max_closing_speed_m_per_s > 0 and g.spec.mass_kg > 0
        palm, left, right = g.boxes(g.stroke_m)
        assert left[0][1] == pytest.approx(g.stroke_m / 2, abs=1e-3)
        assert right[1][1] == pytest.approx(-g.stroke_m / 2, abs=1e-3)
    with pytest.raises(InputError, match="known grippers"):
        load_gripper("no_such_gripper")


def test_a_data_gripper_rides_on_the_flange_with_its_tcp_and_pads() -> None:
    """IK puts the 2F-140's TCP (pad-face midpoint) on the grasp; the pad faces are the opening apart, across the
    closing axis; the fingertips reach tip_beyond_center below the grasp centre."""
    g = gripper("robotiq_2f140")
    with Panda(gripper="robotiq_2f140") as robot:
        centre = np.array([0.0, 0.0, 0.05])
        sol = robot.solve_grasp_ik(centre, (0.0, 1.0, 0.0), (0.0, 0.0, -1.0))
        robot.set_joints(sol.q, 0.12)
        tcp, rot = robot.ee_pose()
        assert np.linalg.norm(tcp - centre) < 1e-3 and rot[:, 2] == pytest.approx([0.0, 0.0, -1.0], abs=1e-3)
        (p0, r0), (p1, r1) = [(p, r) for p, r, _, _ in robot.pad_states()]
        h = robot.pads.half_extents_m[1]
        faces = [p0 - r0[:, 1] * h, p1 + r1[:, 1] * h]
        assert np.linalg.norm(faces[0] - faces[1]) == pytest.approx(0.12, abs=1e-6)
        assert abs((faces[0] - faces[1]) @ np.array([1.0, 0.0, 0.0])) < 1e-3  # the closing axis is world y
        assert robot.lowest_point() == pytest.approx(centre[2] - g.tip_beyond_center_m, abs=1e-3)
        # the flange carries the gripper 0.215 m behind the TCP
        flange, _ = robot.link_pose(robot.ee_link)
        assert np.linalg.norm(flange - tcp) == pytest.approx(g.spec.tcp_offset_m, abs=1e-6)


def test_a_box_wider_than_the_franka_hand_has_grasps_only_with_the_wide_gripper() -> None:
    pts, nrm, com = _box(0.11, 0.20, 0.06)
    narrow = select_grasps(pts, nrm, com, friction=0.7, settings=GraspSettings(gripper="franka_hand"))
    wide = select_grasps(pts, nrm, com, friction=0.7, settings=GraspSettings(gripper="robotiq_2f140"))
    assert not narrow.ok and "usable opening 76 mm (franka_hand)" in narrow.reason
    assert wide.ok and wide.best().width_m == pytest.approx(0.11, abs=0.005)


@pytest.mark.parametrize("width_m, expected", [(0.04, "franka_hand"), (0.11, "robotiq_2f140"), (0.20, None)])
def test_the_gripper_choice_changes_with_object_width(width_m: float, expected: str | None) -> None:
    """A 100 kPa foam block of 150 g, 16 cm long: 4 cm wide goes in the Franka Hand, 11 cm in the wide gripper, and
    no gripper holds 20 cm."""
    pts, nrm, com = _box(width_m, 0.16, 0.06)
    choice = choose_gripper(pts, nrm, com, friction=0.7, mass_kg=0.15, youngs_modulus_pa=1e5, poisson_ratio=0.3)
    assert choice.name == expected, choice.reason
    if expected is None:
        assert "no gripper can hold the object" in choice.reason
    else:
        assert choice.reason.startswith(expected) and "centre of mass" in choice.reason
        assert [o.name for o in choice.options][0] == "franka_hand"  # the smallest is tried first


def test_the_gripper_choice_weighs_stiffness() -> None:
    """The same 4 cm block as a 10 kPa plush: the Franka Hand's 17 mm pads would have to sink 35 mm per finger to hold
    its 150 g with margin (more than the 40 mm width allows), so a gripper with larger pads is chosen."""
    pts, nrm, com = _box(0.04, 0.16, 0.06)
    choice = choose_gripper(pts, nrm, com, friction=0.7, mass_kg=0.15, **PLUSH)
    assert choice.name not in (None, "franka_hand")
    assert not choice.option("franka_hand").good and "beyond" in choice.option("franka_hand").note


def test_the_squeeze_range_scales_with_stiffness() -> None:
    """The force target is 3 m g / (2 mu) and the estimated squeeze to reach it: sub-millimetre on a 1.5 MPa rubber
    ball in the Franka Hand, centimetres on a 10 kPa plush in the 2F-140."""
    franka, wide = gripper("franka_hand"), gripper("robotiq_2f140")
    rubber = squeeze_plan(1.5e6, 0.45, 0.05, franka.pad_area_m2, 0.04, 9.81, 0.8, 20.0, 70.0)
    plush = squeeze_plan(1e4, 0.3, 0.14, wide.pad_area_m2, 0.15, 9.81, 0.7, 20.0, 125.0)
    assert 2 * 0.7 * plush.force_target_n == pytest.approx(3.0 * 0.15 * 9.81)  # 2 mu N = 3 m g
    assert rubber.force_target_n == 1.0  # the floor: 3 m g / (2 mu) = 0.74 N for 40 g at mu 0.8
    assert rubber.high_m < 1e-3 and plush.depth_m > 0.01 and plush.high_m > 0.02
    assert rubber.depth_m < 2e-4 and plush.low_m < plush.depth_m < plush.high_m
    # linear in E: ten times stiffer, a tenth of the depth
    k1, k10 = (pad_stiffness_n_per_m(e, 0.3, 0.1, wide.pad_area_m2) for e in (1e4, 1e5))
    assert k10 == pytest.approx(10 * k1)
    heavy = squeeze_plan(1e4, 0.3, 0.14, wide.pad_area_m2, 5.0, 9.81, 0.7, 20.0, 125.0)
    assert heavy.force_target_n == 10.0  # capped at half the 20 N budget
