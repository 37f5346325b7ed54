"""Convex collision proxy: CoACD decomposition (parameters from the L0 contract), OBJ parts and a URDF."""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
import trimesh
from pydantic import Field

from contracts.base import Model
from tasks.geometry.meshing import mesh_from_field
from tasks.geometry.particles import inside_lattice

NOMINAL_DENSITY_KG_PER_M3 = 100.0  # placeholder for the URDF inertial only; L1 sets the real mass


class CoacdSettings(Model):
    """CoACD knobs (see coacd.run_coacd); method 'hull' is a single convex hull for quick previews."""

    method: str = Field(default="coacd", pattern="^(coacd|hull)$")
    threshold: float = Field(default=0.08, gt=0, description="concavity threshold [-]")
    max_convex_hull: int = Field(default=16, description="hull budget, -1 for no limit")
    preprocess_resolution: int = Field(default=30, gt=0)
    resolution: int = Field(default=2000, gt=0, description="sampling resolution of the Hausdorff metric")
    mcts_iterations: int = Field(default=150, gt=0)
    mcts_nodes: int = Field(default=20, gt=0)
    mcts_max_depth: int = Field(default=3, gt=0)
    max_input_faces: int = Field(default=20000, gt=0, description="decimate larger inputs first [-]")
    seed: int = 0
    union_ratio_max: float = Field(default=1.5, gt=1.0, description="with our merge: while the hulls' union is more "
                                   "than this over the mesh volume, merge down to a larger budget (GROW_BUDGETS) [-]")
    merge: str = Field(default="volume", pattern="^(volume|coacd)$",
                       description="how the pieces come down to the hull budget: 'volume', ours (merge_hulls: the pair "
                                   "whose joint hull adds least volume first), or 'coacd' (CoACD's own, 2-3x slower)")


def convex_parts(mesh: trimesh.Trimesh, settings: CoacdSettings) -> list[trimesh.Trimesh]:
    """Convex pieces covering the mesh (CoACD, or one hull)."""
    if settings.method == "hull":
        return [mesh.convex_hull]
    import coacd

    coacd.set_log_level("error")
    # a mesh that hugs its hull: CoACD's root hull only (on its own remeshed copy: faceted as its parts always are;
    # a smooth hull of every vertex of a ball rolls in pybullet and never settles)
    root_only = _hugs_hull(mesh)
    src = mesh
    if len(mesh.faces) > settings.max_input_faces:
        src = _coarsen(mesh, settings.max_input_faces)
    cm = coacd.Mesh(np.asarray(src.vertices, dtype=np.float64), np.asarray(src.faces, dtype=np.int32))
    own_merge = settings.merge == "volume" and not root_only
    volume = float(mesh.volume)

    def decompose(threshold: float, preprocess_mode: str = "auto") -> list[trimesh.Trimesh]:
        raw = coacd.run_coacd(
            cm, threshold=1.0 if root_only else threshold,
            max_convex_hull=1 if root_only else (-1 if own_merge else settings.max_convex_hull),
            preprocess_resolution=settings.preprocess_resolution, resolution=settings.resolution,
            mcts_iterations=settings.mcts_iterations, mcts_nodes=settings.mcts_nodes,
            mcts_max_depth=settings.mcts_max_depth, seed=settings.seed, merge=not own_merge,
            preprocess_mode=preprocess_mode,
        )
        pieces = [hull for v, f in raw if (hull := piece_hull(v, f)) is not None]
        if own_merge and settings.max_convex_hull > 0:
            pieces = merged_to_cover(pieces, settings.max_convex_hull, volume, settings.union_ratio_max)
        return pieces

    parts = decompose(settings.threshold)
    if root_only or volume <= 0 or len(parts) > FINER_MAX_PIECES_ONCE:
        return parts
    # a thin, gently curved good (a necktie, a belt, a strap lying in an arc) is under CoACD's concavity threshold
    # (measured against its bounding box's diagonal) as one piece or a few whose hulls are twice its volume, a coiled
    # rope or cable as a few fat rings (1.6-1.95x): split finer (these only: a finer threshold costs a coiled rope
    # 4 -> 29 s of CPU, which is still better than an L0 that fails its proxy gate)
    # A thin-walled hollow good (a knee brace's sleeve, a play teepee's canvas, a disc cone, a carton of fries) comes
    # out of the first pass as 17-26 pieces, each a hull across the hollow it walls (1.64-2.01x the mesh): split once
    # finer (0.4: 68-138 pieces, 7-20 s of CPU, merged down to GROW_BUDGETS 1.35-1.52x); the second, finer still, only
    # after a first pass of at most FINER_MAX_PIECES
    steps = FINER_THRESHOLDS if len(parts) <= FINER_MAX_PIECES else FINER_THRESHOLDS[:1]
    # CoACD's own preprocessing ('auto': when it judges the input not manifold) remeshes it on a grid of
    # preprocess_resolution cells along its longest side, which fattens a part thinner than a cell (a cotton swab's
    # 2.6 mm stick in an 8 cm swab: 3 pieces 2.02x the mesh at the finest threshold, 0.98 without it): our input is
    # watertight (the mesh, or _coarsen's marching-cubes copy), so the finer passes skip it
    mode = "off" if src.is_watertight and src.is_winding_consistent else "auto"
    best, ratio = parts, union_volume(parts) / volume
    for finer in steps:
        if ratio <= settings.union_ratio_max:
            break
        pieces = decompose(settings.threshold * finer, mode)
        if (r := union_volume(pieces) / volume) < ratio:
            best, ratio = pieces, r
    return best


FINER_THRESHOLDS = (0.4, 0.15)  # CoACD's threshold x these, in turn, while the hulls' union is over union_ratio_max
FINER_MAX_PIECES = 12  # ... and CoACD's first pass found at most this many pieces [-]
FINER_MAX_PIECES_ONCE = 32  # ... or at most this many: the first of FINER_THRESHOLDS only [-]


def piece_hull(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh | None:
    """The convex hull of one of CoACD's pieces, None for a flat or degenerate one (unmerged, CoACD can return a
    sliver of three points: qhull cannot hull it, and it covers no volume)."""
    from scipy.spatial import QhullError

    points = np.unique(np.asarray(vertices, dtype=np.float64), axis=0)
    if len(points) < 4:
        return None
    try:
        with np.errstate(invalid="ignore", divide="ignore"):  # (a flat piece's joggled hull has zero-area faces)
            hull = trimesh.convex.convex_hull(points)
    except QhullError:
        return None
    return hull if hull.volume > 0 else None


def merged_to_cover(pieces: list[trimesh.Trimesh], budget: int, volume_m3: float, ratio_max: float
                    ) -> list[trimesh.Trimesh]:
    """The pieces merged down to `budget` (merge_hulls), or to the next of GROW_BUDGETS while their union is over
    ratio_max x volume_m3 (a thin hollow good: a beanie, a bucket hat)."""
    parts = merge_hulls(pieces, budget)
    for larger in GROW_BUDGETS:
        if len(parts) == len(pieces) or volume_m3 <= 0 or union_volume(parts) <= ratio_max * volume_m3:
            break
        if larger > budget:
            parts = merge_hulls(pieces, larger)
    return parts


# CoACD's own merge scores each candidate pair by the concavity of its joint hull against the mesh (Hausdorff samples):
# on a dog bed it merged 72 pieces down to 16 in 21 of its 38 s of CPU. merge_hulls scores a pair by the volume its
# joint hull adds to the two (V-HACD's measure), a qhull call each: 2.8 s for the same 72, union / mesh volume 1.13
# against CoACD's 1.11.
NEAR_GAP = 0.02  # pieces whose boxes lie within this fraction of the object's longest extent are neighbours [-]
# budgets tried in turn while the union is over CoacdSettings.union_ratio_max: a knitted beanie's 46 pieces merged to
# 16 covered 1.90 of its volume (the L0 gate 'proxy hugs mesh' allows 1.6: the asset failed L0), to 24 1.65, to 32
# 1.50; a bucket hat 1.87, 1.60, 1.50
GROW_BUDGETS = (24, 32, 48)


def merge_hulls(parts: list[trimesh.Trimesh], budget: int) -> list[trimesh.Trimesh]:
    """Merge convex pieces pairwise, neighbours first and the pair whose joint hull adds least volume first, until
    at most `budget` remain (deterministic: ties go to the lowest indices)."""
    from scipy.spatial import ConvexHull

    if len(parts) <= budget:
        return parts
    points = [np.asarray(p.vertices, dtype=np.float64) for p in parts]
    volumes = [float(p.volume) for p in parts]
    boxes = [(pt.min(axis=0), pt.max(axis=0)) for pt in points]
    reach = NEAR_GAP * float(np.ptp(np.vstack(points), axis=0).max())

    def added(i: int, j: int, far_too: bool) -> float:
        gap = np.maximum(boxes[i][0] - boxes[j][1], boxes[j][0] - boxes[i][1]).max()
        if gap > reach and not far_too:
            return np.inf
        return float(ConvexHull(np.vstack([points[i], points[j]])).volume) - volumes[i] - volumes[j]

    alive = list(range(len(parts)))
    cost: dict[tuple[int, int], float] = {(a, b): added(a, b, False) for k, a in enumerate(alive) for b in alive[k + 1:]}
    while len(alive) > budget:
        pair = min(cost, key=lambda ab: (cost[ab], ab))
        if not np.isfinite(cost[pair]):  # no neighbours left: price every pair
            cost = {ab: added(*ab, True) for ab in cost}
            pair = min(cost, key=lambda ab: (cost[ab], ab))
        i, j = pair
        hull = ConvexHull(np.vstack([points[i], points[j]]))
        new = len(points)
        points.append(hull.points[hull.vertices])
        volumes.append(float(hull.volume))
        boxes.append((points[new].min(axis=0), points[new].max(axis=0)))
        alive = [k for k in alive if k not in pair]
        cost = {ab: c for ab, c in cost.items() if i not in ab and j not in ab}
        cost.update({(k, new): added(k, new, False) for k in alive})
        alive.append(new)
    return [trimesh.Trimesh(points[k]).convex_hull for k in alive]


# A mesh within a few percent of its convex hull everywhere is proxied by CoACD's root hull alone: the shallow grooves of a yarn ball
# or a pom-pom (volume 0.95 of the hull, the gap's 95th percentile 2.3-2.5 % of the longest extent) kept CoACD
# splitting into its 16-part budget for 38-41 s on one core, to cover the same volume; a strawberry (0.93, 4.4 %),
# a brain stress ball (0.92) or a rubber duck (0.85) still go through CoACD (3-4 s).
NEAR_CONVEX_VOLUME_RATIO = 0.93  # mesh volume / hull volume at least [-]
NEAR_CONVEX_GAP_P95 = 0.03  # 95th percentile hull-to-mesh distance / longest extent at most [-]
# ... and at least: a smooth convex body (a ball, a block, a marshmallow: under 1 %) goes through CoACD as before (its
# parts are what L1 was tuned on: a marshmallow's one root hull jittered on its flat face and never settled in pybullet)
NEAR_CONVEX_GAP_MIN = 0.01
NEAR_CONVEX_SAMPLES = 600


def _hugs_hull(mesh: trimesh.Trimesh) -> bool:
    """True when the mesh's convex hull hugs a grooved or bumpy surface (NEAR_CONVEX_*)."""
    hull = mesh.convex_hull
    if hull.volume <= 0 or mesh.volume / hull.volume < NEAR_CONVEX_VOLUME_RATIO:
        return False
    points, _ = trimesh.sample.sample_surface_even(hull, NEAR_CONVEX_SAMPLES, seed=0)
    _, gap, _ = trimesh.proximity.closest_point(mesh, points)
    p95 = float(np.percentile(gap, 95)) / float(mesh.extents.max())
    return NEAR_CONVEX_GAP_MIN <= p95 <= NEAR_CONVEX_GAP_P95


COARSE_THINNEST = 6  # cells across the coarse copy's thinnest extent [-]
COARSE_MAX_CELLS = 200  # cells along its longest, at most [-]


def _coarsen(mesh: trimesh.Trimesh, max_faces: int) -> trimesh.Trimesh:
    """Coarser watertight copy for CoACD (occupancy on a grid, remeshed; falls back to the input); the grid keeps
    COARSE_THINNEST cells across the thinnest extent (up to COARSE_MAX_CELLS along the longest), so a long or flat
    good (a 1.5 m pool noodle 6.5 cm across, a bath mat) is not lost between its cells; a copy that lost or gained more
    than COARSE_VOLUME_TOLERANCE of the volume (a thin wall between the cells: a straw hat's brim kept 5 %, a cat
    tunnel's 34 %) is redone on finer grids, else the mesh itself is used."""
    res = int(max(24, min(96, np.sqrt(max_faces / 6.0))))
    longest, thinnest = float(mesh.extents.max()), float(mesh.extents.min())
    dx0 = max(min(longest / res, thinnest / COARSE_THINNEST), longest / COARSE_MAX_CELLS)
    volume = float(mesh.volume)
    for refine in COARSE_REFINE:
        dx = dx0 / refine
        lo = mesh.bounds[0] - 1.5 * dx
        shape = tuple(int(n) for n in np.ceil(mesh.extents / dx).astype(int) + 4)
        occ = inside_lattice(mesh, lo + 1e-4 * dx, dx, shape)
        try:
            coarse = mesh_from_field(0.5 - occ.astype(np.float64), lo, dx)
        except Exception:  # pragma: no cover - keep the original when coarsening fails
            return mesh
        # a flat good's cells across its thinnest side can make the copy finer than the mesh (a foam puzzle tile:
        # 14,904 faces -> 81,312, CoACD 21 s instead of 8 s): then the mesh itself is the coarser
        if len(coarse.faces) >= len(mesh.faces):
            return mesh
        if abs(float(coarse.volume) / volume - 1.0) <= COARSE_VOLUME_TOLERANCE:
            return coarse
    return mesh


COARSE_REFINE = (1.0, 2.0)  # the coarse grid, then one twice as fine [-]
COARSE_VOLUME_TOLERANCE = 0.15  # the coarse copy's volume within this share of the mesh's [-]


def union_volume(parts: list[trimesh.Trimesh]) -> float:
    """Volume of the union of convex parts [m^3] (manifold3d boolean union; sum of volumes if it fails)."""
    try:
        import manifold3d as mf

        solids = [
            mf.Manifold(mf.Mesh(vert_properties=np.asarray(p.vertices, np.float32), tri_verts=np.asarray(p.faces, np.uint32)))
            for p in parts
        ]
        return float(mf.Manifold.batch_boolean(solids, mf.OpType.Add).volume()) if len(solids) > 1 else float(parts[0].volume)
    except Exception:  # pragma: no cover
        return float(sum(p.volume for p in parts))


def write_collision(parts: list[trimesh.Trimesh], mesh: trimesh.Trimesh, out_dir: Path, name: str) -> Path:
    """Write part_NNN.obj files and `<name>.urdf` (one link, one collision per convex part); returns the URDF path."""
    out_dir.mkdir(parents=True, exist_ok=True)
    files = []
    for i, part in enumerate(parts):
        fname = f"part_{i:03d}.obj"
        part.export(out_dir / fname)
        files.append(fname)
    mass = NOMINAL_DENSITY_KG_PER_M3 * float(mesh.volume)
    com = mesh.center_mass
    inertia = np.asarray(mesh.moment_inertia) * NOMINAL_DENSITY_KG_PER_M3
    geoms = "".join(
        f'    <collision><origin xyz="0 0 0"/><geometry><mesh filename="{f}" scale="1 1 1"/></geometry></collision>\n'
        f'    <visual><origin xyz="0 0 0"/><geometry><mesh filename="{f}" scale="1 1 1"/></geometry></visual>\n'
        for f in files
    )
    safe = escape(name.replace(" ", "_")) or "asset"
    urdf = (
        f'<?xml version="1.0"?>\n<robot name="{safe}">\n  <!-- inertial: nominal density {NOMINAL_DENSITY_KG_PER_M3} kg/m^3;'
        f" L1 sets the real mass -->\n"
        f'  <link name="base_link">\n    <inertial>\n      <origin xyz="{com[0]:.9g} {com[1]:.9g} {com[2]:.9g}"/>\n'
        f'      <mass value="{mass:.9g}"/>\n'
        f'      <inertia ixx="{inertia[0, 0]:.9g}" ixy="{inertia[0, 1]:.9g}" ixz="{inertia[0, 2]:.9g}" '
        f'iyy="{inertia[1, 1]:.9g}" iyz="{inertia[1, 2]:.9g}" izz="{inertia[2, 2]:.9g}"/>\n    </inertial>\n'
        f"{geoms}  </link>\n</robot>\n"
    )
    path = out_dir / f"{safe}.urdf"
    path.write_text(urdf, encoding="utf-8")
    return path
