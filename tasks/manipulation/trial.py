"""One pick-and-place in the MPM: the Panda's finger pads as kinematic box colliders driven from the trajectory.

The simulation starts ``TrialSettings.settle_before_closure_s`` before closure (the object rests on the table, the
open pads already beside it) and runs to the end of the plan (release, retreat, settle), then, with the hand still,
until the object is at rest (the ``settled`` label's test, at most ``settle_until_rest_max_s``). Every control interval
(``control_hz``) the pads are set to the constant-velocity motion that lands on the planned pose at the interval's end
(``Trajectory.pad_motion``); the mean reaction force on each finger over the interval (eq. 3) and its impulse are
recorded with the commanded joint states. Particle states (x, F) are recorded at ``record_fps``. SI units.
"""

from __future__ import annotations

import math
import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from contracts.errors import SimulationError
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan, GraspCandidate
from contracts.sim import SimConfig
from tasks.manipulation.body import TrialBody
from tasks.manipulation.data import approach_track
from tasks.manipulation.diagnosis import mode_flags
from tasks.manipulation.frame import SimFrame
from tasks.manipulation.outcome import TrialTolerances, frame_back, label_trial, turn_rate_deg_per_s
from tasks.mpm import Simulator, build_model, pad_collider
from tasks.mpm.model import SceneSpec
from tasks.robot import PHASES, ObjectPose, PlaceApproach, Trajectory, plan_trajectory
from tasks.robot.grasp import GraspSettings, turned_approaches

PAD_FACES = ("-y", "+y")  # gripping face of the left and right pad boxes in the finger links' axes
CARRY_PHASES = ("lift", "transport")  # the hand holds the object off the table: the grid lattice moves with it
HOLD_PHASES = ("closure", "lift", "transport")  # a force-controlled closure keeps its force target through these


@dataclass(frozen=True)
class TrialSettings:
    """Numerics of one trial (not physics): resolution, time stepping, control and recording rates."""

    device: str = "cpu"
    cpu_threads: int = 1                 # CPU: threads sharing the trial's particles (SimConfig.cpu_threads)
    grid_margin_m: float = 0.02          # free space around the object in the (moving) grid window [m]
    substeps: int = 1                    # numerical revision: dt / substeps, same action durations
    dt_max_s: float = 2e-4               # cap on the adaptive time step [s] at a grid of dt_max_dx_m or finer
    # a coarser grid (the larger pads of a wide gripper allow one) raises the cap in proportion to dx, so a pad moves
    # the same fraction of a cell per step; the CFL limit still applies [m]; None: the cap is dt_max_s at any dx
    dt_max_dx_m: float | None = 0.008
    cfl: float = 0.4
    control_hz: float = 240.0            # pad pose updates and force reports per second
    record_fps: float = 30.0             # particle-state frames per second
    settle_before_closure_s: float = 0.1  # simulated rest before the fingers start closing [s]
    # pad boxes grow outward from the gripping face (the finger body behind it): a box thinner than the squeeze
    # lets the displaced material close behind it (particles leave through its back face) and the grip collapses
    pad_half_thickness_m: float = 0.01
    # a robot aborts a pick whose lift failed: the outcome is decided (not lifted, so not transported or placed), and
    # transport, release, retreat and settle (~half the simulated time) would be spent on a known failure
    stop_when_lift_fails: bool = True
    # ... when the COM rose less than this share of the `lifted` threshold by the lift's end: a soft body hanging from
    # the pads lags the hand and may still rise during transport (the label is decided over the whole hold) [-]
    lift_fail_fraction: float = 0.75
    # after the plan's last phase the hand holds still and the simulation goes on until the object is at rest (the
    # `settled` thresholds of TrialTolerances), at most this long: a ball still rolling at 6 cm/s when a 0.2 s settle
    # phase ends has not been judged, it has been cut off [s]; 0 ends every trial with the plan
    settle_until_rest_max_s: float = 2.0
    # the trial is simulated in a frame turned about the vertical so that the closing axis makes this angle with the
    # MPM grid's x axis (tasks.manipulation.frame); everything recorded is in the world frame. None: the world frame,
    # where the grasp meets the grid at an angle that depends on the object's yaw, and so did the outcome at draft
    # resolution. 45: pad faces at 45 degrees to both horizontal grid axes; faces parallel to a node plane (0)
    # under-grip at every resolution tried (tasks/manipulation/BENCHMARKS.md) [deg]
    closing_axis_to_grid_deg: float | None = 45.0
    # force-controlled closure (ActionPlan.grip_force_limit_n): once the force target is reached, the fingers dwell
    # this long, then the lift starts (the rest of the planned closure, to the deepest squeeze, is skipped) [s]
    skip_rest_of_closure: bool = True
    closure_dwell_s: float = 0.05
    # while held, the fingers close further when the force falls below this share of the target (a force-controlled
    # gripper keeps its set force as a soft object relaxes under the pads) [-]
    reclose_fraction: float = 0.9
    # the fingers touch the object where their mean normal force first reaches this share of the target [-]
    touch_fraction: float = 0.05
    # force-guarded place: while the hand lowers the object onto the target, it stops (braking over place_brake_s)
    # once the table carries this share of the object's weight, and the fingers open there: a plan's place height
    # assumes the object hangs in the hand as it was gripped, and an object turned in the hand (or sagging) would
    # otherwise be pressed into the table and spring away at release. None: lower to the planned place height [-]
    place_support_fraction: float | None = 0.5
    # the guarded part of the lowering: the last place_guard_height_m above the place height at place_guard_speed,
    # where the table is met slowly; the hand brakes to rest over place_brake_s when the guard trips [m, m/s, s]
    place_guard_height_m: float = 0.03
    place_guard_speed_m_per_s: float = 0.1
    place_brake_s: float = 0.02


@dataclass
class TrialResult:
    """What one trial measured: the labels and metrics, the recorded arrays and a few facts about the run."""

    metrics: dict[str, float]
    arrays: dict[str, np.ndarray]
    info: dict[str, object]


def object_pose(plan: ActionPlan) -> ObjectPose:
    """Where the object starts: the table origin, turned by the plan's initial yaw."""
    return ObjectPose((0.0, 0.0), plan.initial_yaw_deg)


def _pad_normals(quat_xyzw: np.ndarray) -> np.ndarray:
    """Unit y axes of the pad boxes (N, 2, 3) from quaternions (N, 2, 4)."""
    x, y, z, w = np.moveaxis(quat_xyzw, -1, 0)
    return np.stack([2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)], axis=-1)


def world_gaussians(body: TrialBody, pose: ObjectPose) -> dict[str, np.ndarray]:
    """The body's rest Gaussians placed on the table at the object pose, with their particle binding."""
    g, rot = body.gaussians, pose.rotation
    return {"gaussian_positions_m": pose.point_to_world(g["positions_m"]),
            "gaussian_covariances_m2": np.einsum("ij,gjk,lk->gil", rot, g["covariances_m2"], rot),
            "gaussian_colors": np.asarray(g["colors"], dtype=np.float32),
            "gaussian_particle_index": np.asarray(g["particle_index"]),
            "gaussian_particle_weight": np.asarray(g["particle_weight"])}


def _at_rest(com_m: np.ndarray, com_span_s: float, x_m: np.ndarray, x_prev_m: np.ndarray, frame_span_s: float,
             x_back_m: np.ndarray, back_span_s: float, tol: TrialTolerances) -> bool:
    """The `settled` label's condition (tasks.manipulation.outcome) if the trial ended now: the COM speed over the
    window com_m, the fastest particle's displacement since the last recorded frame and the body's turn rate since
    x_back_m (back_span_s ago) are below the thresholds."""
    v_com = float(np.linalg.norm(com_m[-1] - com_m[0])) / com_span_s
    v_par = float(np.max(np.linalg.norm(x_m - x_prev_m, axis=1))) / frame_span_s
    return (v_com <= tol.settle_speed_m_per_s and v_par <= tol.settle_particle_speed_m_per_s
            and turn_rate_deg_per_s(x_back_m, x_m, back_span_s) <= tol.settle_turn_rate_deg_per_s)


def run_trial(body: TrialBody, physical: PhysicalModel, material: Material, plan: ActionPlan,
              settings: TrialSettings | None = None, tolerances: TrialTolerances | None = None,
              trajectory: Trajectory | None = None) -> TrialResult:
    """Simulate the plan with the object; return labels, metrics and the recording (raises SimulationError only
    when the plan itself cannot be made: unreachable poses)."""
    s = settings or TrialSettings()
    tol = tolerances or TrialTolerances()
    wall0 = time.perf_counter()
    pose = object_pose(plan)
    traj = trajectory or trial_trajectory(plan, body, s)
    x0 = pose.point_to_world(body.particles_m)
    frame = SimFrame.aligned(traj.closing_axis_world, s.closing_axis_to_grid_deg)
    t_start = max(0.0, traj.phases["closure"][0] - s.settle_before_closure_s)
    t_end = traj.duration_s
    dt_c = 1.0 / s.control_hz
    n_int = int(math.ceil((t_end - t_start) / dt_c - 1e-9))
    n_ext = int(math.ceil(max(0.0, s.settle_until_rest_max_s) / dt_c - 1e-9))  # intervals after the plan, at most
    n_all = n_int + n_ext
    per_frame = max(1, int(round(s.control_hz / s.record_fps)))

    first = traj.pad_motion(t_start, t_start + dt_c)
    mu_g = physical.gripper_friction
    # the pad boxes grow outward from the gripping faces: the left finger's face is its box's -y face, the right's
    # (the same link axes, mirrored) its +y face
    colliders = [pad_collider(traj.pad_half_extents_m, face, friction=mu_g,
                              position_m=tuple(frame.to_sim(first.position_m[0, k])),
                              rotation_xyzw=tuple(frame.quat_to_sim(first.quat_xyzw[0, k])), name=f"finger_{k}")
                 for k, face in enumerate(PAD_FACES)]
    scene = SceneSpec(positions_m=frame.to_sim(x0), volumes_m3=body.volumes_m3, density_kg_per_m3=physical.density_kg_per_m3,
                      material=material, colliders=colliders, ground=True, ground_friction=physical.ground_friction,
                      gravity_m_per_s2=physical.gravity_m_per_s2)
    dx = 2.0 * body.spacing_m
    dt_max = s.dt_max_s * (max(1.0, dx / s.dt_max_dx_m) if s.dt_max_dx_m else 1.0)
    cfg = SimConfig(device=s.device, cpu_threads=s.cpu_threads, dx_m=dx, dt_max_s=dt_max,
                    cfl=s.cfl, substeps=s.substeps,
                    grid_margin_m=s.grid_margin_m, ground_friction=physical.ground_friction,
                    gravity_m_per_s2=physical.gravity_m_per_s2)
    model = build_model([scene], cfg)
    sim = Simulator(model)
    w = body.volumes_m3 / body.volume_m3

    t_c = np.concatenate([t_start + dt_c * np.arange(n_int), t_end + dt_c * np.arange(n_ext)])
    dt_k = np.concatenate([np.minimum(t_c[:n_int] + dt_c, t_end) - t_c[:n_int], np.full(n_ext, dt_c)])
    force = np.full((n_all, 2, 3), np.nan)
    ground = np.full((n_all, 3), np.nan)
    pad_pos = np.zeros((n_all, 2, 3))
    pad_quat = np.zeros((n_all, 2, 4))
    pad_vel = np.zeros((n_all, 2, 3))
    cmd_q = np.zeros((n_all, 7))
    cmd_qdot = np.zeros((n_all, 7))
    cmd_open = np.zeros((n_all, 2))
    com = np.full((n_all + 1, 3), np.nan)
    phase = np.zeros(n_all, dtype=np.int8)
    frames_t: list[float] = []
    frames_x: list[np.ndarray] = []
    frames_f: list[np.ndarray] = []
    frames_k: list[int] = []
    steps = 0
    healthy, issue, stopped = True, "", ""
    lift_end = traj.phases["lift"][1]
    lift_needed = tol.lift_height_m - tol.slip_tolerance_m  # the `lifted` label's threshold
    k_close = int(max(0, min(n_int - 1, math.ceil((traj.phases["closure"][0] - t_start) / dt_c - 1e-9))))

    def particles_world() -> dict[str, np.ndarray]:
        """Positions in the world frame; F stays in the simulation frame (turned only when a frame is recorded)."""
        q = sim.particles(0)
        return {"x": frame.to_world(q["x"]), "F_sim": q["F"]}

    p = particles_world()
    com[0] = w @ p["x"]
    # force-controlled closure (plan.grip_force_limit_n, the force target per finger): the fingers close at the plan's
    # speed until their mean normal force, extrapolated one control interval ahead, reaches the target; they then hold
    # that opening and the plan goes on with the lift (the rest of the planned closure is skipped after a short dwell:
    # control_t_s is plan time, control_sim_t_s the simulated time); while the object is held (closure, lift,
    # transport) they close further at the closing speed whenever the force falls below `reclose` x the target, never
    # past the plan's deepest squeeze; they open when the plan opens them wider (release)
    guard_n = plan.grip_force_limit_n
    hold_opening: float | None = None  # set only when guard_n is not None
    guard: dict[str, float] = {}
    last_normal = float("nan")
    axis = np.asarray(traj.closing_axis_world, dtype=float)
    n_rest = max(1, int(round(0.1 / dt_c)))  # the `settled` label's COM speed window (tasks.manipulation.outcome)
    closure_end, skipped, contact_k = traj.phases["closure"][1], 0.0, 1.0
    weight = physical.mass_kg * float(np.linalg.norm(physical.gravity_m_per_s2))
    place_guard: dict[str, float | str] = {}
    touch_opening: float | None = None  # the opening where the closing fingers' force began to rise [m]
    sim_t = np.zeros(n_all)
    k = -1
    while k + 1 < n_all:
        k += 1
        t0, t1 = t_c[k], t_c[k] + dt_k[k]
        # after the plan: stop at the end of the plan or at a frame once the object is at rest (the label's test)
        if k >= n_int and (k == n_int or k % per_frame == 0):
            lo = max(0, k - n_rest)
            now = sim.time_s + t_start
            i_back = frame_back(np.asarray([*frames_t, now]))
            if _at_rest(com[lo:k + 1], float(t_c[k] - t_c[lo]), p["x"], frames_x[-1], float(now - frames_t[-1]),
                        frames_x[i_back], float(now - frames_t[i_back]), tol):
                k -= 1
                break
        if k % per_frame == 0:
            frames_t.append(sim.time_s + t_start)
            frames_x.append(p["x"].astype(np.float32))
            frames_f.append(frame.tensor_to_world(p["F_sim"]).astype(np.float32))
            frames_k.append(k)
        st = traj.state_at(t0)
        hold_end = hold_opening
        if (hold_opening is not None and guard_n is not None and st.phase in HOLD_PHASES and np.isfinite(last_normal)
                and last_normal < s.reclose_fraction * float(guard_n)):
            # per finger: at the closing speed, but no further than the contact stiffness measured at the target
            # says the force deficit needs (a stiff object is not squeezed by a whole speed x interval at once)
            step = min(plan.closing_speed_m_per_s * (t1 - t0), (float(guard_n) - last_normal) / contact_k)
            hold_end = max(traj.closed_width_m, hold_opening - 2.0 * step)
        m = traj.pad_motion(t0, t1, hold_opening, hold_end)
        # while the hand carries the object, the grid lattice moves with it (tasks.mpm Control.set_grid_velocity):
        # pads crossing lattice planes would release and re-grip node layers and the squeeze would leak away
        carrying = traj.phase_at(t0) in CARRY_PHASES
        sim.control.set_grid_velocity(0, frame.to_sim(m.linear_velocity_m_per_s[0].mean(axis=0)) if carrying
                                      else (0.0, 0.0, 0.0))
        for f in range(2):
            sim.control.set_collider(0, f, position_m=frame.to_sim(m.position_m[0, f]),
                                     rotation_xyzw=frame.quat_to_sim(m.quat_xyzw[0, f]),
                                     linear_velocity_m_per_s=frame.to_sim(m.linear_velocity_m_per_s[0, f]),
                                     angular_velocity_rad_per_s=frame.to_sim(m.angular_velocity_rad_per_s[0, f]))
        cmd_q[k], cmd_qdot[k] = st.q, st.qdot
        # hold_end is None only when hold_opening is
        if hold_opening is not None and hold_end is not None and hold_opening > st.finger_opening_m:
            cmd_open[k] = (hold_opening, (hold_end - hold_opening) / (t1 - t0))
        else:
            cmd_open[k] = (st.finger_opening_m, st.finger_opening_rate_m_per_s)
        sim_t[k] = sim.time_s + t_start
        pad_pos[k], pad_quat[k], pad_vel[k] = m.position_m[0], m.quat_xyzw[0], m.linear_velocity_m_per_s[0]
        phase[k] = PHASES.index(st.phase)
        report = sim.advance(t1 - t0)
        steps += report.steps
        force[k] = frame.to_world(np.array([report.collider_force(model, 0, f) for f in range(2)], dtype=float))
        ground[k] = frame.to_world(np.asarray(report.ground_force_n[0], dtype=float))
        p = particles_world()
        com[k + 1] = w @ p["x"]
        hold_opening = hold_end
        if guard_n is not None and st.phase in HOLD_PHASES:
            normal = 0.5 * float(-(force[k, 0] @ axis) + force[k, 1] @ axis)  # mean per finger over the interval
            rise = max(0.0, normal - last_normal) if np.isfinite(last_normal) else 0.0
            if (touch_opening is None and st.phase == "closure" and np.isfinite(normal)
                    and normal >= s.touch_fraction * float(guard_n)):
                touch_opening = traj.opening_at(t0)  # the force began to rise during this interval
            if hold_opening is None and st.phase == "closure" and np.isfinite(normal) and normal + rise >= guard_n:
                hold_opening = traj.opening_at(t1)  # about to reach the target by the next interval
                # the contact's stiffness per finger as measured on the way in: the force over the squeeze since the
                # force began to rise (not since the grasp's geometric contact width: on a grid the pads meet the
                # object's nodes up to ~1.5 cells before its surface, so a stiff object reaches the target with the
                # pads short of that width, and a stiffness from it would be huge and forbid any re-closing)
                touched = touch_opening if touch_opening is not None else traj.contact_width_m
                squeeze_in = 0.5 * (touched - hold_opening)
                contact_k = max(1.0, normal / max(squeeze_in, 0.5 * plan.closing_speed_m_per_s * dt_c))
                guard = {"stopped_at_s": float(t1), "opening_m": hold_opening, "normal_force_n": normal,
                         "touch_opening_m": float(touched), "contact_stiffness_n_per_m": float(contact_k)}
                skipped = max(0.0, closure_end - s.closure_dwell_s - t1) if s.skip_rest_of_closure else 0.0
                if skipped > 0.0:  # the lift starts after the dwell, not at the planned (deepest) closure's end
                    t_c, dt_k, n_int, n_all = _replan_times(t_c, dt_k, k, t1 + skipped, t_end, dt_c, n_ext)
            last_normal = normal
        support = -float(ground[k, 2])  # the force the object exerts on the table, downward [N]
        if (s.place_support_fraction is not None and not place_guard
                and traj.lower_window_s[0] <= t0 and t1 + s.place_brake_s < traj.lower_window_s[1]
                and support >= s.place_support_fraction * weight):
            # the table carries the object: stop lowering here and release (the plan after t1 is re-timed)
            planned_z = float(traj.place_center_world_m[2])
            try:
                stopped_traj = trial_trajectory(plan, body, s, place_stop_s=float(t1))
            except SimulationError as exc:  # no path back from where it stopped: lower to the planned height
                place_guard = {"stopped_at_s": float("nan"), "support_n": support, "weight_n": weight,
                               "not_stopped": str(exc)}
            else:
                traj = stopped_traj
                place_guard = {"stopped_at_s": float(t1), "support_n": support, "weight_n": weight,
                               "stopped_above_plan_m": float(traj.place_center_world_m[2]) - planned_z}
                t_end = traj.duration_s
                t_c, dt_k, n_int, n_all = _replan_times(t_c, dt_k, k, t1, t_end, dt_c, n_ext)
        if not report.health.ok:
            healthy = False
            first_issue = report.health.first()
            assert first_issue is not None  # health.ok is False only when an issue was recorded
            issue = f"{first_issue.check} at t={first_issue.sim_time_s:.4f} s: {first_issue.detail}"
            break
        if s.stop_when_lift_fails and t1 >= lift_end - 1e-9 > t0:
            rise = float(np.max(com[k_close:k + 2, 2]) - com[k_close, 2])
            if rise < s.lift_fail_fraction * lift_needed:
                stopped = f"lift failed: the object rose {rise:.4f} m of the {lift_needed:.4f} m needed"
                break
    n_done = k + 1
    if guard:
        guard["min_opening_m"] = float(np.min(cmd_open[:n_done, 0]))
        guard["closure_skipped_s"] = skipped
    frames_t.append(sim.time_s + t_start)
    frames_x.append(p["x"].astype(np.float32))
    frames_f.append(frame.tensor_to_world(p["F_sim"]).astype(np.float32))
    frames_k.append(n_done)

    t_c, cmd_q, cmd_qdot, cmd_open, phase = t_c[:n_done], cmd_q[:n_done], cmd_qdot[:n_done], cmd_open[:n_done], \
        phase[:n_done]
    pad_pos, pad_quat, pad_vel, force, com = (pad_pos[:n_done], pad_quat[:n_done], pad_vel[:n_done], force[:n_done],
                                              com[:n_done + 1])
    ground = ground[:n_done]
    arrays = {
        "control_t_s": t_c, "control_dt_s": dt_k[:n_done], "control_sim_t_s": sim_t[:n_done],
        "command_q_rad": cmd_q, "command_qdot_rad_per_s": cmd_qdot, "command_opening_m": cmd_open,
        "phase": phase, "finger_position_m": pad_pos, "finger_quat_xyzw": pad_quat,
        "finger_velocity_m_per_s": pad_vel, "finger_force_n": force, "ground_force_n": ground,
        "finger_impulse_n_s": force * dt_k[:n_done, None, None],
        "object_com_m": com, "frame_t_s": np.asarray(frames_t), "frame_control_index": np.asarray(frames_k),
        "particles_x_m": np.stack(frames_x), "particles_F": np.stack(frames_f),
        "finger_half_extents_m": np.asarray(traj.pad_half_extents_m, dtype=np.float64),
        "closing_axis_world": np.asarray(traj.closing_axis_world, dtype=np.float64),
        "rest_particles_m": x0.astype(np.float32), "particle_volumes_m3": np.asarray(body.volumes_m3, dtype=np.float64),
        **world_gaussians(body, pose), **approach_track(traj, t_start, s.record_fps),
    }
    labels = label_trial(arrays, traj, plan, physical, tol, n_done, healthy, ground_contact_m=float(model.dx))
    wall = time.perf_counter() - wall0  # the whole trial: simulation, recording and labelling
    info = {"particles": int(len(x0)), "steps": int(steps), "wall_time_s": float(wall),
            "sim_time_s": float(sim.time_s), "dx_m": float(model.dx), "particle_spacing_m": float(body.spacing_m),
            "l0_particle_spacing_m": float(body.source_spacing_m), "health_issue": issue, "stopped": stopped,
            "settings": asdict(s), "tolerances": asdict(tol), "phases": {k: list(v) for k, v in traj.phases.items()},
            "object_pose": {"xy_m": list(pose.xy_m), "yaw_deg": pose.yaw_deg}, "intervals": int(n_done),
            "settle_extension_s": float(max(0, n_done - n_int) * dt_c),
            "grip_guard": guard, "place_guard": place_guard, "sim_frame_yaw_deg": math.degrees(frame.yaw_rad)}
    labels.update({"particles": float(len(x0)), "steps": float(steps), "stopped_after_failed_lift": float(bool(stopped)),
                   "grip_guard_stopped": float(bool(guard)), "place_guard_stopped": float(bool(place_guard)
                                                                                        and "not_stopped" not in place_guard),
                   "closed_width_m": float(guard["min_opening_m"]) if guard else float(traj.closed_width_m),
                   "squeeze_per_finger_m": 0.5 * (traj.contact_width_m - (float(guard["min_opening_m"]) if guard
                                                                         else float(traj.closed_width_m))),
                   "grip_force_target_n": float(guard_n) if guard_n is not None else float("nan")})
    labels.update(mode_flags(labels, tol))  # the failure mode the revision routes read (tasks.manipulation.diagnosis)
    # wall time stays in info, not in the data
    return TrialResult(labels, arrays, info)


def _replan_times(t_c: np.ndarray, dt_k: np.ndarray, k: int, t_next: float, t_end: float, dt_c: float, n_ext: int
                  ) -> tuple[np.ndarray, np.ndarray, int, int]:
    """Control intervals after interval k when the plan goes on at plan time t_next [s] (the closure's skipped
    rest): (start times, durations, intervals to the plan's end, intervals in all)."""
    m = int(math.ceil(max(0.0, t_end - t_next) / dt_c - 1e-9))
    plan_t = t_next + dt_c * np.arange(m)
    t_new = np.concatenate([t_c[:k + 1], plan_t, t_end + dt_c * np.arange(n_ext)])
    dt_new = np.concatenate([dt_k[:k + 1], np.minimum(plan_t + dt_c, t_end) - plan_t, np.full(n_ext, dt_c)])
    return t_new, dt_new, k + 1 + m, k + 1 + m + n_ext


_PLANNED: OrderedDict[tuple[object, ...], Trajectory] = OrderedDict()  # the last trajectories planned in this process
_PLANNED_LOCK = threading.Lock()
PLANNED_KEPT = 16  # trajectories kept (each ~1-2 MB: its dense pad table)


def trial_trajectory(plan: ActionPlan, body: TrialBody, settings: TrialSettings, place_stop_s: float | None = None
                     ) -> Trajectory:
    """The plan's trajectory as a trial executes it (raises UnreachableError or SimulationError); place_stop_s: where
    a force-guarded place stopped the lowering [s].

    A trajectory depends on the plan, the body's height and these settings alone, and is not changed once planned: the
    last PLANNED_KEPT are kept in the process, so that a plan checked for reachability (plan_executable, ~1-2 s of IK
    and pad table on the CPU) is not planned again by its trial, nor a trial's by its side-by-side conditions."""
    s = settings
    guarded = s.place_guard_height_m if s.place_support_fraction is not None else 0.0
    key = (plan.model_dump_json(), float(body.height_m), float(s.pad_half_thickness_m), float(guarded),
           float(s.place_guard_speed_m_per_s), None if place_stop_s is None else float(place_stop_s),
           float(s.place_brake_s))
    with _PLANNED_LOCK:
        kept = _PLANNED.get(key)
        if kept is not None:
            _PLANNED.move_to_end(key)
            return kept
    place = PlaceApproach(height_m=guarded, speed_m_per_s=s.place_guard_speed_m_per_s, stop_s=place_stop_s,
                          brake_s=s.place_brake_s)
    traj = plan_trajectory(plan, object_pose=object_pose(plan), object_height_m=body.height_m,
                           pad_half_thickness_m=s.pad_half_thickness_m, place=place)
    with _PLANNED_LOCK:
        _PLANNED[key] = traj
        while len(_PLANNED) > PLANNED_KEPT:
            _PLANNED.popitem(last=False)
    return traj


def plan_or_error(plan: ActionPlan, body: TrialBody, settings: TrialSettings | None = None
                  ) -> tuple[Trajectory | None, str]:
    """The plan's trajectory, or None and the reason it cannot be executed (unreachable, into the table)."""
    try:
        return trial_trajectory(plan, body, settings or TrialSettings()), ""
    except SimulationError as exc:
        return None, str(exc)


def reachable_plan(plan: ActionPlan, grasps: list[GraspCandidate], body: TrialBody,
                   settings: TrialSettings | None = None, grasp_settings: GraspSettings | None = None,
                   executable: Callable[[ActionPlan], bool] | None = None) -> ActionPlan:
    """The plan, or when its grasp cannot be executed under the plan's condition (a side approach that an initial
    yaw turns away from the arm): first the same grasp approached from another side (its contacts kept: what the
    trials tested; needs ``grasp_settings``, the sampler's, for the hand's collision test), else the same plan with
    the best-ranked grasp that can be executed; unchanged when none can.
    executable: whether a plan can be executed on this body (default: plan_or_error plans it; L3's context passes
    the same answer remembered in the cache, tasks.manipulation.context.plan_executable)."""
    def plans(p: ActionPlan) -> bool:
        return plan_or_error(p, body, settings)[0] is not None

    can = executable or plans
    if can(plan):
        return plan
    same = turned_approaches(plan.grasp, body.surface_points_m, grasp_settings) if grasp_settings is not None else []
    for g in [*same, *(g for g in grasps if g.rank != plan.grasp.rank)]:
        other = plan.model_copy(update={"grasp": g})
        if can(other):
            return other
    return plan


__all__ = ["TrialSettings", "TrialResult", "run_trial", "trial_trajectory", "plan_or_error", "reachable_plan", "object_pose"]
