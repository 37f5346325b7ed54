"""L3 robot: the Franka Panda's kinematics with a gripper on its flange (contracts/grippers), the Planner's gripper
choice, grasp selection, the hold force and squeeze range, and the timed pick-and-place plan (no MPM here).

Typical use (asset frame = table frame at the object, metres):
    choice = choose_gripper(surface_points, outward_normals, center_of_mass, mu, E, nu, mass)   # tasks.robot.choice
    selection = select_grasps(surface_points, outward_normals, center_of_mass, friction=mu,
                              settings=GraspSettings(gripper=choice.name))
    plan = ActionPlan(grasp=selection.best(), gripper=choice.name, squeeze_depth_m=..., grip_force_limit_n=...,
                      target_xy_m=...)
    traj = plan_trajectory(plan, object_height_m=top_z)
    left, right = traj.finger_pads(t)      # box colliders: pose, half extents, linear/angular velocity
"""

from tasks.robot.grasp import GraspSelection, GraspSettings, NoGraspError, select_grasps
from tasks.robot.panda import Panda, UnreachableError, pad_geometry
from tasks.robot.trajectory import (PHASES, FingerPad, ObjectPose, PadArrays, PlaceApproach, RobotState, Trajectory,
                                    plan_trajectory)

__all__ = [
    "GraspSelection", "GraspSettings", "NoGraspError", "select_grasps", "Panda", "UnreachableError", "pad_geometry",
    "PHASES", "FingerPad", "ObjectPose", "PadArrays", "PlaceApproach", "RobotState", "Trajectory", "plan_trajectory",
]
