"""A synthetic attempt for the render and recording tests: the robot follows a real planned trajectory (pybullet IK),
the object (a box_body cube) stays at rest; the arrays have the layout of tasks.manipulation.data. No MPM."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from contracts.robot import ActionPlan
from tasks.manipulation.body import box_body
from tasks.manipulation.data import approach_track
from tasks.manipulation.trial import object_pose, world_gaussians
from tasks.robot import PHASES, plan_trajectory, select_grasps

CONTROL_HZ = 240.0
RECORD_FPS = 30.0


def synthetic_attempt(edge_m: float = 0.03, spacing_m: float = 0.005, approach_s: float | None = None,
                      end_s: float | None = None, gripper: str | None = None,
                      force_n: float = 2.0) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Arrays and attributes of a pick-and-place attempt of a cube at rest: simulated part from the closure's start to
    end_s [s] (default: the whole plan), the recorded approach's last approach_s [s] (default: all of it) and a
    constant force_n [N] on each finger while it closes and holds."""
    body = box_body(edge_m, spacing_m, gaussians_per_face=100)
    grasp = select_grasps(body.surface_points_m, body.surface_normals, np.array([0.0, 0.0, edge_m / 2]), 0.8).best()
    kw: dict[str, Any] = dict(grasp=grasp, squeeze_depth_m=0.003, target_xy_m=(0.08, 0.06), lift_height_m=0.05,
                              closing_speed_m_per_s=0.04, closure_duration_s=0.3, lift_duration_s=0.4,
                              transport_duration_s=0.6, release_duration_s=0.2, retreat_duration_s=0.2,
                              settle_duration_s=0.2)
    if gripper:
        kw["gripper"] = gripper
    plan = ActionPlan(**kw)
    pose = object_pose(plan)
    traj = plan_trajectory(plan, object_pose=pose, object_height_m=body.height_m, pad_half_thickness_m=0.01)
    t0 = traj.phases["closure"][0]
    t_c = np.arange(t0, traj.duration_s if end_s is None else end_s, 1.0 / CONTROL_HZ)
    states = [traj.state_at(float(t)) for t in t_c]
    pads = traj.pads_at(t_c)
    phase = np.array([PHASES.index(s.phase) for s in states], np.int8)
    holding = np.isin(phase, [PHASES.index(p) for p in ("closure", "lift", "transport")])
    force = np.zeros((len(t_c), 2, 3))
    axis = np.asarray(traj.closing_axis_world)
    force[holding, 0], force[holding, 1] = -force_n * axis, force_n * axis
    x0 = pose.point_to_world(body.particles_m)
    k_frames = np.arange(0, len(t_c), int(round(CONTROL_HZ / RECORD_FPS)))
    approach = approach_track(traj, t0, RECORD_FPS)
    if approach_s is not None:
        keep = approach["approach_t_s"] >= t0 - approach_s - 1e-9
        approach = {k: v[keep] for k, v in approach.items()}
    arrays = {"control_t_s": t_c, "control_sim_t_s": t_c, "command_q_rad": np.array([s.q for s in states]),
              "command_opening_m": np.array([[s.finger_opening_m, s.finger_opening_rate_m_per_s] for s in states]),
              "phase": phase, "finger_position_m": pads.position_m, "finger_quat_xyzw": pads.quat_xyzw,
              "finger_half_extents_m": np.asarray(traj.pad_half_extents_m), "finger_force_n": force,
              "closing_axis_world": axis, "object_com_m": np.tile(x0.mean(axis=0), (len(t_c) + 1, 1)),
              "frame_t_s": t_c[k_frames], "frame_control_index": k_frames,
              "particles_x_m": np.repeat(x0[None].astype(np.float32), len(k_frames), axis=0),
              "particles_F": np.tile(np.eye(3, dtype=np.float32), (len(k_frames), len(x0), 1, 1)),
              "rest_particles_m": x0.astype(np.float32), **world_gaussians(body, pose), **approach}
    attrs = {"plan": plan.model_dump(mode="json"), "labels": {"lifted": 0.0}, "role": "selection", "attempt": 0}
    return arrays, attrs


def short_attempt(approach_s: float, length_s: float) -> tuple[dict[str, np.ndarray], dict]:
    """synthetic_attempt cut to its first length_s seconds of control (states and frames alike)."""
    arrays, attrs = synthetic_attempt(approach_s=approach_s)
    keep = arrays["control_t_s"] < arrays["control_t_s"][0] + length_s
    k_frames = arrays["frame_control_index"] < keep.sum()
    short = dict(arrays, **{k: arrays[k][keep] for k in ("control_t_s", "control_sim_t_s", "command_q_rad",
                                                         "command_opening_m", "phase", "finger_position_m",
                                                         "finger_quat_xyzw", "finger_force_n")},
                 object_com_m=arrays["object_com_m"][:keep.sum() + 1],
                 **{k: arrays[k][k_frames] for k in ("frame_t_s", "frame_control_index", "particles_x_m",
                                                     "particles_F")})
    return short, attrs


def cube_context(root: Path) -> Any:
    """An L3Context on the 3 cm foam cube of synthetic_attempt (no grasps, the packaged contract, cached trials), for
    tests that store trials through L3's _store."""
    from contracts.material import Material
    from contracts.physical import PhysicalModel
    from contracts.stage import load_contract
    from flows.l3_manipulation import CachedTrials, L3Context, L3Options

    body = box_body(0.03, 0.005)
    phys = PhysicalModel(density_kg_per_m3=300.0, volume_m3=body.volume_m3, mass_kg=300.0 * body.volume_m3,
                         particle_count=len(body.particles_m), particle_spacing_m=0.005, ground_friction=0.5,
                         gripper_friction=0.8, center_of_mass_m=(0.0, 0.0, 0.015), extents_m=(0.03,) * 3,
                         category="foam")
    return L3Context(root, body, phys, Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0),
                     "given", [], L3Options(), load_contract("L3"), runner=CachedTrials())
