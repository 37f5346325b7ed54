"""The robot as drawable triangles: the Panda's URDF visual meshes posed by FK at recorded joint states, and a gripper
without a URDF mesh (a GripperSpec of contracts/grippers) as boxes around its recorded finger pads.

The visual meshes of pybullet_data's franka_panda (visual/*.obj, collision/*.obj where the URDF uses those) are placed
in their link frames (the URDF's visual origin) and coarsened by vertex clustering for the CPU rasteriser; link poses
come from pybullet's forward kinematics in a private DIRECT client (tasks.robot.Panda). A box gripper is drawn in the
TCP frame rebuilt from the recorded pads (origin between the pad faces, y towards finger 0, z along the approach), so
it follows what the trial simulated whatever the gripper. Lengths in metres.

Robot knowledge, not drawing (#37): plain arrays out, nothing from tasks.render in; the renderers (tasks.render) sit
below the robot and draw what this gives them.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from contracts.errors import InputError
from contracts.robot import load_gripper
from tasks.quiet_pybullet import pybullet as pb
from tasks.render.gripper_model import unit_box
from tasks.robot.panda import Panda

ARM_RGB = np.array([0.93, 0.93, 0.95])      # the Panda's white links
DARK_RGB = np.array([0.20, 0.20, 0.23])     # fingers, a box gripper's body
PAD_RGB = np.array([0.35, 0.36, 0.40])      # a box gripper's fingers
LIGHT_DIR = np.array([0.35, -0.45, 0.82]) / np.linalg.norm([0.35, -0.45, 0.82])
CLUSTER_CELL_M = 0.004                      # vertex-clustering cell of the visual meshes
HAND_LINKS = ("panda_hand", "panda_leftfinger", "panda_rightfinger")
FLANGE_LINK = "panda_link8"


@dataclass(frozen=True)
class LinkMesh:
    """One link's visual mesh in its URDF link frame: vertices [m], faces, unit vertex normals, base colour."""

    name: str
    vertices_m: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    rgb: np.ndarray


def _rpy_matrix(rpy: list[float]) -> np.ndarray:
    """URDF roll-pitch-yaw -> rotation matrix."""
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


def cluster_decimate(vertices_m: np.ndarray, faces: np.ndarray, cell_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Coarsen a mesh by vertex clustering: vertices in one grid cell merge at their mean; collapsed and repeated
    faces are dropped (winding kept). Deterministic."""
    v = np.asarray(vertices_m, np.float64)
    key = np.floor(v / cell_m).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    count = np.bincount(inv)
    merged = np.stack([np.bincount(inv, weights=v[:, k]) for k in range(3)], axis=1) / count[:, None]
    f = inv[np.asarray(faces, np.int64)]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    # drop repeats of the same triangle (same vertex set and winding)
    rolled = np.stack([np.roll(f, -k, axis=1) for k in range(3)])
    canon = rolled[np.argmin(rolled[:, :, 0], axis=0), np.arange(len(f))]
    _, first = np.unique(canon, axis=0, return_index=True)
    f = f[np.sort(first)]
    used, f = np.unique(f, return_inverse=True)
    return merged[used], f.reshape(-1, 3)


def vertex_normals(vertices_m: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted unit vertex normals of a mesh wound outward."""
    v = np.asarray(vertices_m, np.float64)
    fn = np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, faces[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)


@lru_cache(maxsize=2)
def panda_visual_meshes(cell_m: float = CLUSTER_CELL_M) -> tuple[LinkMesh, ...]:
    """The URDF's visual meshes of every Panda link, in link frames, coarsened to cell_m (cached per process)."""
    import pybullet_data
    import trimesh

    root = Path(pybullet_data.getDataPath()) / "franka_panda"
    out = []
    for link in ET.parse(root / "panda.urdf").getroot().iter("link"):
        vis = link.find("visual")
        mesh_el = vis.find("geometry/mesh") if vis is not None else None
        if vis is None or mesh_el is None:
            continue
        origin = vis.find("origin")
        xyz = [float(x) for x in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        rpy = [float(x) for x in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        mesh = trimesh.load(root / mesh_el.get("filename", "").replace("package://", ""), force="mesh",
                            skip_materials=True)
        v = np.asarray(mesh.vertices) @ _rpy_matrix(rpy).T + np.asarray(xyz)
        v, f = cluster_decimate(v, np.asarray(mesh.faces), cell_m)
        name = link.get("name", "")
        rgb = DARK_RGB if name in ("panda_leftfinger", "panda_rightfinger") else ARM_RGB
        out.append(LinkMesh(name, v, f, vertex_normals(v, f), rgb))
    return tuple(out)


def link_poses(q_rad: np.ndarray, opening_m: np.ndarray) -> list[dict[str, tuple[np.ndarray, np.ndarray]]]:
    """Per robot state (arm angles [rad], finger opening [m]), each Panda link's world pose (position [m], rotation)
    by pybullet FK in a private DIRECT client, the base link included."""
    poses = []
    with Panda() as panda:
        names = {pb.getJointInfo(panda.body, j, physicsClientId=panda.cid)[12].decode(): j
                 for j in range(pb.getNumJoints(panda.body, physicsClientId=panda.cid))}
        base = pb.getBodyInfo(panda.body, physicsClientId=panda.cid)[0].decode()
        base_pos, base_orn = pb.getBasePositionAndOrientation(panda.body, physicsClientId=panda.cid)
        base_rot = np.asarray(pb.getMatrixFromQuaternion(base_orn)).reshape(3, 3)
        for qk, wk in zip(np.asarray(q_rad), np.asarray(opening_m)):
            panda.set_joints(np.asarray(qk), float(wk))
            frame = {base: (np.asarray(base_pos, np.float64), base_rot)}
            frame.update({n: panda.link_pose(j) for n, j in names.items()})
            poses.append(frame)
    return poses


def gripper_spec(plan: dict[str, Any] | None) -> Any:
    """The GripperSpec a recorded plan names (contracts/grippers), or None (older data: the URDF's Franka Hand).
    A name this installation does not know gives a stand-in without a URDF hand: boxes from the recorded pads alone."""
    from types import SimpleNamespace

    name = (plan or {}).get("gripper")
    if not name:
        return None
    try:
        return load_gripper(str(name))
    except (ImportError, InputError):
        return SimpleNamespace(name=str(name), urdf_hand=False)


def uses_urdf_hand(spec: Any) -> bool:
    """Whether the URDF's own hand and fingers are drawn (no spec, or a spec that is the URDF's hand)."""
    return spec is None or bool(getattr(spec, "urdf_hand", False))


def tcp_frame(pad_position_m: np.ndarray, pad_half_extents_m: np.ndarray, approach_world: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, float]:
    """The TCP frame of two recorded pads: origin between the pad faces [m], rotation (columns x, y towards finger 0,
    z along the approach) and the opening between the faces [m] (pad boxes grow outward from their faces)."""
    p0, p1 = np.asarray(pad_position_m[0], np.float64), np.asarray(pad_position_m[1], np.float64)
    y = p0 - p1
    sep = float(np.linalg.norm(y))
    y = y / max(sep, 1e-12)
    z = np.asarray(approach_world, np.float64) - float(np.dot(approach_world, y)) * y
    z /= max(float(np.linalg.norm(z)), 1e-12)
    return 0.5 * (p0 + p1), np.column_stack([np.cross(y, z), y, z]), max(0.0, sep - 2.0 * float(pad_half_extents_m[1]))


def gripper_boxes(pad_position_m: np.ndarray, pad_half_extents_m: np.ndarray, approach_world: np.ndarray,
                  spec: Any = None) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """A gripper without a URDF mesh as boxes (centre [m], rotation, half extents [m], colour): its body and two
    fingers, from the recorded pads and, when given, the GripperSpec's body box and finger sizes (TCP frame)."""
    origin, rot, opening = tcp_frame(pad_position_m, pad_half_extents_m, approach_world)
    half = np.asarray(pad_half_extents_m, np.float64)
    pad = getattr(spec, "pad", None)
    tip = float(pad.tip_beyond_center_m) if pad is not None else float(half[2])
    half_w = float(getattr(spec, "finger_half_width_m", None) or half[0])
    thick = float(getattr(spec, "finger_thickness_m", None) or 2.0 * half[1])
    top = float(getattr(spec, "finger_top_m", None) or -(3.0 * half[2] + 0.03))
    palm = getattr(spec, "palm_box", None)
    if palm is not None:
        lo, hi = np.asarray(palm.lo_m, np.float64), np.asarray(palm.hi_m, np.float64)
    else:  # a body as wide as the fingers' outer faces, 6 cm deep above them
        reach = 0.5 * opening + thick
        lo, hi = np.array([-half_w - 0.01, -reach, top - 0.06]), np.array([half_w + 0.01, reach, top])
    boxes = [(lo, hi, DARK_RGB)]
    for sign in (1.0, -1.0):  # finger 0 at +y, finger 1 at -y, each outward from its face
        face, back = sign * 0.5 * opening, sign * (0.5 * opening + thick)
        boxes.append((np.array([-half_w, min(face, back), top]), np.array([half_w, max(face, back), tip]), PAD_RGB))
    return [(origin + rot @ (0.5 * (a + b)), rot, 0.5 * (b - a), c) for a, b, c in boxes]


def box_mesh(center_m: np.ndarray, rotation: np.ndarray, half_extents_m: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World vertices [m], faces and normals of a posed box."""
    v, f, n = unit_box()
    r = np.asarray(rotation)
    return (v * np.asarray(half_extents_m)) @ r.T + np.asarray(center_m), f, n @ r.T


def shade(normals_world: np.ndarray, rgb: np.ndarray, view_dir: np.ndarray) -> np.ndarray:
    """Per-vertex colour in [0, 1]: ambient, a key light from above and a weak fill from the camera."""
    key = np.clip(normals_world @ LIGHT_DIR, 0.0, None)
    fill = np.clip(-(normals_world @ view_dir), 0.0, None)
    k = 0.38 + 0.5 * key + 0.17 * fill
    return np.clip(k[:, None] * np.asarray(rgb)[None, :], 0.0, 1.0)


def robot_meshes(pose: dict[str, tuple[np.ndarray, np.ndarray]], pad_position_m: np.ndarray,
                 pad_half_extents_m: np.ndarray, spec: Any, view_dir: np.ndarray
                 ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, bool]]:
    """World-posed triangles of the robot at one state: (vertices [m], faces, vertex colours, is_gripper) per part.
    The URDF's hand and fingers, or for another gripper its boxes around the recorded pads."""
    urdf_hand = uses_urdf_hand(spec)
    parts = []
    for link in panda_visual_meshes():
        if link.name not in pose or (not urdf_hand and link.name in HAND_LINKS):
            continue
        p, r = pose[link.name]
        n = link.normals @ r.T
        parts.append((link.vertices_m @ r.T + p, link.faces, shade(n, link.rgb, view_dir), link.name in HAND_LINKS))
    if not urdf_hand:
        approach = pose[FLANGE_LINK][1][:, 2] if FLANGE_LINK in pose else np.array([0.0, 0.0, -1.0])
        for c, r, h, rgb in gripper_boxes(pad_position_m, pad_half_extents_m, approach, spec):
            v, f, n = box_mesh(c, r, h)
            parts.append((v, f, shade(n, rgb, view_dir), True))
    return parts
