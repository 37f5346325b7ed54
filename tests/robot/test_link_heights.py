"""The robot's clearance above the table is measured on its collision meshes, as the grasp selector measures it.

pybullet's AABB pads every mesh by Bullet's 4 mm collision margin: a grasp whose fingertips clear the table by the
selector's 3 mm margin was refused by the planner as "0.9 mm into the table" (eval C, kitchen sponge, grasp rank 0).
"""

from __future__ import annotations

import numpy as np
import pytest

from contracts.robot import ActionPlan, GraspCandidate
from tasks.robot.grasp import GraspSettings, _lowest_finger_point
from tasks.robot.panda import FINGER_LINKS, Panda, grasp_rotation, pad_geometry
from tasks.robot.trajectory import plan_trajectory


@pytest.fixture(scope="module")
def panda() -> Panda:
    p = Panda()
    yield p
    p.close()


def test_fingertips_are_the_finger_mesh_tip_below_the_pad_centre(panda: Panda) -> None:
    centre = np.array([0.0, 0.0, 0.02])
    rot = grasp_rotation(np.array([0.0, -1.0, 0.0]), np.array([0.0, 0.0, -1.0]))
    panda.set_joints(panda.solve_ik(panda.ee_target_for_grasp(centre, rot), rot).q, 0.06)
    tips = panda.link_heights(FINGER_LINKS)
    # the finger mesh reaches tip_beyond_center_m past the pad centre along the approach (straight down here)
    assert tips == pytest.approx(centre[2] - pad_geometry().tip_beyond_center_m, abs=2e-4)


def test_a_grasp_the_selector_keeps_clear_of_the_table_can_be_planned() -> None:
    tip = pad_geometry().tip_beyond_center_m
    margin = GraspSettings().table_margin_m
    centre = (0.0, 0.0, tip + margin + 1e-4)  # fingertips 3.1 mm above the table: accepted by the grasp selector
    grasp = GraspCandidate(center_m=centre, closing_axis=(0.0, 1.0, 0.0), approach_axis=(0.0, 0.0, -1.0),
                           width_m=0.05, friction_cone_ok=True, score=0.0, rank=0)
    lowest = _lowest_finger_point(np.asarray(centre), np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, -1.0]), 0.05)
    assert lowest >= margin
    traj = plan_trajectory(ActionPlan(grasp=grasp, squeeze_depth_m=0.002, target_xy_m=(0.08, 0.06)),
                           object_height_m=0.03)
    assert traj.min_robot_height_m == pytest.approx(lowest, abs=5e-4)
