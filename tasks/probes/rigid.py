"""L1 rigid probes in pybullet on the convex collision proxy: placement, drop, slide.

The proxy is a list of convex hulls (vertex arrays, asset frame: z up, resting on z = 0, metres). The object is
one rigid body of the L1 mass with its centre of mass at the given point. Ground friction is the object's coefficient
(the plane's own is 1.0 and Bullet multiplies them). Every probe runs in its own DIRECT client: no shared state.
"""

from __future__ import annotations

import collections
import math
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from contracts.errors import SimulationError
from tasks.quiet_pybullet import pybullet as pb

TIME_STEP_S = 1.0 / 480.0
SOLVER_ITERATIONS = 100
REST_LINEAR_SPEED_M_PER_S = 0.005
REST_ANGULAR_SPEED_RAD_PER_S = 0.05
REST_WINDOW_S = 0.05  # rest speeds are the pose's net change over this long (a chatter between contacts nets out) [s]
TRACE_FPS = 30.0
LOCK_INERTIA_FACTOR = 1e6  # rotational inertia x this locks rotation on the incline (rolling shapes test sliding)

Trace = list[tuple[float, tuple[float, float, float], tuple[float, float, float, float]]]
"""(sim time [s], centre-of-mass position [m], asset-frame orientation quaternion xyzw) samples at TRACE_FPS."""


@dataclass(frozen=True)
class RigidBodySpec:
    """What pybullet needs of the object: hulls [m], mass [kg], centre of mass [m], friction [-]."""

    hulls_m: Sequence[np.ndarray]
    mass_kg: float
    center_of_mass_m: np.ndarray
    friction: float

    @property
    def height_m(self) -> float:
        """Height of the proxy's bounding box [m]."""
        pts = np.vstack(self.hulls_m)
        return float(pts[:, 2].max() - pts[:, 2].min())


@contextmanager
def _world(gravity: tuple[float, float, float]) -> Iterator[int]:
    """A fresh DIRECT pybullet world with a ground plane at z = 0."""
    cid = pb.connect(pb.DIRECT)
    try:
        pb.setPhysicsEngineParameter(fixedTimeStep=TIME_STEP_S, numSolverIterations=SOLVER_ITERATIONS, physicsClientId=cid)
        pb.setGravity(*gravity, physicsClientId=cid)
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid)
        ground = pb.createMultiBody(0, plane, physicsClientId=cid)
        pb.changeDynamics(ground, -1, lateralFriction=1.0, restitution=0.0, physicsClientId=cid)
        yield cid
    finally:
        pb.disconnect(cid)


def _inertia_about_com(body: RigidBodySpec) -> np.ndarray:
    """Inertia tensor [kg m^2] of the hulls as one homogeneous solid of the body's mass, about its centre of mass."""
    hulls = [trimesh.convex.convex_hull(np.asarray(h, dtype=float)) for h in body.hulls_m]
    volume = sum(h.volume for h in hulls)
    if not volume > 0:
        raise SimulationError("the collision proxy has no volume")
    density = body.mass_kg / volume
    com = np.asarray(body.center_of_mass_m, dtype=float)
    inertia = np.zeros((3, 3))
    for h in hulls:
        h.density = density
        d = h.center_mass - com  # parallel-axis shift from the hull's own centre of mass
        inertia += h.moment_inertia + h.mass * (np.dot(d, d) * np.eye(3) - np.outer(d, d))
    return inertia


def _write_urdf(body: RigidBodySpec, folder: Path) -> Path:
    """A compound URDF: one convex collision per hull, inertial frame at the centre of mass."""
    com = np.asarray(body.center_of_mass_m, dtype=float)
    i = _inertia_about_com(body)
    parts = []
    for k, h in enumerate(body.hulls_m):
        hull = trimesh.convex.convex_hull(np.asarray(h, dtype=float))
        hull.export(folder / f"hull_{k:03d}.obj")
        parts.append(f'<collision><geometry><mesh filename="hull_{k:03d}.obj"/></geometry></collision>')
    urdf = folder / "object.urdf"
    urdf.write_text(
        '<?xml version="1.0"?><robot name="object"><link name="base"><inertial>'
        f'<origin xyz="{com[0]:.9g} {com[1]:.9g} {com[2]:.9g}"/><mass value="{body.mass_kg:.9g}"/>'
        f'<inertia ixx="{i[0, 0]:.9g}" ixy="{i[0, 1]:.9g}" ixz="{i[0, 2]:.9g}" iyy="{i[1, 1]:.9g}" iyz="{i[1, 2]:.9g}" '
        f'izz="{i[2, 2]:.9g}"/></inertial>' + "".join(parts) + "</link></robot>",
        encoding="utf-8",
    )
    return urdf


def _spawn(cid: int, body: RigidBodySpec, lift_m: float) -> int:
    """Load the object as a compound of convex hulls; pybullet's base frame is then its centre of mass."""
    with tempfile.TemporaryDirectory(prefix="ds-rigid-") as folder:
        urdf = _write_urdf(body, Path(folder))
        uid = pb.loadURDF(str(urdf), basePosition=(0.0, 0.0, lift_m), flags=pb.URDF_USE_INERTIA_FROM_FILE,
                          physicsClientId=cid)
    pb.changeDynamics(uid, -1, lateralFriction=body.friction, restitution=0.0, linearDamping=0.0, angularDamping=0.0,
                      frictionAnchor=1, physicsClientId=cid)
    return uid


def _pose(cid: int, uid: int) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    """(centre of mass [m], orientation of the asset frame xyzw) in the world.

    pybullet's base frame is the link's inertial frame, and Bullet turns it to the principal axes of the inertia
    tensor. For an asymmetric body (a duck: ixz != 0) that frame is tilted from the asset's axes from the start, so
    the base orientation is not the object's; the asset frame's orientation is base * inverse(local inertial frame).
    """
    pos, orn = pb.getBasePositionAndOrientation(uid, physicsClientId=cid)
    local_orn = pb.getDynamicsInfo(uid, -1, physicsClientId=cid)[4]
    _, inv_local = pb.invertTransform((0.0, 0.0, 0.0), local_orn)
    _, asset_orn = pb.multiplyTransforms((0.0, 0.0, 0.0), orn, (0.0, 0.0, 0.0), inv_local)
    return tuple(pos), tuple(asset_orn)


def _penetration_m(cid: int, uid: int) -> float:
    """Deepest current penetration of the object into anything [m] (0 when none)."""
    dists = [c[8] for c in pb.getContactPoints(bodyA=uid, physicsClientId=cid)]
    return float(max(0.0, -min(dists))) if dists else 0.0


def _lowest_point_m(cid: int, uid: int, body: RigidBodySpec) -> float:
    """Lowest z of the posed proxy [m] (negative = below the ground)."""
    pos, orn = _pose(cid, uid)
    rot = np.asarray(pb.getMatrixFromQuaternion(orn)).reshape(3, 3)
    pts = (np.vstack(body.hulls_m) - np.asarray(body.center_of_mass_m)) @ rot.T + np.asarray(pos)
    return float(pts[:, 2].min())


def _tilt_deg(orn: Sequence[float]) -> float:
    """Angle between the body's z axis (asset frame, see _pose) and the world's z axis [deg]."""
    rot = np.asarray(pb.getMatrixFromQuaternion(orn)).reshape(3, 3)
    return float(math.degrees(math.acos(float(np.clip(rot[2, 2], -1.0, 1.0)))))


def _sample(cid: int, uid: int, trace: Trace | None, t_s: float) -> None:
    """Append the body's pose to the trace when one is being recorded."""
    if trace is not None:
        pos, orn = _pose(cid, uid)
        trace.append((t_s, pos, orn))  # _pose returns tuples


def _turn_rad(q0: Sequence[float], q1: Sequence[float]) -> float:
    """The angle of the rotation from orientation q0 to q1 (xyzw quaternions) [rad]."""
    dot = abs(float(np.dot(q0, q1)))
    return 2.0 * math.atan2(math.sqrt(max(0.0, 1.0 - min(1.0, dot) ** 2)), dot)


def _settle(cid: int, uid: int, duration_s: float, trace: Trace | None = None, t0_s: float = 0.0) -> tuple[float, float]:
    """Step for duration; return (time after which the body stayed at rest [s] or inf, max penetration [m]). At rest:
    the pose's net change over the last REST_WINDOW_S under the rest speeds. pybullet's reported velocity is not used:
    a sausage resting on its cylinder-like hull chattered between contacts every step (0.08 rad/s there and back, its
    pose still), and the reported velocity never fell under the rest speed."""
    steps = int(round(duration_s / TIME_STEP_S))
    every = max(1, int(round(1.0 / (TRACE_FPS * TIME_STEP_S))))
    window = max(1, int(round(REST_WINDOW_S / TIME_STEP_S)))
    last_moving = 0
    max_pen = 0.0
    _sample(cid, uid, trace, t0_s)
    poses = collections.deque([pb.getBasePositionAndOrientation(uid, physicsClientId=cid)], maxlen=window)
    for i in range(steps):
        pb.stepSimulation(physicsClientId=cid)
        if (i + 1) % every == 0:
            _sample(cid, uid, trace, t0_s + (i + 1) * TIME_STEP_S)
        pos, orn = pb.getBasePositionAndOrientation(uid, physicsClientId=cid)
        was, turned = poses[0]
        span_s = len(poses) * TIME_STEP_S
        poses.append((pos, orn))
        v = float(np.linalg.norm(np.subtract(pos, was))) / span_s
        w = _turn_rad(turned, orn) / span_s
        if v > REST_LINEAR_SPEED_M_PER_S or w > REST_ANGULAR_SPEED_RAD_PER_S:
            last_moving = i + 1
        max_pen = max(max_pen, _penetration_m(cid, uid))
    settle = (last_moving * TIME_STEP_S) if last_moving < steps else math.inf
    return settle, max_pen


def placement_probe(body: RigidBodySpec, duration_s: float = 3.0, trace: Trace | None = None) -> dict[str, float]:
    """Set the object on the ground 1 mm up, let it settle; metrics: tilt, final penetration, settle time, drift."""
    with _world((0.0, 0.0, -9.81)) as cid:
        uid = _spawn(cid, body, lift_m=0.001)
        start, _ = _pose(cid, uid)
        settle_s, _ = _settle(cid, uid, duration_s, trace)
        pos, orn = _pose(cid, uid)
        return {
            "place_tilt_deg": _tilt_deg(orn),
            "place_penetration_m": max(_penetration_m(cid, uid), -_lowest_point_m(cid, uid, body)),
            "place_settle_time_s": settle_s,
            "place_drift_m": float(np.linalg.norm(np.subtract(pos[:2], start[:2]))),
        }


def drop_probe(
    body: RigidBodySpec, clearance_fraction: float = 0.25, duration_s: float = 3.0, trace: Trace | None = None
) -> dict[str, float]:
    """Drop from a clearance of a fraction of the object's height; metrics after the bounce and settle."""
    clearance = clearance_fraction * body.height_m
    with _world((0.0, 0.0, -9.81)) as cid:
        uid = _spawn(cid, body, lift_m=clearance)
        start, _ = _pose(cid, uid)
        settle_s, max_pen = _settle(cid, uid, duration_s, trace)
        pos, orn = _pose(cid, uid)
        return {
            "drop_clearance_m": clearance,
            "drop_penetration_m": max(_penetration_m(cid, uid), -_lowest_point_m(cid, uid, body)),
            "drop_max_transient_penetration_m": max_pen,
            "drop_rest_displacement_m": float(np.linalg.norm(np.subtract(pos[:2], start[:2]))),
            "drop_tilt_deg": _tilt_deg(orn),
            "drop_settle_time_s": settle_s,
        }


def _slope_motion(
    body: RigidBodySpec, theta_deg: float, settle_s: float, measure_s: float, trace: Trace | None = None
) -> tuple[float, float]:
    """Object on an incline of theta (gravity tilted, rotation locked by a huge inertia so rolling shapes test sliding).

    Returns (mean speed down the slope over the measuring window [m/s], fitted acceleration [m/s^2]).
    """
    th = math.radians(theta_deg)
    g = 9.81
    with _world((0.0, 0.0, -g)) as cid:
        uid = _spawn(cid, body, lift_m=0.001)
        _settle(cid, uid, settle_s, trace)
        # Rotation is locked by a huge rotational inertia, not by resetting the pose every step: a reset drops the
        # contact manifold and its friction anchors, and a body standing on one contact point at a time (a
        # polyhedral ball on a small facet) then crept down an incline below atan(mu) (1 cm/s at mu = 0.9).
        inertia = pb.getDynamicsInfo(uid, -1, physicsClientId=cid)[2]
        pb.changeDynamics(uid, -1, localInertiaDiagonal=[LOCK_INERTIA_FACTOR * i for i in inertia], physicsClientId=cid)
        linear, _ = pb.getBaseVelocity(uid, physicsClientId=cid)  # the lock keeps whatever spin the body had: a
        pb.resetBaseVelocity(uid, linearVelocity=linear, angularVelocity=(0.0, 0.0, 0.0), physicsClientId=cid)
        # banana still rocking at the lock turned on at 0.17 rad/s and crept up the incline at 3 mm/s below atan(mu)
        every = max(1, int(round(1.0 / (TRACE_FPS * TIME_STEP_S))))
        pb.setGravity(g * math.sin(th), 0.0, -g * math.cos(th), physicsClientId=cid)
        steps = int(round(measure_s / TIME_STEP_S))
        xs = np.empty(steps)
        for i in range(steps):
            pb.stepSimulation(physicsClientId=cid)
            pos, _ = pb.getBasePositionAndOrientation(uid, physicsClientId=cid)
            xs[i] = pos[0]
            if (i + 1) % every == 0:
                _sample(cid, uid, trace, settle_s + (i + 1) * TIME_STEP_S)
        t = (np.arange(steps) + 1) * TIME_STEP_S
        half = steps // 2
        mean_speed = float((xs[-1] - xs[half]) / (t[-1] - t[half]))
        accel = float(2.0 * np.polyfit(t[half:], xs[half:], 2)[0])
        return mean_speed, accel


def slide_probe(
    body: RigidBodySpec, margin_deg: float = 3.0, measure_s: float = 1.0, trace: Trace | None = None
) -> dict[str, float]:
    """Incline just below and just above atan(mu): sticks below, slides above with a = g (sin - mu cos)."""
    mu = body.friction
    critical = math.degrees(math.atan(mu))
    below, above = max(0.0, critical - margin_deg), min(89.0, critical + margin_deg)
    v_below, _ = _slope_motion(body, below, settle_s=0.3, measure_s=measure_s)
    v_above, a_above = _slope_motion(body, above, settle_s=0.3, measure_s=measure_s, trace=trace)
    th = math.radians(above)
    a_expected = 9.81 * (math.sin(th) - mu * math.cos(th))
    return {
        "slide_critical_angle_deg": critical,
        "slide_below_angle_deg": below,
        "slide_above_angle_deg": above,
        "slide_below_speed_m_per_s": v_below,
        "slide_below_sticks": float(abs(v_below) < 1e-3),
        "slide_above_slides": float(v_above > 1e-3),
        "slide_accel_m_per_s2": a_above,
        "slide_accel_expected_m_per_s2": a_expected,
        "slide_accel_error_rel": abs(a_above - a_expected) / a_expected,
    }
