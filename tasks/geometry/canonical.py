"""Canonical frame: z up, resting on a stable face on z = 0, centred in x, y, longest horizontal extent on x (metres)."""

from __future__ import annotations

from typing import Literal

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError, cKDTree

Orientation = Literal["keep_if_stable", "most_stable", "keep"]


def is_resting_stable(mesh: trimesh.Trimesh, margin_frac: float = 0.05) -> bool:
    """True when the centre of mass projects inside the support polygon of the lowest points (with a margin)."""
    z = mesh.vertices[:, 2]
    tol = max(1e-4, 0.01 * float(mesh.extents.max()))
    contact = mesh.vertices[z <= z.min() + tol][:, :2]
    com = mesh.center_mass[:2] if mesh.is_watertight else mesh.centroid[:2]
    if len(contact) < 3:
        return False
    try:
        ch = ConvexHull(contact)
    except QhullError:
        return False
    eq = ch.equations  # a x + b y + c <= 0 inside
    dist_inside = -(eq[:, :2] @ com + eq[:, 2])
    return bool(dist_inside.min() >= margin_frac * float(np.sqrt(ch.volume)))


def tip_angle_deg(mesh: trimesh.Trimesh, contact_m: float = 0.002) -> float:
    """How far the resting body can lean before its centre of mass leaves its base [deg]: atan(the centre of mass'
    distance inside the support polygon of the points within contact_m of the ground / its height). 0 when it is
    outside or there is no base polygon."""
    z = mesh.vertices[:, 2]
    contact = mesh.vertices[z <= z.min() + contact_m][:, :2]
    com = mesh.center_mass if mesh.is_watertight else mesh.centroid
    if len(contact) < 3:
        return 0.0
    try:
        ch = ConvexHull(contact)
    except QhullError:
        return 0.0
    inside = float(np.min(-(ch.equations[:, :2] @ com[:2] + ch.equations[:, 2])))
    return float(np.degrees(np.arctan2(max(inside, 0.0), max(float(com[2] - z.min()), 1e-9))))


SEAT_TIP_DEG = 15.0  # a toy that stands is given a base it can lean this far on (see seat_flat)
SEAT_MAX_CUT = 0.06  # ... by flattening at most this share of its height


def seat_flat(mesh: trimesh.Trimesh, min_tip_deg: float = SEAT_TIP_DEG, max_cut: float = SEAT_MAX_CUT
              ) -> tuple[trimesh.Trimesh, float]:
    """A standing soft toy on a rounded bottom rests on a few points and tips over when set down a few degrees off
    (a plush penguin of 18 cm: 6 deg). A stuffed body sits on a flattened base: cut the bottom flat at the lowest
    height (in steps of 0.5 % of the height, at most max_cut of it) where the base holds a lean of min_tip_deg.
    Returns the mesh resting on z = 0 and the height cut [m] (0: the base was already wide enough, or a cut does not
    widen it)."""
    if not mesh.is_watertight or tip_angle_deg(mesh) >= min_tip_deg:
        return mesh, 0.0
    lo, hi = mesh.bounds
    height = float(hi[2] - lo[2])
    start = tip_angle_deg(mesh)
    best: tuple[float, float, trimesh.Trimesh] = (start, 0.0, mesh)  # (tip [deg], cut [m], mesh)
    for k in range(1, int(round(max_cut / 0.005)) + 1):
        cut = k * 0.005 * height
        seated = mesh.slice_plane([0.0, 0.0, lo[2] + cut], [0.0, 0.0, 1.0], cap=True)
        if seated is None or len(seated.faces) == 0 or not seated.is_watertight:
            break
        seated.apply_translation([0.0, 0.0, -float(seated.bounds[0][2])])
        tip = tip_angle_deg(seated)
        if tip > best[0] + 1e-9:
            best = (tip, cut, seated)
        if tip >= min_tip_deg:
            break
    if best[0] <= start + 1.0:
        return mesh, 0.0
    seated = best[2]
    if mesh.visual.kind == "vertex":  # slice_plane drops vertex colours: each vertex takes its nearest original's
        where = np.asarray(seated.vertices) + np.array([0.0, 0.0, lo[2] + best[1]])  # back where it was cut
        _, idx = cKDTree(np.asarray(mesh.vertices)).query(where)
        colors = np.asarray(mesh.visual.vertex_colors)[idx]
        seated.visual = trimesh.visual.ColorVisuals(seated, vertex_colors=colors)
    return seated, best[1]


POSE_HULL_CELLS = 24  # a smooth body's hull is thinned to one vertex per cell of a 24^3 grid for the pose search


def pose_hull(mesh: trimesh.Trimesh, cells: int = POSE_HULL_CELLS) -> trimesh.Trimesh:
    """The convex hull the resting-pose search rolls over: a smooth body's hull (thousands of facets, each a node of
    trimesh's topple graph) thinned to one vertex per grid cell of 1/cells of the longest extent; a hull with few
    facets is kept as it is."""
    hull = mesh.convex_hull
    if len(hull.faces) <= 2 * cells * cells:
        return hull
    pitch = float(mesh.extents.max()) / cells
    keys = np.floor((hull.vertices - hull.bounds[0]) / pitch).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    return trimesh.Trimesh(hull.vertices[np.sort(first)]).convex_hull


def most_stable_rotation(mesh: trimesh.Trimesh) -> np.ndarray:
    """4x4 transform of the most probable resting pose (trimesh's quasi-static drop from the centre of mass, rolled
    over the thinned hull)."""
    com = np.asarray(mesh.center_mass)
    hull = pose_hull(mesh)
    if not np.all(np.einsum("ij,ij->i", com - hull.triangles_center, hull.face_normals) < 0):
        hull = mesh.convex_hull  # the thinned hull must hold the centre of mass (trimesh loops until one does)
    transforms, probs = trimesh.poses.compute_stable_poses(hull, center_mass=com, sigma=0.0, n_samples=1)
    if len(transforms) == 0:
        return np.eye(4)
    return np.asarray(transforms[int(np.argmax(probs))])


def align_horizontal(mesh: trimesh.Trimesh) -> np.ndarray:
    """4x4 rotation about z putting the principal horizontal axis on x (sign fixed by the third moment)."""
    pts = mesh.vertices[:, :2] - mesh.center_mass[:2]
    w = np.ones(len(pts))
    cov = (pts * w[:, None]).T @ pts / w.sum()
    evals, evecs = np.linalg.eigh(cov)
    major = evecs[:, int(np.argmax(evals))]
    if evals.max() - evals.min() < 1e-3 * evals.max():
        major = np.array([1.0, 0.0])
    proj = pts @ major
    if np.mean(proj**3) < 0:
        major = -major
    ang = np.arctan2(major[1], major[0])
    return trimesh.transformations.rotation_matrix(-ang, [0, 0, 1])


def rest_on_ground(mesh: trimesh.Trimesh) -> None:
    """Translate so the lowest point is on z = 0 and the bounding box is centred in x, y (in place)."""
    lo, hi = mesh.bounds
    mesh.apply_translation([-(lo[0] + hi[0]) / 2.0, -(lo[1] + hi[1]) / 2.0, -lo[2]])


def canonicalize(mesh: trimesh.Trimesh, orientation: Orientation, align_xy: bool) -> tuple[trimesh.Trimesh, bool]:
    """Return the mesh in the canonical frame and whether its orientation was changed from the input's ('keep': z
    stays up, only the turn about z of align_xy; 'keep_if_stable': the most stable pose when the input's is not
    stable; 'most_stable': always the most stable pose)."""
    mesh = mesh.copy()
    rest_on_ground(mesh)
    rotated = False
    if orientation == "most_stable" or (orientation == "keep_if_stable" and not is_resting_stable(mesh)):
        tf = most_stable_rotation(mesh)
        if not np.allclose(tf[:3, :3], np.eye(3), atol=1e-9):
            rotated = True
        mesh.apply_transform(tf)
    if align_xy:
        mesh.apply_transform(align_horizontal(mesh))
    rest_on_ground(mesh)
    return mesh, rotated
