"""Antipodal grasp selection for a parallel gripper on the Panda, without learned weights, in the asset frame.

Inputs are numpy arrays in the asset frame (z up, the table is z = 0, metres): surface points, their outward unit
normals and the centre of mass. Closing lines are sampled from surface points along the inward normal and a few
directions around it, so lines cross the whole body, not only its narrow parts; each line's two outermost contacts
give the width between flat pads (within the pads' footprint) and the two contact normals. A candidate must fit the
gripper's stroke (``GraspSettings.gripper``, contracts/grippers; with a clearance per finger), have both normals
inside the friction cone (angle to the closing line <= atan(mu)), keep the fingertips above the table, and let the
open hand come down along the approach axis without any object point inside the palm or a finger (points against
the gripper's collision boxes; tested best-first until the list is full). A soft object may be wider than the stroke
by ``2 * soft_indent_m``: the open fingers press it by up to that much per finger as they come down (the squeeze it
takes before the force target, see tasks.robot.squeeze). Ranking prefers top-down approaches and centres near the
centre of mass, then well-aligned normals and no pre-press. Deterministic for a seed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from contracts.errors import SimulationError
from contracts.robot import DEFAULT_GRIPPER, GraspCandidate
from tasks.robot.gripper import Gripper, gripper

DOWN = np.array([0.0, 0.0, -1.0])


class NoGraspError(SimulationError):
    """The object offers no grasp the gripper can take (too wide, no friction-cone pair, blocked)."""


@dataclass(frozen=True)
class GraspSettings:
    """Knobs of the sampler; lengths [m], angles [deg]."""

    n_points: int = 300
    directions_per_point: int = 3
    direction_spread_deg: float = 20.0
    gripper: str = DEFAULT_GRIPPER       # contracts/grippers/<name>.yaml
    max_opening_m: float | None = None  # None: the gripper's stroke
    soft_indent_m: float = 0.0          # how far the open fingers may press a soft object as they come down [m]
    max_width_m: float | None = None    # widest grasp taken at all [m] (a smaller gripper: its stroke)
    min_clearance_m: float = 0.002
    open_clearance_m: float = 0.01
    max_tilt_deg: float = 30.0
    table_margin_m: float = 0.003
    approach_distance_m: float = 0.10
    collision_tolerance_m: float = 0.001
    max_candidates: int = 16
    dedup_distance_m: float = 0.005
    dedup_angle_deg: float = 10.0
    com_scale_m: float = 0.03
    approach_turns_deg: tuple[float, ...] = (0.0,)  # approaches tried per closing line: the most downward one turned
    #                                                  about the closing axis by these angles (side approaches) [deg]


@dataclass(frozen=True)
class GraspSelection:
    """Ranked candidates (best first) and how many sampled lines survived each test; ``reason`` when none did."""

    candidates: list[GraspCandidate]
    counts: dict[str, int] = field(default_factory=dict)
    narrowest_width_m: float = float("inf")
    reason: str = ""

    @property
    def ok(self) -> bool:
        """At least one grasp."""
        return bool(self.candidates)

    def best(self) -> GraspCandidate:
        """The top-ranked grasp, or NoGraspError with the reason."""
        if not self.candidates:
            raise NoGraspError(self.reason)
        return self.candidates[0]


def _cone_directions(normals: np.ndarray, rng: np.random.Generator, per_point: int, spread_rad: float) -> np.ndarray:
    """Closing directions per point: the inward normal, then random ones within ``spread_rad`` of it. (M, K, 3)."""
    m = len(normals)
    inward = -normals
    dirs = [inward]
    helper = np.where(np.abs(inward[:, :1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    e1 = np.cross(inward, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(inward, e1)
    for _ in range(per_point - 1):
        theta = spread_rad * np.sqrt(rng.random(m))
        phi = 2.0 * np.pi * rng.random(m)
        d = (np.cos(theta)[:, None] * inward
             + np.sin(theta)[:, None] * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2))
        dirs.append(d)
    return np.stack(dirs, axis=1)


def _approach_for(u: np.ndarray, turn_rad: float = 0.0) -> np.ndarray:
    """The approach axis closest to straight down that is perpendicular to the closing axis u, turned about u by
    ``turn_rad`` (0: the most downward; towards the side for larger turns)."""
    a = DOWN - (DOWN @ u) * u
    n = np.linalg.norm(a)
    if n <= 1e-9:
        return np.array([np.nan, np.nan, np.nan])
    a = a / n
    return a if turn_rad == 0.0 else np.cos(turn_rad) * a + np.sin(turn_rad) * np.cross(u, a)


def _mean_normal(normals: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Unit mean of the selected normals."""
    n = normals[mask].sum(axis=0)
    return n / max(np.linalg.norm(n), 1e-12)


def _opening_limit(s: GraspSettings, g: Gripper) -> float:
    """Largest opening the sampler uses [m]."""
    return g.stroke_m if s.max_opening_m is None else min(s.max_opening_m, g.stroke_m)


def _hand_hits(points: np.ndarray, center: np.ndarray, u: np.ndarray, a: np.ndarray, opening: float,
               s: GraspSettings, g: Gripper) -> bool:
    """Whether any object point is inside the open hand swept from the pre-grasp down to the grasp (the fingers
    tested ``soft_indent_m`` further out: a soft object may be pressed that far)."""
    rot = np.column_stack([np.cross(-u, a), -u, a])  # TCP frame: x, y = -u (towards finger 0), z = a
    local = (points - center) @ rot
    tol = s.collision_tolerance_m
    palm, *fingers = g.boxes(opening)
    fingers = list(g.boxes(opening + 2.0 * s.soft_indent_m))[1:] if s.soft_indent_m > 0 else fingers
    for lo, hi in (palm, *fingers):
        lo_swept = lo - np.array([0.0, 0.0, s.approach_distance_m])
        inside = np.all((local > lo_swept + tol) & (local < hi - tol), axis=1)
        if inside.any():
            return True
    return False


def _lowest_finger_point(center: np.ndarray, u: np.ndarray, a: np.ndarray, width: float,
                         g: Gripper | None = None) -> float:
    """Lowest z [m] of the fingertips (pad boxes extended to the tip) at the grasp (default: the Franka Hand)."""
    g = g or gripper()
    half = g.pad_half_extents_m
    x = np.cross(-u, a)
    reach = abs(a[2]) * g.tip_beyond_center_m + abs(x[2]) * half[0]
    reach += abs(u[2]) * (width / 2.0 + 2.0 * half[1])
    return float(center[2] - reach)


@dataclass(frozen=True)
class _Line:
    """A closing line that passed the per-line tests: score, centre [m], closing and approach axes, width [m]."""

    score: float
    center: np.ndarray
    u: np.ndarray
    a: np.ndarray
    width: float


def _evaluate_line(p0: np.ndarray, u: np.ndarray, pts: np.ndarray, nrm: np.ndarray, com: np.ndarray, mu: float,
                   tube: float, s: GraspSettings, g: Gripper, counts: dict[str, int], widths: list[float],
                   turn_rad: float = 0.0) -> _Line | None:
    """Tilt, friction-cone, width and table tests of the closing line p0 + t u with the approach turned by
    ``turn_rad`` about it; counts each pass."""
    counts["lines"] += 1
    a = _approach_for(u, turn_rad)
    tilt = float(np.arccos(np.clip(a @ DOWN, -1.0, 1.0))) if np.isfinite(a).all() else np.pi / 2
    if tilt > np.radians(s.max_tilt_deg):
        return None
    counts["tilt_ok"] += 1
    d = pts - p0
    along = d @ u
    in_tube = np.linalg.norm(d - along[:, None] * u, axis=1) <= tube
    n_a = _mean_normal(nrm, in_tube & (along <= along[in_tube].min() + tube))  # finger 1's contact
    n_b = _mean_normal(nrm, in_tube & (along >= along[in_tube].max() - tube))  # finger 2's contact
    cone = np.arctan(mu)
    ang = max(np.arccos(np.clip(-(n_a @ u), -1.0, 1.0)), np.arccos(np.clip(n_b @ u, -1.0, 1.0)))
    if ang > cone:
        return None
    counts["cone_ok"] += 1
    half = g.pad_half_extents_m
    in_pad = (np.abs(d @ np.cross(u, a)) <= half[0]) & (np.abs(d @ a) <= half[2])
    if not in_pad.any():
        return None  # the pads, centred on p0, cover no surface point (a line grazing an edge)
    lo, hi = along[in_pad].min(), along[in_pad].max()  # the flat pads touch the outermost points they cover
    width = float(hi - lo)
    widths.append(width)
    usable = _opening_limit(s, g) - 2.0 * s.min_clearance_m
    if width > usable + 2.0 * s.soft_indent_m or width > (s.max_width_m or np.inf) or width <= 0.0:
        return None
    counts["width_ok"] += 1
    center = p0 + u * 0.5 * (lo + hi)
    if _lowest_finger_point(center, u, a, width, g) < s.table_margin_m:
        return None
    counts["table_ok"] += 1
    press = max(0.0, width - usable) / (2.0 * s.soft_indent_m) if s.soft_indent_m > 0 else 0.0
    score = -(tilt / np.radians(s.max_tilt_deg) + hang_offset_m(center, u, com) / s.com_scale_m
              + 0.5 * ang / max(cone, 1e-9) + press)
    return _Line(float(score), center, u, a, width)


TURNED_APPROACHES_DEG = (15.0, -15.0, 30.0, -30.0, 45.0, -45.0, 60.0, -60.0, 90.0, -90.0, 120.0, -120.0, 150.0,
                         -150.0, 180.0)  # turns of a grasp's approach about its closing axis, tried smallest first


def turned_approaches(candidate: GraspCandidate, points_m: np.ndarray, settings: GraspSettings | None = None,
                      turns_deg: tuple[float, ...] = TURNED_APPROACHES_DEG) -> list[GraspCandidate]:
    """The same grasp (centre, closing axis, width: the same two contacts) reached along other approaches: its
    approach axis turned about the closing axis, smallest turn first; only approaches that do not come up from below,
    whose fingertips clear the table and whose open hand, swept in from the pre-grasp, clears the object's points [m].
    A condition that turns the object so the arm cannot come in the planned way keeps the grasp the trials tested."""
    s = settings or GraspSettings()
    g = gripper(s.gripper)
    pts = np.asarray(points_m, dtype=float)
    center = np.asarray(candidate.center_m, dtype=float)
    u = np.asarray(candidate.closing_axis, dtype=float)
    u /= np.linalg.norm(u)
    a0 = np.asarray(candidate.approach_axis, dtype=float)
    a0 = a0 - (a0 @ u) * u
    a0 /= np.linalg.norm(a0)
    opening = min(_opening_limit(s, g), candidate.width_m + 2.0 * s.open_clearance_m)
    out: list[GraspCandidate] = []
    for turn in turns_deg:
        t = np.radians(turn)
        a = np.cos(t) * a0 + np.sin(t) * np.cross(u, a0)
        if a[2] > 1e-6 or _lowest_finger_point(center, u, a, candidate.width_m, g) < s.table_margin_m:
            continue
        if _hand_hits(pts, center, u, a, opening, s, g):
            continue
        out.append(candidate.model_copy(update={"approach_axis": tuple(map(float, a))}))
    return out


def hang_offset_m(center: np.ndarray, u: np.ndarray, com: np.ndarray) -> float:
    """How far the centre of mass sits from where a two-pad grasp holds it best [m]. The pads hold the object like a
    hinge about the closing axis u: a centre of mass off that axis sideways is a lever that turns the object in the
    hand while it is carried (weight 1); one above the axis is an inverted pendulum that tips over (weight 1.5),
    one below it hangs still (weight 0.5); an offset along the axis only loads one pad more (weight 0.5)."""
    d = np.asarray(com, dtype=float) - np.asarray(center, dtype=float)
    along = float(d @ u)
    perp = d - along * u
    side = float(np.linalg.norm(perp[:2]))
    up = float(perp[2])
    return float(np.sqrt((0.5 * along) ** 2 + side ** 2 + ((1.5 if up > 0.0 else 0.5) * up) ** 2))


def _rank(lines: list[_Line], pts: np.ndarray, s: GraspSettings, g: Gripper, counts: dict[str, int]
          ) -> list[_Line]:
    """Best first, near-duplicates dropped, the hand collision test run until the list is full."""
    lines = sorted(lines, key=lambda ln: -ln.score)  # stable: ties keep sampling order (deterministic)
    cos_dedup = np.cos(np.radians(s.dedup_angle_deg))
    chosen: list[_Line] = []
    for ln in lines:
        if not all(np.linalg.norm(ln.center - c.center) > s.dedup_distance_m or abs(ln.u @ c.u) < cos_dedup
                   or ln.a @ c.a < cos_dedup for c in chosen):
            continue
        counts["collision_checked"] += 1
        if _hand_hits(pts, ln.center, ln.u, ln.a, min(_opening_limit(s, g), ln.width + 2.0 * s.open_clearance_m),
                      s, g):
            continue
        counts["collision_free"] += 1
        chosen.append(ln)
        if len(chosen) == s.max_candidates:
            break
    return chosen


def select_grasps(points_m: np.ndarray, normals: np.ndarray, center_of_mass_m: np.ndarray, friction: float,
                  seed: int = 0, settings: GraspSettings | None = None) -> GraspSelection:
    """Ranked antipodal grasps (asset frame) for surface points [m] with outward normals and gripper friction mu."""
    s = settings or GraspSettings()
    g = gripper(s.gripper)
    pts = np.asarray(points_m, dtype=float)
    nrm = np.asarray(normals, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3 or nrm.shape != pts.shape or len(pts) < 4:
        raise ValueError("points_m and normals must be matching (N, 3) arrays with N >= 4")
    lengths = np.linalg.norm(nrm, axis=1)
    keep = np.isfinite(pts).all(axis=1) & np.isfinite(nrm).all(axis=1) & (lengths > 1e-9)
    pts, nrm = pts[keep], nrm[keep] / lengths[keep, None]
    com = np.asarray(center_of_mass_m, dtype=float)

    spacing = float(np.median(cKDTree(pts).query(pts, k=2)[0][:, 1]))
    tube = max(1e-3, 1.5 * spacing)  # points within this of a closing line are its contacts [m]
    rng = np.random.default_rng(seed)
    idx = np.sort(rng.choice(len(pts), size=min(s.n_points, len(pts)), replace=False))
    dirs = _cone_directions(nrm[idx], rng, s.directions_per_point, np.radians(s.direction_spread_deg))

    counts = dict.fromkeys(("lines", "tilt_ok", "cone_ok", "width_ok", "table_ok", "collision_checked",
                            "collision_free"), 0)
    widths: list[float] = []
    turns = [float(np.radians(t)) for t in s.approach_turns_deg]
    lines = [ln for p0, line_dirs in zip(pts[idx], dirs) for u in line_dirs for turn in turns
             if (ln := _evaluate_line(p0, u, pts, nrm, com, friction, tube, s, g, counts, widths, turn))
             is not None]
    chosen = _rank(lines, pts, s, g, counts)
    candidates = [GraspCandidate(center_m=tuple(map(float, ln.center)), closing_axis=tuple(map(float, ln.u)),
                                 approach_axis=tuple(map(float, ln.a)), width_m=ln.width, friction_cone_ok=True,
                                 score=ln.score, rank=r) for r, ln in enumerate(chosen)]
    narrowest = min(widths, default=float("inf"))
    usable = _opening_limit(s, g) - 2.0 * s.min_clearance_m + 2.0 * s.soft_indent_m
    reason = "" if candidates else _no_grasp_reason(counts, narrowest, usable, friction, g.name)
    return GraspSelection(candidates, counts, narrowest, reason)


def _no_grasp_reason(counts: dict[str, int], narrowest: float, usable: float, friction: float, name: str) -> str:
    """One line saying which test removed the last sampled closing line."""
    if counts["tilt_ok"] == 0:
        why = "no closing line is close enough to horizontal for an approach from above"
    elif counts["cone_ok"] == 0:
        why = f"no contact pair has both normals inside the friction cone of mu = {friction:g}"
    elif counts["width_ok"] == 0:
        why = (f"the object is wider than the gripper's usable opening {usable * 1000:.0f} mm ({name}) along "
               f"every sampled closing line with both contacts in the friction cone "
               f"(narrowest {narrowest * 1000:.0f} mm)")
    elif counts["table_ok"] == 0:
        why = "every pair that fits sits too low: the fingertips would hit the table"
    else:
        why = "the open hand would collide with the object on every approach"
    return f"no grasp: {why} ({counts['lines']} lines sampled)"
