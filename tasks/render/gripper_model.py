"""The Robotiq 2F-85 and 2F-140 adaptive grippers as drawable links: a faithful model of their parts, not boxes.

Each is a coupling and a rounded housing on the flange, and per finger the four-bar linkage of the real gripper: the
outer knuckle (driver, grey metal) and outer finger (coupler) on the outer pivot, the inner knuckle on the inner pivot,
and the inner finger that carries the silicone pad, kept parallel to the closing plane (parallel-grip mode). The
linkage is posed by its knuckle angle, solved so that the pad face lies where the trial's pad was (the recorded pads
are the MPM colliders); the inner finger reaches from the linkage to that pad, so the pads drawn are the simulated
ones exactly.

Dimensions (metres) are this project's own model of the links, measured from the public kinematic description of
the 2F-85 in MuJoCo Menagerie (google-deepmind/mujoco_menagerie, robotiq_2f85/2f85.xml, BSD-2-Clause: pivot
positions (0, +-0.0306, 0.0549) and (0, +-0.0132, 0.0609) above the base, knuckle (0.055, 0.0375), pad 22 x 37.5 mm)
and from Robotiq's datasheets (2F-85: 85 mm stroke, ~75 mm housing; 2F-140: 140 mm stroke, the same housing with
longer knuckles, pad 27 x 46 mm); no CAD file or mesh is copied. The 2F-140's knuckle length is the one that opens
its pads 140 mm with the 2F-85's pivot layout.

Frame G (the gripper's): origin on the flange, z along the approach (towards the fingertips), y towards finger 0
(the TCP frame's axes, tasks.robot.visual.tcp_frame), x = y cross z. Numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike

BLACK = np.array([0.13, 0.13, 0.14])
METAL = np.array([0.62, 0.63, 0.66])
SILICONE = np.array([0.22, 0.22, 0.24])
COUPLING = np.array([0.30, 0.30, 0.32])


@dataclass(frozen=True)
class RobotiqLinks:
    """One adaptive gripper's link dimensions in frame G [m]."""

    name: str
    mount_m: float  # coupling height between the flange and the housing
    housing_radius_m: float  # the housing's rounded ends (in x, y: a stadium)
    housing_half_straight_m: float  # half the straight part of the stadium along y
    housing_height_m: float
    inner_pivot_m: tuple[float, float]  # (y, z) of the inner knuckle's pivot, finger 0's side, above the mount
    outer_pivot_m: tuple[float, float]  # (y, z) of the outer knuckle's pivot
    knuckle_m: float  # inner knuckle length (pivot to the inner finger's joint)
    knuckle_open_deg: float  # its angle from z when fully open
    driver_m: float  # outer knuckle (metal) part of the outer chain
    finger_inset_m: float  # inner finger joint -> pad face, inwards along y
    link_width_m: float  # knuckles' width along x
    pad_width_m: float
    pad_height_m: float
    pad_thickness_m: float


ROBOTIQ = {
    "robotiq_2f85": RobotiqLinks("robotiq_2f85", 0.0108, 0.030, 0.0125, 0.055, (0.0132, 0.0609), (0.0306, 0.0549),
                                 0.0666, 55.7, 0.032, 0.0255, 0.026, 0.022, 0.0375, 0.008),
    "robotiq_2f140": RobotiqLinks("robotiq_2f140", 0.0108, 0.030, 0.0125, 0.055, (0.0127, 0.0614), (0.0306, 0.0549),
                                  0.0996, 55.7, 0.045, 0.0255, 0.030, 0.027, 0.046, 0.009),
}


@dataclass(frozen=True)
class Part:
    """A drawable part in the world: vertices [m] (V, 3), faces (F, 3) wound outward, unit normals (V, 3), colour."""

    vertices_m: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    rgb: np.ndarray


def robotiq_links(name: str) -> RobotiqLinks | None:
    """The link model of a gripper by its contracts/grippers name, or None (not a Robotiq adaptive gripper)."""
    return ROBOTIQ.get(name)


@lru_cache(maxsize=1)
def unit_box() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A box [-1, 1]^3: 4 vertices per face (flat normals), faces wound outward."""
    verts: list[np.ndarray] = []
    faces: list[list[int]] = []
    normals: list[np.ndarray] = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, w = [k for k in range(3) if k != axis]
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis], p[u], p[w] = sign, a, b
                corners.append(p)
            n0 = len(verts)
            verts += corners
            nrm = np.zeros(3)
            nrm[axis] = sign
            normals += [nrm] * 4
            faces += [[n0, n0 + 1, n0 + 2], [n0, n0 + 2, n0 + 3]]
    v, f, n = np.array(verts), np.array(faces), np.array(normals)
    tri = v[f]
    outward = np.einsum("ij,ij->i", np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), n[f[:, 0]]) > 0
    f[~outward] = f[~outward][:, ::-1]
    return v, f, n


@lru_cache(maxsize=4)
def _unit_cylinder(segments: int = 20) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A cylinder of radius 1 along z from -1 to 1: side with smooth normals, flat caps; faces wound outward."""
    a = 2.0 * np.pi * np.arange(segments) / segments
    ring = np.stack([np.cos(a), np.sin(a)], axis=1)
    side = np.concatenate([np.column_stack([ring, np.full(segments, -1.0)]), np.column_stack([ring, np.ones(segments)])])
    side_n = np.concatenate([np.column_stack([ring, np.zeros(segments)])] * 2)
    faces = []
    for i in range(segments):
        j = (i + 1) % segments
        faces += [[i, j, segments + j], [i, segments + j, segments + i]]
    verts, normals = [side], [side_n]
    base = 2 * segments
    for z in (-1.0, 1.0):
        cap = np.vstack([[0.0, 0.0, z], np.column_stack([ring, np.full(segments, z)])])
        verts.append(cap)
        normals.append(np.tile([0.0, 0.0, z], (segments + 1, 1)))
        for i in range(segments):
            j = (i + 1) % segments
            faces.append([base, base + 1 + j, base + 1 + i] if z < 0 else [base, base + 1 + i, base + 1 + j])
        base += segments + 1
    return np.concatenate(verts), np.array(faces), np.concatenate(normals)


def _posed(unit: tuple[np.ndarray, np.ndarray, np.ndarray], centre: np.ndarray, axes: np.ndarray,
           half: np.ndarray, rgb: np.ndarray) -> Part:
    """A unit shape scaled by half (per local axis), turned by axes (columns: local x, y, z in G) and moved to centre;
    normals transformed by the inverse transpose."""
    v, f, n = unit
    m = axes * np.asarray(half)[None, :]
    normals = n @ np.linalg.inv(m)  # (M^-T n) as rows
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    return Part(v @ m.T + centre, f, normals, rgb)


def box(lo: ArrayLike, hi: ArrayLike, rgb: np.ndarray) -> Part:
    """An axis-aligned box of frame G."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    return _posed(unit_box(), 0.5 * (lo + hi), np.eye(3), 0.5 * (hi - lo), rgb)


def bar(p: np.ndarray, q: np.ndarray, width_m: float, thickness_m: float, rgb: np.ndarray) -> Part:
    """A link from p to q (points in the y-z plane of G), width_m along x, thickness_m across in the y-z plane, its
    ends rounded past p and q by half the thickness."""
    p, q = np.asarray(p, np.float64), np.asarray(q, np.float64)
    along = q - p
    length = float(np.linalg.norm(along))
    along = along / max(length, 1e-12)
    x = np.array([1.0, 0.0, 0.0])
    across = np.cross(along, x)
    axes = np.column_stack([x, across, along])
    return _posed(unit_box(), 0.5 * (p + q), axes,
                  np.array([0.5 * width_m, 0.5 * thickness_m, 0.5 * length + 0.5 * thickness_m]), rgb)


def pin(centre: np.ndarray, length_m: float, radius_m: float, rgb: np.ndarray) -> Part:
    """A pivot pin along x."""
    axes = np.column_stack([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    return _posed(_unit_cylinder(12), np.asarray(centre, np.float64), axes,
                  np.array([radius_m, radius_m, 0.5 * length_m]), rgb)


def knuckle_angle(links: RobotiqLinks, half_opening_m: float) -> float:
    """The inner knuckle's angle from z [rad] that puts the pad face half_opening_m from the centre (clamped to the
    linkage's range: fully open .. the knuckle upright)."""
    s = (half_opening_m + links.finger_inset_m - links.inner_pivot_m[0]) / links.knuckle_m
    return float(np.arcsin(np.clip(s, 0.0, np.sin(np.radians(links.knuckle_open_deg)))))


def gripper_parts_local(links: RobotiqLinks, half_opening_m: float, pad_centre_z_m: float) -> list[Part]:
    """The gripper's parts in frame G with its pad faces half_opening_m from the centre and the pads' centres at
    pad_centre_z_m along the approach (the recorded pads)."""
    parts = []
    m = links.mount_m
    parts.append(_posed(_unit_cylinder(24), np.array([0.0, 0.0, 0.5 * m]), np.eye(3),
                        np.array([0.0375, 0.0375, 0.5 * m]), COUPLING))
    top = m + links.housing_height_m
    r, s = links.housing_radius_m, links.housing_half_straight_m
    parts.append(box([-r, -s, m], [r, s, top], BLACK))  # the stadium: a box and two half-round ends
    for y in (-s, s):
        parts.append(_posed(_unit_cylinder(24), np.array([0.0, y, 0.5 * (m + top)]), np.eye(3),
                            np.array([r, r, 0.5 * (top - m)]), BLACK))
    alpha = knuckle_angle(links, half_opening_m)
    w = links.link_width_m
    for sign in (1.0, -1.0):  # finger 0 at +y
        pi = np.array([0.0, sign * links.inner_pivot_m[0], m + links.inner_pivot_m[1]])
        po = np.array([0.0, sign * links.outer_pivot_m[0], m + links.outer_pivot_m[1]])
        direction = np.array([0.0, sign * np.sin(alpha), np.cos(alpha)])
        a = pi + links.knuckle_m * direction  # inner finger joint
        c = po + links.knuckle_m * direction  # outer finger's end (the four-bar is a parallelogram)
        d = po + links.driver_m * direction  # end of the metal outer knuckle
        parts.append(bar(pi, a, w, 0.007, BLACK))  # inner knuckle
        parts.append(bar(po, d, 0.6 * w, 0.008, METAL))  # outer knuckle (driver)
        parts.append(bar(d, c, 0.75 * w, 0.007, BLACK))  # outer finger (coupler)
        face_y = sign * half_opening_m
        back_y = face_y + sign * links.pad_thickness_m
        pz0, pz1 = pad_centre_z_m - 0.5 * links.pad_height_m, pad_centre_z_m + 0.5 * links.pad_height_m
        joint_lo = min(a[2], c[2]) - 0.006
        # inner finger: a block over both joints, then the finger down (along the approach) to the pad's tip
        y_out = max(abs(a[1]), abs(c[1])) + 0.004
        parts.append(box([-0.5 * links.pad_width_m, min(back_y, sign * y_out), joint_lo],
                         [0.5 * links.pad_width_m, max(back_y, sign * y_out), max(a[2], c[2]) + 0.008], BLACK))
        finger_y = back_y + sign * 0.006
        parts.append(box([-0.5 * links.pad_width_m, min(back_y, finger_y), min(joint_lo, pz0)],
                         [0.5 * links.pad_width_m, max(back_y, finger_y), pz1 + 0.002], BLACK))
        parts.append(box([-0.5 * links.pad_width_m, min(face_y, back_y), pz0],
                         [0.5 * links.pad_width_m, max(face_y, back_y), pz1], SILICONE))  # the pad
        for centre in (pi, po, a, c):
            parts.append(pin(centre, w + 0.004, 0.0045, METAL))
    return parts


def gripper_parts(links: RobotiqLinks, flange_m: np.ndarray, tcp_origin_m: np.ndarray, tcp_rotation: np.ndarray,
                  half_opening_m: float) -> list[Part]:
    """The gripper in the world: frame G's origin at the flange, its axes the TCP frame's (columns x, y, z), the pads'
    centres at the TCP's depth along the approach, their faces half_opening_m from it."""
    rot = np.asarray(tcp_rotation, np.float64)
    flange = np.asarray(flange_m, np.float64)
    pad_z = float((np.asarray(tcp_origin_m, np.float64) - flange) @ rot[:, 2])
    out = []
    for part in gripper_parts_local(links, half_opening_m, pad_z):
        out.append(Part(part.vertices_m @ rot.T + flange, part.faces, part.normals @ rot.T, part.rgb))
    return out
