"""The Franka Panda from pybullet_data, for kinematics only, in its own DIRECT pybullet client.

Frames: the world frame is the table frame (z up, the table top is z = 0, which is the MPM ground); the robot base
stands on the table at ``base_position_m`` (default (-0.5, 0, 0), next to an object at the origin). The end-effector
frame is link 11 ``panda_grasptarget`` (0.105 m past the hand): its z axis is the approach direction, its y axis points
from the grasp centre to the left finger (joint 9). pybullet ignores ``<mimic>``: the two finger joints are coupled
here, each at half the opening. Lengths in metres, angles in radians unless a name says ``_deg``.

Another gripper (contracts/grippers/*.yaml, ``Panda(gripper=name)``) is mounted on the flange (link 7,
``panda_link8``): the end-effector frame is then its TCP (the pad-face midpoint, ``tcp_offset_m`` along the flange z,
turned by ``tcp_yaw_deg``), its pads sit at +-(opening / 2) along the TCP y axis, and its body and fingers are the
record's boxes; the URDF's own hand links are then ignored (not in IK, pads or the table test).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from contracts.errors import SimulationError
from contracts.robot import DEFAULT_GRIPPER
from tasks.quiet_pybullet import pybullet as pb
from tasks.robot.franka_hand import PadGeometry, data_path, pad_geometry
from tasks.robot.gripper import gripper as load, lowest_box_point

URDF = "franka_panda/panda.urdf"
ARM_JOINTS = (0, 1, 2, 3, 4, 5, 6)
FINGER_JOINTS = (9, 10)
HAND_LINK = 8
EE_LINK = 11
FLANGE_LINK = 7  # panda_link8, where a gripper without a URDF is mounted
ARM_LINKS_WITH_COLLISION = tuple(range(1, 7))
URDF_HAND_LINKS = (8, 9, 10)
FINGER_LINKS = (9, 10)
MAX_OPENING_M = 0.08
DEFAULT_BASE_POSITION_M = (-0.5, 0.0, 0.0)
# A standard Panda "ready" configuration: the IK seed and null-space rest pose, not a solution for any target.
READY_Q = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
POSITION_TOL_M = 5e-4  # accepted IK residual [m]
ROTATION_TOL_RAD = np.radians(0.5)  # accepted IK residual [rad]
POLISH_POSITION_M = 2e-5  # the polish stops below these
POLISH_ROTATION_RAD = np.radians(0.02)
LIMIT_BAND_RAD = 0.2

Vec3 = Sequence[float] | np.ndarray  # a point or direction, list or array


class UnreachableError(SimulationError):
    """The Panda cannot reach a requested end-effector pose within tolerance and joint limits."""


@dataclass(frozen=True)
class IKSolution:
    """Arm joint angles [rad] for a target pose and the FK residuals that verify them."""

    q: np.ndarray
    position_error_m: float
    rotation_error_rad: float
    iterations: int


def grasp_rotation(closing_axis: Vec3, approach_axis: Vec3) -> np.ndarray:
    """End-effector rotation (columns x, y, z in the world) for a grasp: z = approach, y = -closing (left finger)."""
    a = np.asarray(approach_axis, dtype=float)
    a = a / np.linalg.norm(a)
    u = np.asarray(closing_axis, dtype=float)
    u = u - np.dot(u, a) * a
    n = np.linalg.norm(u)
    if n < 1e-9:
        raise ValueError("closing axis is parallel to the approach axis")
    y = -u / n
    x = np.cross(y, a)
    return np.column_stack([x, y, a])


def rotation_error(r_target: np.ndarray, r_current: np.ndarray) -> np.ndarray:
    """Axis-angle vector [rad] that rotates r_current onto r_target, in the world frame."""
    d = r_target @ r_current.T
    angle = np.arccos(np.clip((np.trace(d) - 1.0) / 2.0, -1.0, 1.0))
    if angle < 1e-12:
        return np.zeros(3)
    w = np.array([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
    if np.pi - angle < 1e-6:  # near pi: the skew part vanishes, take the axis from the symmetric part
        axis = np.sqrt(np.clip((np.diag(d) + 1.0) / 2.0, 0.0, None))
        k = int(np.argmax(axis))
        axis = (d[:, k] + np.eye(3)[:, k]) / (2.0 * axis[k])
        return angle * axis / np.linalg.norm(axis)
    return angle * w / (2.0 * np.sin(angle))


def _quat_to_matrix(q: Sequence[float]) -> np.ndarray:
    """3x3 rotation of a pybullet quaternion (x, y, z, w)."""
    return np.asarray(pb.getMatrixFromQuaternion(q), dtype=float).reshape(3, 3)


def matrix_to_quat(r: np.ndarray) -> np.ndarray:
    """Quaternion (x, y, z, w) of a 3x3 rotation matrix."""
    m = np.asarray(r, dtype=float)
    t = np.trace(m)
    if t > 0:
        s = 2.0 * np.sqrt(t + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0, 0.0, 0.0, (m[k, j] - m[j, k]) / s]
        q[i] = 0.25 * s
        q[j] = (m[j, i] + m[i, j]) / s
        q[k] = (m[k, i] + m[i, k]) / s
    quat = np.asarray(q)
    return quat / np.linalg.norm(quat)


class Panda:
    """A fixed-base Panda in a private DIRECT client: coupled fingers, forward and inverse kinematics."""

    def __init__(self, base_position_m: Sequence[float] = DEFAULT_BASE_POSITION_M, base_yaw_rad: float = 0.0,
                 pad_half_thickness_m: float = 0.004, gripper: str = DEFAULT_GRIPPER) -> None:
        """Load the URDF with its base at base_position_m [m] (world = table frame), turned by base_yaw_rad about z.

        pad_half_thickness_m: half thickness of the pad boxes [m]; they grow outward from the gripping face, so a
        thicker pad (e.g. >= the MPM grid spacing) changes no contact geometry, only what a coarse grid resolves.
        gripper: the gripper on the flange (contracts/grippers/<name>.yaml).
        """
        self.gripper = load(gripper)
        spec = self.gripper.spec
        self.ee_link = EE_LINK if spec.urdf_hand else FLANGE_LINK
        yaw = np.radians(spec.tcp_yaw_deg)
        # the TCP in the end-effector link's frame: the URDF grasp target itself, or the record's offset on the flange
        self._tcp_pos = np.zeros(3) if spec.urdf_hand else np.array([0.0, 0.0, spec.tcp_offset_m])
        self._tcp_rot = np.eye(3) if spec.urdf_hand else np.array(
            [[np.cos(yaw), -np.sin(yaw), 0.0], [np.sin(yaw), np.cos(yaw), 0.0], [0.0, 0.0, 1.0]])
        self._opening = (spec.stroke_m, 0.0)  # a data gripper's opening [m] and its rate [m/s]
        self.cid = pb.connect(pb.DIRECT)
        self.base_position_m = np.asarray(base_position_m, dtype=float)
        orn = pb.getQuaternionFromEuler((0.0, 0.0, base_yaw_rad))
        self.body = pb.loadURDF(str(data_path() / URDF), self.base_position_m.tolist(), orn, useFixedBase=True,
                                physicsClientId=self.cid)
        info = [pb.getJointInfo(self.body, j, physicsClientId=self.cid) for j in ARM_JOINTS]
        self.lower = np.array([i[8] for i in info])
        self.upper = np.array([i[9] for i in info])
        self.velocity_limits = np.array([i[11] for i in info])
        if spec.urdf_hand:
            self.pads = pad_geometry(float(pad_half_thickness_m))
        else:  # the pads at the TCP, +-(opening / 2) along its y axis, growing outward from their faces
            hx, _, hz = self.gripper.pad_half_extents_m
            ht = float(pad_half_thickness_m)
            self.pads = PadGeometry((0.0, ht, 0.0), (0.0, -ht, 0.0), (hx, ht, hz), 0.0,
                                    self.gripper.tip_beyond_center_m)
        self._movable = [j for j in range(pb.getNumJoints(self.body, physicsClientId=self.cid))
                         if pb.getJointInfo(self.body, j, physicsClientId=self.cid)[2] != pb.JOINT_FIXED]
        self.set_joints(np.asarray(READY_Q), spec.stroke_m)

    def close(self) -> None:
        """Disconnect the private pybullet client."""
        if self.cid >= 0:
            pb.disconnect(self.cid)
            self.cid = -1

    def __enter__(self) -> Panda:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- state --------------------------------------------------------------------------------------------------
    def set_joints(self, q: np.ndarray, opening_m: float, qdot: np.ndarray | None = None,
                   opening_rate_m_per_s: float = 0.0) -> None:
        """Set arm angles [rad] and rates [rad/s], and the finger opening [m] and its rate [m/s] (each finger half)."""
        qdot = np.zeros(7) if qdot is None else qdot
        for j, qj, vj in zip(ARM_JOINTS, q, qdot):
            pb.resetJointState(self.body, j, float(qj), float(vj), physicsClientId=self.cid)
        self._opening = (float(np.clip(opening_m, 0.0, self.gripper.stroke_m)), float(opening_rate_m_per_s))
        half = float(np.clip(opening_m, 0.0, MAX_OPENING_M)) / 2.0
        for j in FINGER_JOINTS:  # the mimic coupling pybullet ignores
            pb.resetJointState(self.body, j, half, opening_rate_m_per_s / 2.0, physicsClientId=self.cid)

    def finger_positions(self) -> tuple[float, float]:
        """Current positions of finger joints 9 and 10 [m]."""
        return tuple(pb.getJointState(self.body, j, physicsClientId=self.cid)[0] for j in FINGER_JOINTS)

    def link_pose(self, link: int) -> tuple[np.ndarray, np.ndarray]:
        """World position [m] and rotation matrix of a link's URDF frame at the current joint state."""
        s = pb.getLinkState(self.body, link, computeForwardKinematics=1, physicsClientId=self.cid)
        return np.asarray(s[4]), _quat_to_matrix(s[5])

    def opening(self) -> float:
        """Current finger opening [m] (the gap between the pad faces)."""
        if self.gripper.spec.urdf_hand:
            return float(sum(self.finger_positions()))
        return self._opening[0]

    def ee_pose(self, q: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Forward kinematics of the end-effector (TCP) frame [m], optionally at arm angles q [rad]."""
        if q is not None:
            for j, qj in zip(ARM_JOINTS, q):
                pb.resetJointState(self.body, j, float(qj), physicsClientId=self.cid)
        p, r = self.link_pose(self.ee_link)
        return p + r @ self._tcp_pos, r @ self._tcp_rot

    def _link_target(self, position: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pose of the end-effector link [m] that puts the TCP at a pose."""
        r_link = rotation @ self._tcp_rot.T
        return position - r_link @ self._tcp_pos, r_link

    def pad_states(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per finger (left, right): pad box centre [m], rotation, linear [m/s] and angular [rad/s] velocity."""
        return [(p, r, v, w) for p, _, r, v, w in self.pad_states_with_quat()]

    def pad_states_with_quat(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per finger (left, right): pad centre [m], quaternion (x, y, z, w), rotation, velocities [m/s, rad/s]."""
        if not self.gripper.spec.urdf_hand:
            return self._data_pad_states()
        out = []
        states = pb.getLinkStates(self.body, list(FINGER_LINKS), computeLinkVelocity=1, computeForwardKinematics=1,
                                  physicsClientId=self.cid)
        for s, centre in zip(states, (self.pads.center_left_m, self.pads.center_right_m)):
            rot = _quat_to_matrix(s[5])
            pos = np.asarray(s[4]) + rot @ np.asarray(centre)
            # pybullet reports the velocity of the link's centre of mass (s[0]); move it to the pad centre
            w = np.asarray(s[7])
            r = pos - np.asarray(s[0])
            v = np.asarray(s[6]) + np.array([w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2],
                                             w[0] * r[1] - w[1] * r[0]])
            out.append((pos, np.asarray(s[5]), rot, v, w))
        return out

    def _data_pad_states(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Pads of a gripper without a URDF: at the TCP +-(opening / 2 + half thickness) along its y axis, turned as
        the TCP; velocities from the flange link's and the opening rate."""
        s = pb.getLinkState(self.body, self.ee_link, computeLinkVelocity=1, computeForwardKinematics=1,
                            physicsClientId=self.cid)
        r_link = _quat_to_matrix(s[5])
        tcp, rot = np.asarray(s[4]) + r_link @ self._tcp_pos, r_link @ self._tcp_rot
        quat = matrix_to_quat(rot)
        w = np.asarray(s[7])
        opening, rate = self._opening
        out = []
        for sign in (1.0, -1.0):  # finger 0 (left) on +y
            pos = tcp + rot @ np.array([0.0, sign * (opening / 2.0 + self.pads.half_extents_m[1]), 0.0])
            v = np.asarray(s[6]) + np.cross(w, pos - np.asarray(s[0])) + rot @ np.array([0.0, sign * rate / 2.0, 0.0])
            out.append((pos, quat, rot, v, w))
        return out

    def gripper_boxes_world(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The gripper's collision boxes (palm, finger 0, finger 1) at the current state: centre [m], rotation (columns
        = box axes) and half extents [m] in the world (what a renderer draws for a gripper without a URDF mesh)."""
        p, r = self.ee_pose()
        return [(p + r @ (0.5 * (lo + hi)), r, 0.5 * (hi - lo)) for lo, hi in self.gripper.boxes(self.opening())]

    def lowest_point(self) -> float:
        """Lowest point [m] of the robot below the base (arm links and gripper) at the current joint state."""
        if self.gripper.spec.urdf_hand:
            return float(self.link_heights((*ARM_LINKS_WITH_COLLISION, FLANGE_LINK, *URDF_HAND_LINKS)).min())

        p, r = self.ee_pose()
        boxes = self.gripper.boxes(self.opening())
        return min(float(self.link_heights(ARM_LINKS_WITH_COLLISION).min()), lowest_box_point(boxes, p, r))

    def link_heights(self, links: Sequence[int]) -> np.ndarray:
        """Lowest point [m] of each link's collision geometry at the current joint state.

        Exact: the lowest vertex of the link's collision mesh (convex hull) in the world. pybullet's ``getAABB`` is
        not used for meshes: it pads every shape by Bullet's collision margin (4 mm for the Panda's meshes) and, for a
        turned link, bounds a turned local box, so it put fingertips that clear the table by 3 mm "into" it. A link
        without a mesh falls back to its AABB.
        """
        links = list(links)
        states = pb.getLinkStates(self.body, links, computeForwardKinematics=1, physicsClientId=self.cid)
        out = np.empty(len(links))
        for i, (link, s) in enumerate(zip(links, states)):
            shapes = self._collision_vertices(link)
            if not shapes:
                out[i] = pb.getAABB(self.body, link, physicsClientId=self.cid)[0][2]
                continue
            # collision shapes are placed relative to the link's inertial frame (s[0], s[1])
            rot_z = _quat_to_matrix(s[1])[2]
            out[i] = float(s[0][2]) + min(float(np.min(v @ (rot_z @ rc)) + rot_z @ pc) for v, pc, rc in shapes)
        return out

    def _collision_vertices(self, link: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Per collision mesh of a link: convex-hull vertices in the shape's frame [m] (scaled), and the shape's
        position [m] and rotation in the link's inertial frame (cached; [] where a shape is not a mesh)."""
        cache = self.__dict__.setdefault("_hull_cache", {})
        if link not in cache:
            import trimesh

            shapes = []
            for d in pb.getCollisionShapeData(self.body, link, physicsClientId=self.cid):
                name = d[4].decode() if isinstance(d[4], bytes) else d[4]
                if d[2] != pb.GEOM_MESH or not name:
                    return cache.setdefault(link, [])
                mesh = trimesh.load(name, force="mesh")
                v = np.asarray(mesh.convex_hull.vertices) * np.asarray(d[3])
                shapes.append((v, np.asarray(d[5], dtype=float), _quat_to_matrix(d[6])))
            cache[link] = shapes
        return cache[link]

    # --- inverse kinematics -------------------------------------------------------------------------------------
    def ee_target_for_grasp(self, center_m: Vec3, rotation: np.ndarray) -> np.ndarray:
        """End-effector position [m] that puts the pad centres' midpoint at a grasp centre [m]."""
        offset = self.gripper.tcp_beyond_pad_center_m
        # the pads sit symmetrically in x and y of the hand, so only the depth along the approach axis differs
        return np.asarray(center_m, dtype=float) + rotation @ np.array([0.0, 0.0, offset])

    def _jacobian(self, q: np.ndarray) -> np.ndarray:
        """6x7 geometric Jacobian of the end-effector (linear over angular) at q."""
        full = np.zeros(len(self._movable))
        full[:7] = q
        full[7:] = self.finger_positions()
        jl, ja = pb.calculateJacobian(self.body, self.ee_link, self._tcp_pos.tolist(), full.tolist(),
                                      [0.0] * len(full), [0.0] * len(full), physicsClientId=self.cid)
        return np.vstack([np.asarray(jl)[:, :7], np.asarray(ja)[:, :7]])

    def _errors(self, q: np.ndarray, position: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Position [m] and rotation [rad] error vectors of the end-effector at q."""
        p, r = self.ee_pose(q)
        return position - p, rotation_error(rotation, r)

    def _polish(self, q: np.ndarray, position: np.ndarray, rotation: np.ndarray, rest: np.ndarray,
                iterations: int) -> tuple[np.ndarray, int]:
        """Damped least squares on the exact Jacobian, inside joint limits, with a weak pull towards rest."""
        for it in range(iterations):
            ep, er = self._errors(q, position, rotation)
            if np.linalg.norm(ep) < POLISH_POSITION_M and np.linalg.norm(er) < POLISH_ROTATION_RAD:
                return q, it
            e = np.concatenate([ep, 0.3 * er])  # 0.3 m: length scale that weighs radians against metres
            jac = self._jacobian(q)
            jac[3:] *= 0.3
            lam2 = 1e-6 + 1e-2 * float(e @ e)
            jjt = jac @ jac.T + lam2 * np.eye(6)
            dq = jac.T @ np.linalg.solve(jjt, e)
            pinv = jac.T @ np.linalg.solve(jac @ jac.T + 1e-9 * np.eye(6), np.eye(6))
            # null space: towards rest, kept LIMIT_BAND_RAD inside the joint limits (steers away from the limits)
            goal = np.clip(rest, self.lower + LIMIT_BAND_RAD, self.upper - LIMIT_BAND_RAD)
            dq += (np.eye(7) - pinv @ jac) @ (0.05 * (goal - q))
            step = np.max(np.abs(dq))
            if step > 0.2:
                dq *= 0.2 / step
            q = np.clip(q + dq, self.lower, self.upper)
        return q, iterations

    def solve_ik(self, position_m: Vec3, rotation: np.ndarray, seed: np.ndarray | None = None,
                 rest: np.ndarray | None = None, max_iterations: int = 200) -> IKSolution:
        """Arm angles that put the end-effector at a world pose; verified by FK, or UnreachableError.

        pybullet's null-space IK (joint limits, ranges, rest poses) gives the first guess from the seed; a damped
        least-squares polish on the exact Jacobian brings it to tolerance; a few deterministic restarts are tried.
        """
        position = np.asarray(position_m, dtype=float)
        rest = np.asarray(READY_Q if rest is None else rest, dtype=float)
        seeds = [np.asarray(seed, dtype=float)] if seed is not None else []
        seeds += [np.asarray(READY_Q), *(np.asarray(READY_Q) + d for d in _restart_offsets())]
        link_position, link_rotation = self._link_target(position, rotation)
        quat = matrix_to_quat(link_rotation)
        best: IKSolution | None = None
        fingers = self.finger_positions()
        opening = self.opening()
        for s in seeds:
            self.set_joints(np.clip(s, self.lower, self.upper), opening)
            lower = [*self.lower, 0.0, 0.0]
            upper = [*self.upper, 0.04, 0.04]
            q0 = pb.calculateInverseKinematics(
                self.body, self.ee_link, link_position.tolist(), quat.tolist(), lowerLimits=lower, upperLimits=upper,
                jointRanges=[u - lo for u, lo in zip(upper, lower)], restPoses=[*rest, *fingers],
                maxNumIterations=100, residualThreshold=1e-6, physicsClientId=self.cid)
            q = np.clip(np.asarray(q0[:7]), self.lower, self.upper)
            q, its = self._polish(q, position, rotation, rest, max_iterations)
            ep, er = self._errors(q, position, rotation)
            sol = IKSolution(q, float(np.linalg.norm(ep)), float(np.linalg.norm(er)), its)
            if best is None or (sol.position_error_m + 0.1 * sol.rotation_error_rad
                                < best.position_error_m + 0.1 * best.rotation_error_rad):
                best = sol
            if sol.position_error_m <= POSITION_TOL_M and sol.rotation_error_rad <= ROTATION_TOL_RAD:
                self.set_joints(sol.q, opening)
                return sol
        assert best is not None
        self.set_joints(best.q, opening)
        raise UnreachableError(
            f"Panda cannot reach end-effector position {np.round(position, 4).tolist()} m with the requested "
            f"orientation (base at {self.base_position_m.tolist()} m): best residual "
            f"{best.position_error_m * 1000:.1f} mm, {np.degrees(best.rotation_error_rad):.1f} deg "
            f"(tolerance {POSITION_TOL_M * 1000:.1f} mm, {np.degrees(ROTATION_TOL_RAD):.1f} deg)")

    def track_ik(self, position_m: Vec3, rotation: np.ndarray, seed: np.ndarray) -> IKSolution:
        """IK for a pose close to the one at ``seed`` (a path step): polish from the seed, falling back to solve_ik."""
        position = np.asarray(position_m, dtype=float)
        q, its = self._polish(np.asarray(seed, dtype=float), position, rotation, np.asarray(seed, dtype=float), 100)
        ep, er = self._errors(q, position, rotation)
        if np.linalg.norm(ep) <= POSITION_TOL_M and np.linalg.norm(er) <= ROTATION_TOL_RAD:
            return IKSolution(q, float(np.linalg.norm(ep)), float(np.linalg.norm(er)), its)
        return self.solve_ik(position, rotation, seed=seed, rest=seed)

    def solve_grasp_ik(self, center_m: Vec3, closing_axis: Vec3, approach_axis: Vec3, seed: np.ndarray | None = None,
                       rest: np.ndarray | None = None) -> IKSolution:
        """Arm angles that put the pad centres' midpoint at a grasp centre [m] with the grasp's axes (world)."""
        rot = grasp_rotation(closing_axis, approach_axis)
        return self.solve_ik(self.ee_target_for_grasp(center_m, rot), rot, seed=seed, rest=rest)


def _restart_offsets() -> list[np.ndarray]:
    """Deterministic joint offsets [rad] from the ready pose for IK restarts."""
    return [np.array([0.0, 0.4, 0.0, 0.6, 0.0, -0.4, 0.0]),
            np.array([0.0, -0.3, 0.0, -0.4, 0.0, 0.5, 0.0]),
            np.array([0.8, 0.2, 0.0, 0.2, 0.0, 0.0, 0.0]),
            np.array([-0.8, 0.2, 0.0, 0.2, 0.0, 0.0, 0.0])]
