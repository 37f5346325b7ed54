"""The timed pick-and-place: continuous joints, consistent pad velocities, pads on the grasp, phases where planned."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from contracts.robot import ActionPlan, GraspCandidate
from tasks.robot.panda import UnreachableError
from tasks.robot.trajectory import PHASES, ObjectPose, PlaceApproach, Trajectory, plan_trajectory

DT = 1e-3


def _plan(target=(0.12, 0.15), yaw_deg=30.0, squeeze=0.004) -> ActionPlan:
    grasp = GraspCandidate(center_m=(0.0, 0.0, 0.03), closing_axis=(1.0, 0.0, 0.0), approach_axis=(0.0, 0.0, -1.0),
                           width_m=0.05, friction_cone_ok=True, score=0.0, rank=0)
    return ActionPlan(grasp=grasp, squeeze_depth_m=squeeze, target_xy_m=target, initial_yaw_deg=yaw_deg)


@pytest.fixture(scope="module")
def traj() -> Trajectory:
    return plan_trajectory(_plan(), object_height_m=0.06)


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz], axis=-1)


def test_phases_in_order_and_timed_by_the_plan(traj: Trajectory) -> None:
    plan = _plan()
    assert list(traj.phases) == list(PHASES)
    ends = [traj.phases[p] for p in PHASES]
    assert all(a[1] == pytest.approx(b[0]) for a, b in zip(ends, ends[1:]))
    t0, t1 = traj.phases["approach"]
    assert t1 - t0 >= plan.approach_duration_s  # lengthened only to respect joint speed limits
    assert traj.max_joint_speed_ratio <= 1.0
    for name, field in (("lift", "lift_duration_s"),
                        ("transport", "transport_duration_s"), ("release", "release_duration_s")):
        t0, t1 = traj.phases[name]
        assert t1 - t0 == pytest.approx(getattr(plan, field))
    assert traj.phase_at(0.5 * sum(traj.phases["lift"])) == "lift"


def test_joint_positions_are_continuous_and_rates_match(traj: Trajectory) -> None:
    for a, b in zip(traj.segments, traj.segments[1:]):  # no jumps at piece boundaries
        qa, _ = a.arm(a.t1 - a.t0)
        qb, _ = b.arm(0.0)
        assert np.max(np.abs(qa - qb)) < 1e-6
        assert abs(a.fingers(a.t1 - a.t0)[0] - b.fingers(0.0)[0]) < 1e-9
    ts = np.arange(0.0, traj.duration_s, DT)
    states = [traj.state_at(float(t)) for t in ts]
    q = np.array([s.q for s in states])
    qdot = np.array([s.qdot for s in states])
    assert np.max(np.abs(np.diff(q, axis=0))) < 5e-3  # < 5 rad/s anywhere
    fd = (q[2:] - q[:-2]) / (2 * DT)
    assert np.max(np.abs(fd - qdot[1:-1])) < 0.02
    w = np.array([s.finger_opening_m for s in states])
    assert np.all(w >= 0.0) and np.all(w <= 0.08)
    assert np.max(np.abs(np.diff(w))) < 1e-3


def test_pad_velocity_is_the_derivative_of_the_pad_pose(traj: Trajectory) -> None:
    ts = np.arange(DT, traj.duration_s - DT, 7 * DT)
    now, ahead, back = traj.pads_at(ts), traj.pads_at(ts + 1e-4), traj.pads_at(ts - 1e-4)
    v_fd = (ahead.position_m - back.position_m) / 2e-4
    scale = np.abs(now.linear_velocity_m_per_s).max()
    assert scale > 0.1
    assert np.max(np.abs(v_fd - now.linear_velocity_m_per_s)) < 1e-3
    conj = back.quat_xyzw * np.array([-1, -1, -1, 1])
    dq = _quat_mul(ahead.quat_xyzw, conj)  # rotation over 2e-4 s, world frame
    dq *= np.sign(dq[..., 3:4])
    w_fd = 2.0 * dq[..., :3] / 2e-4
    assert np.abs(now.angular_velocity_rad_per_s).max() > 0.5
    assert np.max(np.abs(w_fd - now.angular_velocity_rad_per_s)) < 2e-3


def test_pads_sit_on_the_grasp_at_contact_and_squeeze_after(traj: Trajectory) -> None:
    left, right = traj.finger_pads(traj.contact_time_s)
    c, u = traj.grasp_center_world_m, traj.closing_axis_world
    assert np.linalg.norm(left.contact_point_m - (c - u * 0.025)) < 5e-4
    assert np.linalg.norm(right.contact_point_m - (c + u * 0.025)) < 5e-4
    assert left.normal @ u == pytest.approx(1.0) and right.normal @ u == pytest.approx(-1.0)
    end = traj.phases["closure"][1]
    assert traj.state_at(end - 1e-3).finger_opening_m == pytest.approx(0.05 - 2 * 0.004)
    speed = abs(traj.state_at(0.5 * (traj.phases["closure"][0] + traj.contact_time_s)).finger_opening_rate_m_per_s)
    assert speed == pytest.approx(2 * 0.02)  # each finger at the plan's closing speed
    lifted = traj.finger_pads(traj.phases["lift"][1])
    assert 0.5 * (lifted[0].position_m + lifted[1].position_m) == pytest.approx(c + [0, 0, 0.10], abs=5e-4)
    placed = traj.finger_pads(traj.phases["release"][0])
    expect = c + np.array([0.12, 0.15, 0.01])
    assert 0.5 * (placed[0].position_m + placed[1].position_m) == pytest.approx(expect, abs=5e-4)
    assert np.linalg.norm(placed[0].linear_velocity_m_per_s) < 1e-3


def test_closing_axis_follows_object_yaw_and_robot_stays_above_table(traj: Trajectory) -> None:
    yaw = np.radians(30.0)
    assert abs(traj.closing_axis_world @ [np.cos(yaw), np.sin(yaw), 0.0]) == pytest.approx(1.0)
    assert traj.ik_max_position_error_m < 1e-3 and np.degrees(traj.ik_max_rotation_error_rad) < 2.0
    assert traj.min_robot_height_m >= 0.0
    pads = traj.pads_at(np.arange(0.0, traj.duration_s, 0.01))
    corners_z = pads.position_m[..., 2] - np.abs(pads.half_extents_m).sum(axis=-1)  # conservative lowest corner
    assert corners_z.min() > 0.0
    start = traj.finger_pads(0.0)[0].position_m
    assert start[2] > 0.2  # starts well above the object


def test_pad_motion_lands_constant_velocity_colliders_on_the_plan(traj: Trajectory) -> None:
    for t0 in (0.3, traj.contact_time_s, 2.5, 3.7, 5.2):
        dt = 2e-3
        m = traj.pad_motion(t0, t0 + dt)
        end = traj.pads_at(np.array([t0 + dt]))
        assert np.allclose(m.position_m + m.linear_velocity_m_per_s * dt, end.position_m, atol=1e-12)
        w = m.angular_velocity_rad_per_s[0]  # exp(w dt) q0, as the MPM's Control integrates it
        wl = np.linalg.norm(w, axis=-1, keepdims=True)
        dq = np.concatenate([np.where(wl > 0, w / np.maximum(wl, 1e-300), 0) * np.sin(0.5 * wl * dt),
                             np.cos(0.5 * wl * dt)], axis=-1)
        q1 = _quat_mul(dq, m.quat_xyzw[0])
        assert np.allclose(np.abs(np.sum(q1 * end.quat_xyzw[0], axis=-1)), 1.0, atol=1e-10)
        inst = traj.pads_at(np.array([t0 + 0.5 * dt]))
        assert np.allclose(m.linear_velocity_m_per_s, inst.linear_velocity_m_per_s, atol=2e-3)
        assert np.allclose(m.angular_velocity_rad_per_s, inst.angular_velocity_rad_per_s, atol=1e-2)


def test_finger_pads_are_table_lookups_without_kinematics(traj: Trajectory, monkeypatch: pytest.MonkeyPatch) -> None:
    """The trial reads the pads every MPM step: finger_pads and pads_at interpolate the table plan_trajectory filled
    once (pybullet FK at table_dt_s), with no pybullet call, no robot kinematics and no evaluation of the plan's
    pieces per step. (Their seconds per step: `python -m benchmarks.pads_bench --json`.)"""
    import inspect

    from tasks.quiet_pybullet import pybullet as pb
    from tasks.robot.panda import Panda, _quat_to_matrix

    calls: list[str] = []

    def counted(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def call(*args: Any, **kwargs: Any) -> Any:
            calls.append(name)
            return fn(*args, **kwargs)
        return call

    for name in dir(pb):
        fn = getattr(pb, name)
        if not name.startswith("_") and callable(fn) and not isinstance(fn, type):
            monkeypatch.setattr(pb, name, counted(f"pybullet.{name}", fn))
    for name, fn in vars(Panda).items():
        if inspect.isfunction(fn) and not name.startswith("__"):
            monkeypatch.setattr(Panda, name, counted(f"Panda.{name}", fn))
    for name in ("state_at", "_segment"):
        monkeypatch.setattr(Trajectory, name, counted(f"Trajectory.{name}", getattr(Trajectory, name)))
    _quat_to_matrix([0.0, 0.0, 0.0, 1.0])
    assert calls == ["pybullet.getMatrixFromQuaternion"]  # the counting sees pybullet calls made from tasks.robot
    calls.clear()

    times = np.arange(2000) * 3.1e-3
    pads = [traj.finger_pads(float(t)) for t in times]
    batch = traj.pads_at(times)
    assert calls == [], sorted(set(calls))
    # what they return is the table, interpolated: at a sample time, the stored pad pose and velocity
    table = traj._table
    for k in (0, 7, len(table["t"]) // 2, len(table["t"]) - 2):
        for f, pad in enumerate(traj.finger_pads(float(table["t"][k]))):
            assert np.allclose(pad.position_m, table["pos"][k, f], atol=1e-12)
            assert np.allclose(pad.linear_velocity_m_per_s, table["vel"][k, f], atol=1e-12)
    assert calls == []
    for k in (1, 999, 1999):
        assert np.allclose([p.position_m for p in pads[k]], batch.position_m[k])


def test_unreachable_target_raises_a_clear_error() -> None:
    with pytest.raises(UnreachableError, match="cannot reach"):
        plan_trajectory(_plan(target=(1.2, 0.0)), ObjectPose((0.0, 0.0), 0.0), object_height_m=0.06)


def test_selected_grasp_runs_clear_of_the_object_until_contact() -> None:
    import trimesh

    from tasks.robot.grasp import select_grasps

    mesh = trimesh.creation.box((0.05, 0.12, 0.06))
    mesh.apply_translation((0, 0, 0.03))
    pts, faces = trimesh.sample.sample_surface_even(mesh, 2500, seed=1)
    grasp = select_grasps(pts, mesh.face_normals[faces], mesh.center_mass, friction=0.5).best()
    plan = ActionPlan(grasp=grasp, squeeze_depth_m=0.003, target_xy_m=(0.1, -0.2), initial_yaw_deg=-60.0)
    pose = ObjectPose((0.02, 0.03), -60.0)
    tr = plan_trajectory(plan, pose, object_height_m=0.06)
    world = pose.point_to_world(pts)
    ts = np.arange(0.0, tr.contact_time_s - 0.01, 0.01)
    pads = tr.pads_at(ts)
    for k in range(len(ts)):
        for f in range(2):
            rot = np.array(tr.finger_pads(ts[k])[f].rotation)
            local = (world - pads.position_m[k, f]) @ rot
            assert not np.any(np.all(np.abs(local) < pads.half_extents_m[k, f], axis=1)), (ts[k], f)
    left, right = tr.finger_pads(tr.phases["closure"][1] - 1e-3)
    squeeze = np.linalg.norm(right.contact_point_m - left.contact_point_m)
    assert squeeze == pytest.approx(grasp.width_m - 2 * 0.003, abs=1e-4)


def test_a_guarded_place_lowers_slowly_at_the_end_and_stops_where_the_table_took_the_object(traj: Trajectory
                                                                                            ) -> None:
    """PlaceApproach: the last 3 cm at 0.1 m/s; a stop inside it: the plan is unchanged up to the stop, the hand brakes
    to rest within the brake time above the planned place height, and release, retreat and settle follow from there."""
    guarded = plan_trajectory(_plan(), object_height_m=0.06, place=PlaceApproach(height_m=0.03, speed_m_per_s=0.1))
    lo, hi = guarded.lower_window_s
    t_slow = 0.03 / 0.1 + 0.02  # ramped_travel_time
    assert guarded.phases["transport"][1] - guarded.phases["transport"][0] == pytest.approx(
        _plan().transport_duration_s + t_slow)
    assert np.allclose(guarded.place_center_world_m, traj.place_center_world_m, atol=1e-9)
    pads = guarded.pads_at(np.array([hi - t_slow + 0.05, hi - 0.05]))
    assert np.allclose(pads.linear_velocity_m_per_s[:, :, 2], -0.1, atol=0.005)  # the guarded part: 0.1 m/s down
    t_stop = hi - 0.5 * t_slow
    stopped = plan_trajectory(_plan(), object_height_m=0.06,
                              place=PlaceApproach(height_m=0.03, speed_m_per_s=0.1, stop_s=t_stop, brake_s=0.02))
    assert stopped.place_stopped_s == t_stop and guarded.place_stopped_s is None
    for t in np.arange(0.0, t_stop, 0.05):
        assert np.allclose(stopped.state_at(float(t)).q, guarded.state_at(float(t)).q, atol=1e-9)
    assert stopped.lower_window_s[1] == pytest.approx(t_stop + 0.02) == pytest.approx(stopped.phases["release"][0])
    assert np.max(np.abs(stopped.state_at(stopped.phases["release"][0]).qdot)) < 1e-9
    speeds = [np.max(np.abs(stopped.state_at(float(t)).qdot)) for t in np.arange(t_stop, t_stop + 0.02, 0.002)]
    assert all(b <= a + 1e-9 for a, b in zip(speeds, speeds[1:]))  # it only slows down
    drop = stopped.place_center_world_m[2] - traj.place_center_world_m[2]
    covered = 0.5 * 0.1 * 0.02 + 0.1 * (0.5 * t_slow - 0.02) + 0.5 * 0.1 * 0.02  # ramp, cruise, brake [m]
    assert drop == pytest.approx(0.03 - covered, abs=5e-4)
    rel = stopped.pads_at(np.array(stopped.phases["release"]))
    assert np.allclose(rel.position_m[0].mean(axis=0), rel.position_m[1].mean(axis=0), atol=1e-5)  # the hand waits
    assert stopped.duration_s < guarded.duration_s
    late = plan_trajectory(_plan(), object_height_m=0.06, place=PlaceApproach(height_m=0.03, stop_s=hi + 0.01))
    assert late.place_stopped_s is None and late.duration_s == pytest.approx(guarded.duration_s)
