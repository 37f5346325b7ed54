"""The timed pick-and-place of an ActionPlan: joint trajectory, finger opening and finger-pad boxes at any time.

Phases: approach (joint move to a pre-grasp clear of the object and the table, lengthened if needed to respect the
joint speed limits, then a straight descent) -> closure (fingers close from the open width to ``width - 2 * squeeze``
at the closing speed per finger, then hold) -> lift (straight up) -> transport (straight, at the lift height, to above
the target; then straight down to the place height) -> release (fingers open) -> retreat (straight back along the
approach) -> settle (hold). Joint moves use min-jerk timing; straight Cartesian moves are densely sampled IK joined by
a spline in the path parameter, timed min-jerk.

Frames: world = table frame (z up, table top z = 0 = the MPM ground). The asset frame sits at ``ObjectPose`` (origin on
the table at xy, turned by yaw about z); the object is placed at ``plan.target_xy_m`` with the same yaw. Finger 0 is the
left finger (joint 9), at ``centre - closing_axis_world * w / 2``; finger 1 the right one (joint 10); the world
closing axis is the grasp's, or its reverse where that keeps the joints further from their limits. Pad poses and
velocities are precomputed once on a dense time table and interpolated, so ``finger_pads(t)`` is cheap at any dt.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline

from contracts.errors import SimulationError
from contracts.robot import ActionPlan
from tasks.robot.panda import READY_Q, IKSolution, Panda, UnreachableError, grasp_rotation
from tasks.robot.timing import min_jerk, ramped_travel, ramped_travel_time

PHASES = ("approach", "closure", "lift", "transport", "release", "retreat", "settle")
CARTESIAN_STEP_M = 0.004
MAX_JOINT_STEP_RAD = 0.15
SPEED_LIMIT_FRACTION = 0.9


@dataclass(frozen=True)
class ObjectPose:
    """Pose of the asset frame on the table: origin at (x, y, 0) [m], yaw [deg] about z."""

    xy_m: tuple[float, float] = (0.0, 0.0)
    yaw_deg: float = 0.0

    @property
    def rotation(self) -> np.ndarray:
        """3x3 rotation asset -> world."""
        c, s = np.cos(np.radians(self.yaw_deg)), np.sin(np.radians(self.yaw_deg))
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def point_to_world(self, p: np.ndarray) -> np.ndarray:
        """Asset-frame point(s) [m] -> world [m]."""
        return np.asarray(p, dtype=float) @ self.rotation.T + np.array([*self.xy_m, 0.0])


@dataclass(frozen=True)
class RobotState:
    """The commanded robot at one time: arm angles [rad] and rates [rad/s], finger opening [m] and rate [m/s]."""

    t_s: float
    q: np.ndarray
    qdot: np.ndarray
    finger_opening_m: float
    finger_opening_rate_m_per_s: float
    phase: str

    @property
    def finger_joints_m(self) -> tuple[float, float]:
        """Positions of finger joints 9 and 10 [m] (each half the opening: the mimic coupling)."""
        return (self.finger_opening_m / 2.0, self.finger_opening_m / 2.0)

    @property
    def joint_positions(self) -> np.ndarray:
        """All 9 movable joints: 7 arm [rad] then 2 fingers [m]."""
        return np.concatenate([self.q, self.finger_joints_m])


@dataclass(frozen=True)
class FingerPad:
    """A finger pad as a box collider in the world: centre [m], orientation, half extents [m], velocities."""

    position_m: np.ndarray
    quat_xyzw: np.ndarray
    rotation: np.ndarray
    half_extents_m: np.ndarray
    linear_velocity_m_per_s: np.ndarray
    angular_velocity_rad_per_s: np.ndarray
    normal: np.ndarray

    @property
    def contact_point_m(self) -> np.ndarray:
        """Centre of the gripping face [m] (the face whose outward normal is ``normal``, towards the other pad)."""
        return self.position_m + self.normal * self.half_extents_m[1]


@dataclass(frozen=True)
class PadArrays:
    """Pads at many times: arrays of shape (N, 2, ...) with finger 0 = left, 1 = right; SI units."""

    t_s: np.ndarray
    position_m: np.ndarray
    quat_xyzw: np.ndarray
    linear_velocity_m_per_s: np.ndarray
    angular_velocity_rad_per_s: np.ndarray
    half_extents_m: np.ndarray

    def _split(self) -> list[PadArrays]:
        """One PadArrays (N = 1) per time."""
        return [PadArrays(self.t_s[k:k + 1], self.position_m[k:k + 1], self.quat_xyzw[k:k + 1],
                          self.linear_velocity_m_per_s[k:k + 1], self.angular_velocity_rad_per_s[k:k + 1],
                          self.half_extents_m[k:k + 1]) for k in range(len(self.t_s))]


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions (x, y, z, w), broadcast over leading axes."""
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz], axis=-1)


# --- motion pieces (local time tau in [0, duration]) -------------------------------------------------------------
ArmFn = Callable[[float], tuple[np.ndarray, np.ndarray]]
FingerFn = Callable[[float], tuple[float, float]]


@dataclass(frozen=True)
class PlaceApproach:
    """How the hand lowers the object onto the target: the last height_m [m] above the place height slowly, at
    speed_m_per_s [m/s] (a guarded move: contact with the table is found at low speed), and, for a force-guarded
    place, stopped at stop_s [s] (braking over brake_s [s]) because the table already carries the object; the
    release, retreat and settle then start where the hand stopped. height_m 0: one min-jerk move down."""

    height_m: float = 0.0
    speed_m_per_s: float = 0.1
    stop_s: float | None = None
    brake_s: float = 0.02


def _hold_arm(q: np.ndarray) -> ArmFn:
    """Arm at rest at q."""
    return lambda tau: (q.copy(), np.zeros(7))


def _joint_move(qa: np.ndarray, qb: np.ndarray, duration: float) -> ArmFn:
    """Min-jerk straight line in joint space."""
    def f(tau: float) -> tuple[np.ndarray, np.ndarray]:
        s, ds = min_jerk(tau / duration)
        return qa + float(s) * (qb - qa), float(ds) / duration * (qb - qa)
    return f


Profile = Callable[[float], tuple[float, float]]  # local time [s] -> path parameter s in [0, 1] and ds/dt [1/s]


def _min_jerk_profile(duration: float) -> Profile:
    """Min-jerk timing of a path over duration [s]."""
    def f(tau: float) -> tuple[float, float]:
        s, ds = min_jerk(tau / duration)
        return float(s), float(ds) / duration
    return f


def _ramped_profile(length_m: float, speed: float) -> Profile:
    """Constant speed [m/s] with short ramps along a straight path of length_m [m]."""
    def f(tau: float) -> tuple[float, float]:
        d, rate = ramped_travel(tau, length_m, speed)
        return float(d) / length_m, float(rate) / length_m
    return f


def _braked_profile(profile: Profile, tau_stop: float, brake_s: float) -> tuple[Profile, float]:
    """The profile up to tau_stop [s], then brought to rest at constant deceleration over brake_s [s]:
    (the new profile, the path parameter where it rests)."""
    s_g, rate = profile(tau_stop)
    s_end = min(1.0, s_g + 0.5 * rate * brake_s)

    def f(tau: float) -> tuple[float, float]:
        if tau <= tau_stop:
            return profile(tau)
        u = min(tau - tau_stop, brake_s)
        return min(s_end, s_g + rate * u - 0.5 * rate / brake_s * u * u), rate * (1.0 - u / brake_s)
    return f, s_end


def _profiled_move(spline: CubicSpline, profile: Profile) -> ArmFn:
    """The joint path q(s) timed by a profile."""
    deriv = spline.derivative()

    def f(tau: float) -> tuple[np.ndarray, np.ndarray]:
        s, ds = profile(tau)
        return spline(s), deriv(s) * ds
    return f


def _path_move(spline: CubicSpline, duration: float) -> ArmFn:
    """Min-jerk timing along a joint path q(s), s in [0, 1]."""
    return _profiled_move(spline, _min_jerk_profile(duration))


def _hold_fingers(w: float) -> FingerFn:
    """Fingers at rest at opening w [m]."""
    return lambda tau: (w, 0.0)


def _close_fingers(w_open: float, w_closed: float, speed: float) -> FingerFn:
    """Opening [m] that closes at ``speed`` per finger (2 * speed in opening) with short ramps, then holds."""
    def f(tau: float) -> tuple[float, float]:
        d, rate = ramped_travel(tau, (w_open - w_closed) / 2.0, speed)
        return w_open - 2.0 * float(d), -2.0 * float(rate)
    return f


def _open_fingers(w_a: float, w_b: float, duration: float) -> FingerFn:
    """Min-jerk opening from w_a to w_b [m]."""
    def f(tau: float) -> tuple[float, float]:
        s, ds = min_jerk(tau / duration)
        return w_a + float(s) * (w_b - w_a), float(ds) / duration * (w_b - w_a)
    return f


@dataclass
class _Segment:
    """One timed piece of the plan."""

    t0: float
    t1: float
    phase: str
    arm: ArmFn
    fingers: FingerFn


@dataclass
class Trajectory:
    """A timed plan; sample it with ``state_at`` and ``finger_pads`` (any t [s]) or ``pads_at`` (arrays).

    Also records: phase windows [s], the world closing/approach axes, grasp and place centres [m], the open, contact
    and closed widths [m], the contact time [s], the worst IK residuals, the lowest robot link point over the motion
    [m] and the peak joint speed as a fraction of the URDF limits.
    """

    segments: list[_Segment]
    phases: dict[str, tuple[float, float]]
    closing_axis_world: np.ndarray
    approach_axis_world: np.ndarray
    grasp_center_world_m: np.ndarray
    place_center_world_m: np.ndarray
    open_width_m: float
    contact_width_m: float
    closed_width_m: float
    contact_time_s: float
    ik_max_position_error_m: float
    ik_max_rotation_error_rad: float
    table_dt_s: float
    pad_half_extents_m: np.ndarray
    _table: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    min_robot_height_m: float = float("nan")
    max_joint_speed_ratio: float = float("nan")
    # the straight lowering onto the target [s]: a force-guarded place stops inside it (plan_trajectory place_stop_s)
    lower_window_s: tuple[float, float] = (float("nan"), float("nan"))
    place_stopped_s: float | None = None  # where a guarded place began to brake [s]; None: lowered all the way

    @property
    def duration_s(self) -> float:
        """End of the settle phase [s]."""
        return self.segments[-1].t1

    def phase_at(self, t: float) -> str:
        """Name of the phase at time t [s] (before 0: approach; after the end: settle)."""
        return self._segment(t).phase

    def _segment(self, t: float) -> _Segment:
        """The segment that contains t (clamped to the plan)."""
        starts = [s.t0 for s in self.segments]
        i = max(0, min(len(self.segments) - 1, bisect_right(starts, t) - 1))
        return self.segments[i]

    def state_at(self, t: float) -> RobotState:
        """Commanded robot state at time t [s], evaluated exactly from the plan's pieces."""
        seg = self._segment(t)
        tau = float(np.clip(t - seg.t0, 0.0, seg.t1 - seg.t0))
        q, qdot = seg.arm(tau)
        w, wdot = seg.fingers(tau)
        if t >= self.duration_s or t < 0.0:
            qdot, wdot = np.zeros(7), 0.0
        return RobotState(float(t), np.asarray(q, dtype=float), np.asarray(qdot, dtype=float), float(w), float(wdot),
                          seg.phase)

    def pads_at(self, times: np.ndarray) -> PadArrays:
        """Pad boxes at many times [s], linearly interpolated from the dense table (quaternions normalised)."""
        t = np.clip(np.asarray(times, dtype=float), 0.0, self.duration_s)
        x = t / self.table_dt_s
        i = np.minimum(np.floor(x).astype(int), len(self._table["t"]) - 2)
        a = (x - i)[:, None, None]
        tab = self._table

        def lerp(k: str) -> np.ndarray:
            return (1.0 - a) * tab[k][i] + a * tab[k][i + 1]

        quat = lerp("quat")
        quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
        halves = np.broadcast_to(self.pad_half_extents_m, (len(t), 2, 3)).copy()
        return PadArrays(t, lerp("pos"), quat, lerp("vel"), lerp("omega"), halves)

    def finger_pads(self, t: float) -> tuple[FingerPad, FingerPad]:
        """The two pad boxes (left, right) at time t [s]: world pose, half extents, linear and angular velocity."""
        arr = self.pads_at(np.array([t]))
        pads = []
        for k, sign in ((0, -1.0), (1, 1.0)):
            rot = _quat_matrix(arr.quat_xyzw[0, k])
            pads.append(FingerPad(arr.position_m[0, k], arr.quat_xyzw[0, k], rot, self.pad_half_extents_m.copy(),
                                  arr.linear_velocity_m_per_s[0, k], arr.angular_velocity_rad_per_s[0, k],
                                  sign * rot[:, 1]))
        return pads[0], pads[1]

    def opening_at(self, t: float) -> float:
        """Commanded finger opening at time t [s] (from the dense table) [m]."""
        x = float(np.clip(t, 0.0, self.duration_s)) / self.table_dt_s
        i = min(int(np.floor(x)), len(self._table["t"]) - 2)
        a = x - i
        return float((1.0 - a) * self._table["opening"][i] + a * self._table["opening"][i + 1])

    def _held_open(self, pads: PadArrays, min_opening_m: float) -> PadArrays:
        """The pads (N = 1) moved apart along the line between them so that the opening is at least min_opening_m."""
        extra = min_opening_m - self.opening_at(float(pads.t_s[0]))
        if extra <= 0.0:
            return pads
        d = pads.position_m[0, 0] - pads.position_m[0, 1]
        d = d / max(float(np.linalg.norm(d)), 1e-12)  # finger 0 lies on +d, finger 1 on -d
        pos = pads.position_m.copy()
        pos[0, 0] += 0.5 * extra * d
        pos[0, 1] -= 0.5 * extra * d
        return PadArrays(pads.t_s, pos, pads.quat_xyzw, pads.linear_velocity_m_per_s,
                         pads.angular_velocity_rad_per_s, pads.half_extents_m)

    def pad_motion(self, t0: float, t1: float, min_opening_m: float | None = None,
                   min_opening_end_m: float | None = None) -> PadArrays:
        """Pads as constant-velocity kinematic colliders over [t0, t1] [s]: pose at t0 and the mean linear and angular
        (world frame) velocities that carry it exactly onto the planned pose at t1, ``q(t) = exp(w (t - t0)) q0``.

        Arrays have N = 1: shapes (1, 2, ...). Feed them to the MPM's per-step collider control to avoid the drift
        of extrapolating the instantaneous velocity. ``min_opening_m`` holds the fingers at least that far apart (a
        force-guarded closure that stopped early: the hand follows the plan, the fingers stay where they stopped
        until the plan opens them wider). ``min_opening_end_m``: that floor at t1 when it differs from the one at t0
        (a force-controlled closure that closes further while it holds).
        """
        if not t1 > t0:
            raise ValueError("pad_motion needs t1 > t0")
        a, b = self.pads_at(np.array([t0, t1]))._split()
        if min_opening_m is not None:
            end = min_opening_m if min_opening_end_m is None else min_opening_end_m
            a, b = self._held_open(a, min_opening_m), self._held_open(b, end)
        dt = t1 - t0
        dq = quat_mul(b.quat_xyzw, a.quat_xyzw * np.array([-1.0, -1.0, -1.0, 1.0]))
        dq *= np.where(dq[..., 3:4] < 0.0, -1.0, 1.0)
        sin_half = np.linalg.norm(dq[..., :3], axis=-1, keepdims=True)
        angle = 2.0 * np.arctan2(sin_half, dq[..., 3:4])
        axis = dq[..., :3] / np.maximum(sin_half, 1e-300)
        omega = np.where(sin_half > 1e-15, axis * angle / dt, 0.0)
        vel = (b.position_m - a.position_m) / dt
        return PadArrays(a.t_s, a.position_m, a.quat_xyzw, vel, omega, a.half_extents_m)

    def joint_table(self) -> dict[str, np.ndarray]:
        """The dense table: t [s], q [rad] (N, 7), opening [m] (N,), phase index (N,) into PHASES."""
        return {k: self._table[k].copy() for k in ("t", "q", "opening", "phase")}


def _quat_matrix(q: np.ndarray) -> np.ndarray:
    """3x3 rotation of a unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


# --- planning ----------------------------------------------------------------------------------------------------
def _cartesian_path(panda: Panda, q_start: np.ndarray, ee_a: np.ndarray, ee_b: np.ndarray, rot: np.ndarray,
                    residuals: list[IKSolution]) -> CubicSpline:
    """Joint path q(s), s in [0, 1], that keeps the end-effector on the straight line ee_a -> ee_b at fixed rot."""
    length = float(np.linalg.norm(ee_b - ee_a))
    n = max(8, int(np.ceil(length / CARTESIAN_STEP_M))) + 1
    s = np.linspace(0.0, 1.0, n)
    qs = [q_start]
    for sk in s[1:]:
        sol = panda.track_ik(ee_a + sk * (ee_b - ee_a), rot, seed=qs[-1])
        residuals.append(sol)
        if np.max(np.abs(sol.q - qs[-1])) > MAX_JOINT_STEP_RAD:
            raise SimulationError(f"straight move {np.round(ee_a, 3).tolist()} -> {np.round(ee_b, 3).tolist()} m "
                                  "needs a joint jump (configuration change); no continuous path")
        qs.append(sol.q)
    return CubicSpline(s, np.asarray(qs), axis=0)


def _limit_margin(panda: Panda, q: np.ndarray) -> float:
    """Smallest distance of any arm joint from its limits [rad]."""
    return float(np.min(np.minimum(q - panda.lower, panda.upper - q)))


def _choose_closing_axis(panda: Panda, closing: np.ndarray, approach: np.ndarray, centers: list[np.ndarray]
                         ) -> tuple[np.ndarray, IKSolution]:
    """Closing-axis sign (which finger goes where) that keeps the joints furthest from their limits.

    Both signs are solved at the pre-grasp, grasp, lift, above-target and place centres [m]; returns the sign with the
    pre-grasp solution, or the first UnreachableError if neither sign reaches them all.
    """
    best: tuple[float, np.ndarray, IKSolution] | None = None
    error: UnreachableError | None = None
    for u in (closing, -closing):
        rot = grasp_rotation(u, approach)
        try:
            pre = panda.solve_ik(panda.ee_target_for_grasp(centers[0], rot), rot,
                                 seed=np.asarray(READY_Q))
            margin = _limit_margin(panda, pre.q)
            q = pre.q
            for c in centers[1:]:
                q = panda.solve_ik(panda.ee_target_for_grasp(c, rot), rot, seed=q, rest=q).q
                margin = min(margin, _limit_margin(panda, q))
        except UnreachableError as exc:
            error = error or exc
            continue
        if best is None or margin > best[0] + 1e-6:
            best = (margin, u, pre)
    if best is None:
        assert error is not None
        raise error
    return best[1], best[2]


def plan_trajectory(plan: ActionPlan, object_pose: ObjectPose | None = None, object_height_m: float | None = None,
                    panda: Panda | None = None, open_clearance_m: float = 0.01, approach_clearance_m: float = 0.03,
                    table_dt_s: float = 0.002, pad_half_thickness_m: float = 0.004,
                    place: PlaceApproach | None = None) -> Trajectory:
    """Turn an ActionPlan into a Trajectory (IK verified by FK; raises UnreachableError or SimulationError).

    object_pose: where the asset frame is on the table (default: origin, ``plan.initial_yaw_deg``).
    object_height_m: top of the asset [m]; the pre-grasp puts the fingertips that far above it plus
    approach_clearance_m (without it, the pre-grasp is 0.10 m back along the approach axis).
    open_clearance_m: gap per finger [m] between a pad and the object at the pre-grasp (capped by the gripper's
    stroke: a soft object wider than the stroke is pressed by the open fingers as they come down).
    The plan's gripper (``plan.gripper``) is mounted on the Panda; a given panda must carry the same one.
    pad_half_thickness_m: half thickness of the pad boxes [m] (outward from the gripping face), when no panda is given.
    table_dt_s: spacing of the dense pad table [s].
    place: how the object is lowered onto the target (default: one min-jerk move down to the place height).
    """
    pose = object_pose or ObjectPose((0.0, 0.0), plan.initial_yaw_deg)
    own = panda is None
    panda = panda or Panda(pad_half_thickness_m=pad_half_thickness_m, gripper=plan.gripper)
    if panda.gripper.name != plan.gripper:
        raise ValueError(f"the plan's gripper is {plan.gripper}, the given Panda carries {panda.gripper.name}")
    try:
        return _plan(plan, pose, object_height_m, panda, open_clearance_m, approach_clearance_m, table_dt_s,
                     place or PlaceApproach())
    finally:
        if own:
            panda.close()


def _plan(plan: ActionPlan, pose: ObjectPose, object_height_m: float | None, panda: Panda, open_clearance_m: float,
          approach_clearance_m: float, table_dt_s: float, place: PlaceApproach) -> Trajectory:
    """Waypoints by IK, then the timed segments, then the dense pad table."""
    g = plan.grasp
    rot_obj = pose.rotation
    center = pose.point_to_world(np.asarray(g.center_m))
    approach = rot_obj @ np.asarray(g.approach_axis, dtype=float)
    approach /= np.linalg.norm(approach)
    closing = rot_obj @ np.asarray(g.closing_axis, dtype=float)
    closing -= (closing @ approach) * approach
    closing /= np.linalg.norm(closing)

    # finger widths [m]
    contact = float(g.width_m)
    w_open = min(panda.gripper.stroke_m, contact + 2.0 * open_clearance_m)
    w_closed = max(0.0, contact - 2.0 * plan.squeeze_depth_m)

    # Cartesian waypoints of the grasp centre [m]
    pads = panda.pads
    if object_height_m is None:
        d_pre = 0.10
    else:
        down = -float(approach[2])
        above = object_height_m - center[2] + pads.tip_beyond_center_m + approach_clearance_m  # to clear the top
        side = 0.5 * object_height_m + pads.tip_beyond_center_m + approach_clearance_m  # a side approach's reach
        d_pre = max(0.05, min(above / down if down > 1e-6 else np.inf, side / max(1.0 - down, 1e-6)))
    c_pre = center - approach * d_pre
    c_lift = center + np.array([0.0, 0.0, plan.lift_height_m])
    shift = np.array([plan.target_xy_m[0] - pose.xy_m[0], plan.target_xy_m[1] - pose.xy_m[1], 0.0])
    c_above = c_lift + shift
    c_place = center + shift + np.array([0.0, 0.0, plan.place_height_m])
    c_retreat = c_place - approach * d_pre

    q_ready = np.asarray(READY_Q)
    panda.set_joints(q_ready, w_open)
    closing, pre = _choose_closing_axis(panda, closing, approach, [c_pre, center, c_lift, c_above, c_place])
    rot = grasp_rotation(closing, approach)

    def ee(c: np.ndarray) -> np.ndarray:
        return panda.ee_target_for_grasp(c, rot)

    residuals: list[IKSolution] = [pre]
    descend = _cartesian_path(panda, pre.q, ee(c_pre), ee(center), rot, residuals)
    q_grasp = descend(1.0)
    lift = _cartesian_path(panda, q_grasp, ee(center), ee(c_lift), rot, residuals)
    carry = _cartesian_path(panda, lift(1.0), ee(c_lift), ee(c_above), rot, residuals)
    guarded_m = min(place.height_m, max(0.0, float(c_above[2] - c_place[2]) - 0.005))
    c_guarded = c_place + np.array([0.0, 0.0, guarded_m])  # where the guarded (slow) part of the lowering begins
    lower = _cartesian_path(panda, carry(1.0), ee(c_above), ee(c_guarded), rot, residuals)
    slow = (_cartesian_path(panda, lower(1.0), ee(c_guarded), ee(c_place), rot, residuals) if guarded_m > 0.0
            else None)

    # timing [s]; the joint move to the pre-grasp is slowed, if needed, to keep every joint within its speed limit
    t_descend = 0.4 * plan.approach_duration_s
    t_join = max(0.6 * plan.approach_duration_s,
                 1.875 * float(np.max(np.abs(pre.q - q_ready) / (SPEED_LIMIT_FRACTION * panda.velocity_limits))))
    t_close = max(plan.closure_duration_s,
                  ramped_travel_time((w_open - w_closed) / 2.0, plan.closing_speed_m_per_s) + 0.05)
    l_carry, l_lower = float(np.linalg.norm(c_above - c_lift)), float(np.linalg.norm(c_guarded - c_above))
    roots = np.sqrt([l_carry, l_lower])  # equal peak acceleration of two min-jerk moves: T ~ sqrt(L)
    if roots.sum() <= 0.0:
        roots = np.array([1.0, 0.0])
    t_carry, t_lower = plan.transport_duration_s * roots / roots.sum()
    t_lower_start = t_join + t_descend + t_close + plan.lift_duration_s + t_carry
    # the lowering: a min-jerk move to c_guarded, then (if any) a slow straight one to c_place; a guarded place stops
    # it where the table took the object (place.stop_s) and everything after starts from there
    moves: list[tuple[CubicSpline, Profile, float, np.ndarray, np.ndarray]] = [
        (lower, _min_jerk_profile(t_lower), t_lower, c_above, c_guarded)]
    if slow is not None:
        moves.append((slow, _ramped_profile(guarded_m, place.speed_m_per_s),
                      ramped_travel_time(guarded_m, place.speed_m_per_s), c_guarded, c_place))
    lowering: list[tuple[float, ArmFn]] = []
    t_move, stopped = t_lower_start, None
    for spline, profile, dur, c_a, c_b in moves:
        stop = place.stop_s
        if stop is not None and t_move <= stop < t_move + dur:
            braked, s_end = _braked_profile(profile, stop - t_move, place.brake_s)
            lowering.append((stop - t_move + place.brake_s, _profiled_move(spline, braked)))
            c_place, stopped = c_a + s_end * (c_b - c_a), stop  # each move is straight and linear in s
            c_retreat = c_place - approach * d_pre
            break
        lowering.append((dur, _profiled_move(spline, profile)))
        t_move += dur
    q_place = lowering[-1][1](lowering[-1][0])[0]
    retreat = _cartesian_path(panda, q_place, ee(c_place), ee(c_retreat), rot, residuals)

    pieces: list[tuple[float, str, ArmFn, FingerFn]] = [
        (t_join, "approach", _joint_move(q_ready, pre.q, t_join), _hold_fingers(w_open)),
        (t_descend, "approach", _path_move(descend, t_descend), _hold_fingers(w_open)),
        (t_close, "closure", _hold_arm(q_grasp), _close_fingers(w_open, w_closed, plan.closing_speed_m_per_s)),
        (plan.lift_duration_s, "lift", _path_move(lift, plan.lift_duration_s), _hold_fingers(w_closed)),
        (t_carry, "transport", _path_move(carry, t_carry), _hold_fingers(w_closed)),
        *((dur, "transport", arm, _hold_fingers(w_closed)) for dur, arm in lowering),
        (plan.release_duration_s, "release", _hold_arm(q_place), _open_fingers(w_closed, w_open,
                                                                               plan.release_duration_s)),
        (plan.retreat_duration_s, "retreat", _path_move(retreat, plan.retreat_duration_s), _hold_fingers(w_open)),
        (plan.settle_duration_s, "settle", _hold_arm(retreat(1.0)), _hold_fingers(w_open)),
    ]
    segments, t = [], 0.0
    phases: dict[str, tuple[float, float]] = {}
    for dur, name, arm, fingers in pieces:
        if dur <= 0.0:
            continue
        segments.append(_Segment(t, t + dur, name, arm, fingers))
        t0 = phases.get(name, (t, t))[0]
        phases[name] = (t0, t + dur)
        t += dur

    traj = Trajectory(
        segments=segments, phases=phases, closing_axis_world=closing, approach_axis_world=approach,
        grasp_center_world_m=center, place_center_world_m=c_place, open_width_m=w_open, contact_width_m=contact,
        closed_width_m=w_closed, contact_time_s=phases["closure"][0] + _contact_time(w_open, contact, plan),
        ik_max_position_error_m=max(r.position_error_m for r in residuals),
        ik_max_rotation_error_rad=max(r.rotation_error_rad for r in residuals),
        table_dt_s=table_dt_s, pad_half_extents_m=np.asarray(pads.half_extents_m),
        lower_window_s=(t_lower_start, t_lower_start + sum(d for d, _ in lowering)), place_stopped_s=stopped)
    _fill_table(traj, panda)
    return traj


def _contact_time(w_open: float, contact: float, plan: ActionPlan) -> float:
    """Time after closure starts when the opening equals the contact width [s] (found on the closing profile)."""
    f = _close_fingers(w_open, max(0.0, contact - 2.0 * plan.squeeze_depth_m), plan.closing_speed_m_per_s)
    lo, hi = 0.0, ramped_travel_time(w_open / 2.0, plan.closing_speed_m_per_s) + 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid)[0] > contact else (lo, mid)
    return 0.5 * (lo + hi)


def _fill_table(traj: Trajectory, panda: Panda) -> None:
    """Sample the plan every table_dt_s: joint states, pad poses and velocities (pybullet FK), robot clearance."""
    n = int(np.ceil(traj.duration_s / traj.table_dt_s)) + 2
    times = np.arange(n) * traj.table_dt_s
    q = np.zeros((n, 7))
    speed_ratio = 0.0
    opening = np.zeros(n)
    phase = np.zeros(n, dtype=np.int8)
    pos, quat, vel, omega = (np.zeros((n, 2, 3)), np.zeros((n, 2, 4)), np.zeros((n, 2, 3)), np.zeros((n, 2, 3)))
    lowest = np.inf
    for k, t in enumerate(times):
        st = traj.state_at(float(t))
        q[k], opening[k], phase[k] = st.q, st.finger_opening_m, PHASES.index(st.phase)
        speed_ratio = max(speed_ratio, float(np.max(np.abs(st.qdot) / panda.velocity_limits)))
        panda.set_joints(st.q, st.finger_opening_m, st.qdot, st.finger_opening_rate_m_per_s)
        for f, (p, qk, _, v, w) in enumerate(panda.pad_states_with_quat()):
            pos[k, f], vel[k, f], omega[k, f] = p, v, w
            if k > 0 and float(qk @ quat[k - 1, f]) < 0.0:
                qk = -qk  # keep quaternions on one hemisphere so interpolation is smooth
            quat[k, f] = qk
        if k % 5 == 0 or k == n - 1:
            lowest = min(lowest, panda.lowest_point())
    traj._table = {"t": times, "q": q, "opening": opening, "phase": phase, "pos": pos, "quat": quat, "vel": vel,
                   "omega": omega}
    traj.min_robot_height_m = lowest
    traj.max_joint_speed_ratio = speed_ratio
    if lowest < 0.0:
        raise SimulationError(f"the planned motion takes the robot {-lowest * 1000:.1f} mm into the table")
