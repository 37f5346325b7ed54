"""Signed distances (metres, negative inside) of shape-program primitives, transforms and smooth booleans."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from contracts.shape import (
    Capsule, Cone, Cylinder, Ellipsoid, Part, RoundedBox, ShapeProgram, Superellipsoid, Torus, Transform,
)

_EPS = 1e-12


def _len(v: np.ndarray) -> np.ndarray:
    """Euclidean length over the last axis (columns summed one by one: numpy's reductions over a last axis of 2 or 3
    are several times slower than the elementwise sum)."""
    if v.ndim == 2 and v.shape[1] in (2, 3):
        sq = v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1]
        if v.shape[1] == 3:
            sq += v[:, 2] * v[:, 2]
        return np.sqrt(sq)
    return np.sqrt(np.einsum("...i,...i->...", v, v))


def _max3(q: np.ndarray) -> np.ndarray:
    """Row-wise maximum of an (N, 3) array."""
    return np.maximum(np.maximum(q[:, 0], q[:, 1]), q[:, 2])


def sdf_ellipsoid(p: np.ndarray, prim: Ellipsoid) -> np.ndarray:
    """Near-exact ellipsoid distance (Quilez' k0 (k0 - 1) / k1 bound)."""
    r = np.asarray(prim.radii_m)
    k0 = _len(p / r)
    k1 = _len(p / (r * r))
    return np.where(k1 > _EPS, k0 * (k0 - 1.0) / np.maximum(k1, _EPS), -r.min())


def sdf_superellipsoid(p: np.ndarray, prim: Superellipsoid) -> np.ndarray:
    """Radial distance to a superellipsoid surface (exact sign, distance along the ray from the centre)."""
    r = np.asarray(prim.radii_m)
    e1, e2 = prim.exponent_ns, prim.exponent_ew
    q = np.abs(p) / r + _EPS
    f = (q[:, 0] ** (2.0 / e2) + q[:, 1] ** (2.0 / e2)) ** (e2 / e1) + q[:, 2] ** (2.0 / e1)
    norm = _len(p)
    surf = norm * f ** (-e1 / 2.0)
    return np.where(norm > _EPS, norm - surf, -r.min())


def sdf_capsule(p: np.ndarray, prim: Capsule) -> np.ndarray:
    """Capsule along z."""
    q = p.copy()
    h = prim.length_m / 2.0
    q[:, 2] -= np.clip(q[:, 2], -h, h)
    return _len(q) - prim.radius_m


def sdf_rounded_box(p: np.ndarray, prim: RoundedBox) -> np.ndarray:
    """Box with rounded edges, full extents size_m."""
    half = np.asarray(prim.size_m) / 2.0
    rr = min(prim.edge_radius_m, float(half.min()) * 0.999)
    q = np.abs(p) - (half - rr)
    return _len(np.maximum(q, 0.0)) + np.minimum(_max3(q), 0.0) - rr


def sdf_cylinder(p: np.ndarray, prim: Cylinder) -> np.ndarray:
    """Cylinder along z with rounded rims."""
    rr = min(prim.edge_radius_m, prim.radius_m * 0.999, prim.height_m * 0.4995)
    dx = _len(p[:, :2]) - prim.radius_m + rr
    dz = np.abs(p[:, 2]) - prim.height_m / 2.0 + rr
    d = np.stack([dx, dz], axis=1)
    return np.minimum(np.maximum(dx, dz), 0.0) + _len(np.maximum(d, 0.0)) - rr


def sdf_torus(p: np.ndarray, prim: Torus) -> np.ndarray:
    """Torus in the x-y plane."""
    q = np.stack([_len(p[:, :2]) - prim.major_radius_m, p[:, 2]], axis=1)
    return _len(q) - prim.minor_radius_m


def sdf_cone(p: np.ndarray, prim: Cone) -> np.ndarray:
    """Capped cone (frustum) along z, rounded by edge_radius (Quilez' sdCappedCone)."""
    rr = min(prim.edge_radius_m, prim.height_m * 0.45, max(prim.radius_bottom_m, prim.radius_top_m) * 0.9)
    h = prim.height_m / 2.0 - rr
    r1 = max(prim.radius_bottom_m - rr, 0.0)
    r2 = max(prim.radius_top_m - rr, 0.0)
    qx, qy = _len(p[:, :2]), p[:, 2]
    k1 = np.array([r2, h])
    k2 = np.array([r2 - r1, 2.0 * h])
    ca_x = qx - np.minimum(qx, np.where(qy < 0.0, r1, r2))
    ca_y = np.abs(qy) - h
    t = np.clip(((k1[0] - qx) * k2[0] + (k1[1] - qy) * k2[1]) / float(k2 @ k2), 0.0, 1.0)
    cb_x = qx - k1[0] + k2[0] * t
    cb_y = qy - k1[1] + k2[1] * t
    s = np.where((cb_x < 0.0) & (ca_y < 0.0), -1.0, 1.0)
    return s * np.sqrt(np.minimum(ca_x**2 + ca_y**2, cb_x**2 + cb_y**2)) - rr


_SDF: dict[str, Callable[[np.ndarray, Any], np.ndarray]] = {
    "ellipsoid": sdf_ellipsoid, "superellipsoid": sdf_superellipsoid, "capsule": sdf_capsule,
    "rounded_box": sdf_rounded_box, "cylinder": sdf_cylinder, "torus": sdf_torus, "cone": sdf_cone,
}


def rotation_matrix(tf: Transform) -> np.ndarray:
    """3x3 rotation of a transform (extrinsic XYZ Euler angles in degrees; read-only, shared by equal angles)."""
    return _rotation_matrix(tuple(float(a) for a in tf.rotation_deg))


@functools.lru_cache(maxsize=4096)
def _rotation_matrix(rotation_deg: tuple[float, ...]) -> np.ndarray:
    """(scipy's from_euler is ~90 us a call, and a program's parts are boxed and evaluated once per grid chunk)"""
    r = Rotation.from_euler("xyz", rotation_deg, degrees=True).as_matrix()
    r.setflags(write=False)
    return r


def part_sdf(p: np.ndarray, part: Part) -> np.ndarray:
    """Distance to one transformed part: local = R^T (p - t) / s, scaled back by min(s) (a conservative bound)."""
    tf = part.transform
    s = np.asarray(tf.scale, dtype=np.float64)
    local = p - np.asarray(tf.translation_m)
    if any(tf.rotation_deg):  # (N, 3) @ (3, 3) column by column: a BLAS call on a 3-wide matrix is far slower
        r = rotation_matrix(tf)
        local = local[:, 0:1] * r[0] + local[:, 1:2] * r[1] + local[:, 2:3] * r[2]
    if (s != 1.0).any():
        local = local / s
    return _SDF[part.primitive.kind](local, part.primitive) * float(s.min())


def smooth_min(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Polynomial smooth minimum with blend radius k (k = 0: plain min)."""
    if k <= 0.0:
        return np.minimum(a, b)
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0.0, 1.0)
    return b + (a - b) * h - k * h * (1.0 - h)


def smooth_max(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Polynomial smooth maximum with blend radius k."""
    return -smooth_min(-a, -b, k)


def _part_box(part: Part) -> tuple[np.ndarray, np.ndarray]:
    """(centre, half extents) [m] of a part's world bounding box."""
    tf = part.transform
    half = np.abs(rotation_matrix(tf) * (primitive_half_extent(part) * np.asarray(tf.scale))).sum(axis=1)
    return np.asarray(tf.translation_m, dtype=np.float64), half


def culled_part_sdf(p: np.ndarray, part: Part) -> np.ndarray:
    """part_sdf near the part, the distance to its bounding box beyond its blend radius plus its size from that box
    (a lower bound: every sign is kept, values near the combined surface move only where a part's own distance was a
    loose bound); a program of many small parts evaluates each only around itself."""
    centre, half = _part_box(part)
    margin = part.blend_m + float(half.max())
    gap = np.maximum(np.abs(p - centre) - half, 0.0)
    near = (gap[:, 0] <= margin) & (gap[:, 1] <= margin) & (gap[:, 2] <= margin)
    if near.all():
        return part_sdf(p, part)
    d = _len(gap)
    if near.any():
        d[near] = part_sdf(p[near], part)
    return d


def _grid_part_sdf(axes: Sequence[np.ndarray], part: Part) -> np.ndarray:
    """part_sdf at the points of the grid with coordinate axes (x, y, z), as an (nx, ny, nz) array: the same values,
    the part's local coordinates built per axis and broadcast (p - t and its rotation are separable on a grid)."""
    tf = part.transform
    s = np.asarray(tf.scale, dtype=np.float64)
    rel = [a - c for a, c in zip(axes, np.asarray(tf.translation_m))]
    shape = tuple(len(a) for a in axes)
    if any(tf.rotation_deg):  # part_sdf's column-by-column product, summed in its order
        r = rotation_matrix(tf)
        local = (rel[0][:, None, None, None] * r[0] + rel[1][None, :, None, None] * r[1]) \
            + rel[2][None, None, :, None] * r[2]
    else:
        local = np.empty((*shape, 3))
        local[..., 0] = rel[0][:, None, None]
        local[..., 1] = rel[1][None, :, None]
        local[..., 2] = rel[2][None, None, :]
    local = local.reshape(-1, 3)
    if (s != 1.0).any():
        local = local / s
    return (_SDF[part.primitive.kind](local, part.primitive) * float(s.min())).reshape(shape)


def _grid_culled_part_sdf(axes: Sequence[np.ndarray], part: Part) -> np.ndarray:
    """culled_part_sdf on the grid of `axes`, the same values: the part's near region is a box of grid cells and its
    gap to the part's box is separable by axis, so neither is computed point by point."""
    centre, half = _part_box(part)
    margin = part.blend_m + float(half.max())
    gaps = [np.maximum(np.abs(a - c) - h, 0.0) for a, c, h in zip(axes, centre, half)]
    near = [np.flatnonzero(g <= margin) for g in gaps]  # contiguous: |a - c| falls then rises along a sorted axis
    if all(len(n) == len(a) for n, a in zip(near, axes)):
        return _grid_part_sdf(axes, part)
    sq = (gaps[0] * gaps[0])[:, None, None] + (gaps[1] * gaps[1])[None, :, None]  # _len's order of summation
    sq = sq + (gaps[2] * gaps[2])[None, None, :]
    d = np.sqrt(sq)
    if all(len(n) for n in near):
        box = tuple(slice(int(n[0]), int(n[-1]) + 1) for n in near)
        d[box] = _grid_part_sdf([a[b] for a, b in zip(axes, box)], part)
    return d


def grid_program_sdf(axes: Sequence[np.ndarray], program: ShapeProgram) -> np.ndarray:
    """program_sdf at the points of the grid with coordinate axes (x, y, z), as an (nx, ny, nz) array: the same values
    as program_sdf of the flattened grid, each part evaluated only on the box of cells around it."""
    axes = [np.asarray(a, dtype=np.float64) for a in axes]
    return _combined(program, lambda part: _grid_part_sdf(axes, part), lambda part: _grid_culled_part_sdf(axes, part))


def program_sdf(p: np.ndarray, program: ShapeProgram) -> np.ndarray:
    """Signed distance of a whole program at points p (N, 3); parts are combined in order."""
    p = np.asarray(p, dtype=np.float64)
    return _combined(program, lambda part: part_sdf(p, part), lambda part: culled_part_sdf(p, part))


def _combined(program: ShapeProgram, first: Callable[[Part], np.ndarray], culled: Callable[[Part], np.ndarray]
              ) -> np.ndarray:
    """The program's parts folded in order (union, subtract, intersect with their blends): the first part's field,
    then each later part's culled field."""
    d = first(program.parts[0])
    for part in program.parts[1:]:
        di = culled(part)
        if part.operation == "union":
            d = smooth_min(d, di, part.blend_m)
        elif part.operation == "subtract":
            d = smooth_max(d, -di, part.blend_m)
        else:
            d = smooth_max(d, di, part.blend_m)
    return d


def primitive_half_extent(part: Part) -> np.ndarray:
    """Half extents of the untransformed primitive's bounding box [m]."""
    prim = part.primitive
    if prim.kind == "ellipsoid" or prim.kind == "superellipsoid":
        return np.asarray(prim.radii_m, dtype=np.float64)
    if prim.kind == "capsule":
        return np.array([prim.radius_m, prim.radius_m, prim.radius_m + prim.length_m / 2.0])
    if prim.kind == "rounded_box":
        return np.asarray(prim.size_m, dtype=np.float64) / 2.0
    if prim.kind == "cylinder":
        return np.array([prim.radius_m, prim.radius_m, prim.height_m / 2.0])
    if prim.kind == "torus":
        r = prim.major_radius_m + prim.minor_radius_m
        return np.array([r, r, prim.minor_radius_m])
    r = max(prim.radius_bottom_m, prim.radius_top_m)
    return np.array([r, r, prim.height_m / 2.0])


def program_bounds(program: ShapeProgram) -> np.ndarray:
    """Conservative (2, 3) world bounding box of the union parts, widened by blend radii [m]."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)
    for part in program.parts:
        if part.operation != "union" and part is not program.parts[0]:
            continue
        tf = part.transform
        pts = (corners * primitive_half_extent(part) * np.asarray(tf.scale)) @ rotation_matrix(tf).T
        pts += np.asarray(tf.translation_m)
        lo = np.minimum(lo, pts.min(axis=0) - part.blend_m)
        hi = np.maximum(hi, pts.max(axis=0) + part.blend_m)
    return np.stack([lo, hi])


REVEAL_CUT = "reveal cut"  # a cutting part so named shows what it cuts on its face (a halved cake's layers), not its colour


def part_colors(p: np.ndarray, program: ShapeProgram, sharpness_m: float) -> np.ndarray:
    """Linear RGB at surface points: parts nearest the point win, softly blended over sharpness_m. On the face of a
    cutting part named REVEAL_CUT the innermost solid part holding the point wins (the one whose surface is nearest
    among those it lies in: a cake's sponge inside its frosting coat; the layers a cut shows)."""
    signed = np.stack([part_sdf(p, part) for part in program.parts], axis=1)
    d = np.abs(signed)
    sharp = max(sharpness_m, 1e-6)
    w = np.exp(-(d - d.min(axis=1, keepdims=True)) / sharp)
    cols = np.asarray([part.color_rgb for part in program.parts], dtype=np.float64)
    rgb = (w @ cols) / w.sum(axis=1, keepdims=True)
    reveal = [i for i, part in enumerate(program.parts) if part.operation != "union" and part.name.startswith(REVEAL_CUT)]
    if reveal:
        on_cut = np.isin(np.argmin(d, axis=1), reveal)
        solid = [i for i, part in enumerate(program.parts) if part.operation == "union" or i == 0]
        if on_cut.any() and solid:
            inside = signed[on_cut][:, solid]
            depth = np.where(inside < 0.0, -inside, np.abs(inside) + 1e3)  # (outside every part: the nearest)
            ws = np.exp(-(depth - depth.min(axis=1, keepdims=True)) / sharp)
            rgb[on_cut] = (ws @ cols[solid]) / ws.sum(axis=1, keepdims=True)
    return rgb
