"""A long object said bent ('a pool noodle bent into a U', 'a U-shaped bolster', 'a sausage bent in half', 'a slightly bent
foam tube'): the angle the words give, and the built mesh bent by it along its length in the ground plane, every
cross-section carried round an arc of the same centre-line length (lengths along the object and its volume are
kept, so the stated size and the mass are the straight object's).

    from tasks.geometry.bend import stated_bend, bend_along_length

    bend = stated_bend("a green pool noodle bent into a U")   # Bend(angle_rad=pi, words='bent into a U')
    mesh = bend_along_length(mesh, bend.angle_rad)           # a mesh of aspect >= MIN_ASPECT, z up
"""

from __future__ import annotations

import math
import re
from typing import NamedTuple

import numpy as np
import trimesh

MIN_ASPECT = 4.0  # longest over middle extent: shorter objects are not bent (a bent ball is a ball)
_U = r"(?:a\s+)?(?:u|horseshoe)(?:[\s-]?shape)?"
BEND_PHRASES: list[tuple[re.Pattern[str], float]] = [
    (re.compile(rf"\b(?:bent|curved|curled|bowed|formed|shaped|folded)\s+(?:in)?to\s+{_U}\b", re.I), math.pi),
    (re.compile(r"\bu[\s-]shaped\b|\bhorseshoe(?:[\s-]shaped)?\b", re.I), math.pi),  # 'a horseshoe ring of sausage'
    (re.compile(r"\bbent\s+(?:in|into)\s+(?:half|two)\b|\bbent\s+double\b|\bdoubled\s+over\b", re.I), math.pi),
    (re.compile(r"\bbent\s+(?:at\s+)?(?:a\s+)?right[\s-]angle\b|\bl[\s-]shaped\b|\bbent\s+90\b", re.I), math.pi / 2),
    (re.compile(r"\bbent\b", re.I), math.pi / 3),  # ('curved', 'arched': a banana or a cat is so already)
]


class Bend(NamedTuple):
    """A bend read from a request: the angle between the object's two end directions' normals [rad] and the
    words."""

    angle_rad: float
    words: str


def stated_bend(text: str) -> Bend | None:
    """The bend a request states, the most specific phrase first; None when it says none."""
    for pattern, angle in BEND_PHRASES:
        m = pattern.search(text)
        if m:
            return Bend(angle, m.group(0))
    return None


def can_bend(extents_m: np.ndarray) -> bool:
    """Long enough to bend (extents x, y, z with z up): its longest horizontal extent, the one bend_along_length
    bends, at least MIN_ASPECT x each of the other two."""
    x, y, z = (float(v) for v in extents_m)
    return max(x, y) >= MIN_ASPECT * max(min(x, y), z, 1e-12)


def bend_along_length(mesh: trimesh.Trimesh, angle_rad: float) -> trimesh.Trimesh:
    """A copy of the mesh bent by angle_rad round a vertical axis along its longest horizontal axis: the centre line
    (the long axis through the bounding box's centre) becomes an arc of the same length, each point keeping its
    distance from it; the result rests on z = 0, centred in x and y, with the arc's chord along x."""
    v = np.asarray(mesh.vertices, np.float64).copy()
    ext = v.max(axis=0) - v.min(axis=0)
    long_ax = 0 if ext[0] >= ext[1] else 1
    across = 1 - long_ax
    centre = (v.max(axis=0) + v.min(axis=0)) / 2.0
    s = v[:, long_ax] - centre[long_ax]  # along the centre line [m]
    d = v[:, across] - centre[across]  # across it, in the ground plane [m]
    radius = ext[long_ax] / angle_rad  # of the centre line's arc
    theta = s / radius
    r = radius - d  # the +across side goes inside
    out = np.empty_like(v)
    out[:, 0] = r * np.sin(theta)
    out[:, 1] = radius - r * np.cos(theta)
    out[:, 2] = v[:, 2]
    bent = trimesh.Trimesh(out, np.asarray(mesh.faces), process=False)
    if mesh.visual.kind == "vertex":
        bent.visual.vertex_colors = np.asarray(mesh.visual.vertex_colors)
    lo, hi = out.min(axis=0), out.max(axis=0)
    bent.apply_translation([-(lo[0] + hi[0]) / 2.0, -(lo[1] + hi[1]) / 2.0, -lo[2]])
    return bent
