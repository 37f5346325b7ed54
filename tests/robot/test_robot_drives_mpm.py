"""Slow: the robot's pad boxes, as kinematic MPM colliders, squeeze and lift a soft cube (CPU, ~30 s)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from contracts.material import Material
from contracts.robot import ActionPlan
from contracts.sim import SimConfig
from tasks.robot import plan_trajectory, select_grasps


@pytest.mark.slow
def test_pads_pick_up_a_soft_cube_in_the_mpm() -> None:
    from tasks.mpm.model import box_collider, build_model
    from tasks.mpm.scene import box_scene
    from tasks.mpm.simulator import Simulator

    edge = 0.04
    mesh = trimesh.creation.box((edge,) * 3)
    mesh.apply_translation((0, 0, edge / 2))
    pts, faces = trimesh.sample.sample_surface_even(mesh, 2000, seed=1)
    grasp = select_grasps(pts, mesh.face_normals[faces], mesh.center_mass, friction=1.0).best()
    plan = ActionPlan(grasp=grasp, squeeze_depth_m=0.004, target_xy_m=(0.1, 0.1), closure_duration_s=0.6)
    traj = plan_trajectory(plan, object_height_m=edge)
    t = traj.phases["approach"][1] - 0.05
    start = traj.pad_motion(t, t + 1e-3)
    colliders = [box_collider(traj.pad_half_extents_m, friction=1.0, position_m=tuple(start.position_m[0, k]),
                              rotation_xyzw=tuple(start.quat_xyzw[0, k])) for k in range(2)]
    material = Material(youngs_modulus_pa=2e5, poisson_ratio=0.3, damping_rate_per_s=5.0)
    scene = box_scene((-edge / 2, -edge / 2, 0.0), (edge / 2, edge / 2, edge), 0.0025, material, 500.0,
                      colliders=colliders)
    model = build_model([scene], SimConfig(device="cpu"))
    sim = Simulator(model)
    z0 = float(sim.particles(0)["x"][:, 2].mean())
    dt = 1.0 / 240.0
    squeeze_force = 0.0
    while t < traj.phases["lift"][1]:
        m = traj.pad_motion(t, t + dt)
        for k in range(2):
            sim.control.set_collider(0, k, position_m=m.position_m[0, k], rotation_xyzw=m.quat_xyzw[0, k],
                                     linear_velocity_m_per_s=m.linear_velocity_m_per_s[0, k],
                                     angular_velocity_rad_per_s=m.angular_velocity_rad_per_s[0, k])
        report = sim.advance(dt)
        assert report.health.ok
        if traj.phase_at(t) == "closure":
            squeeze_force = max(squeeze_force, float(np.linalg.norm(report.collider_force(model, 0, 0))))
        t += dt
    z1 = float(sim.particles(0)["x"][:, 2].mean())
    assert squeeze_force > 0.5
    assert z1 - z0 > 0.9 * plan.lift_height_m
