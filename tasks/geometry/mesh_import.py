"""Mesh files (OBJ/PLY/STL/GLB/GLTF/OFF) -> one watertight, outward-oriented, vertex-coloured mesh."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from contracts.errors import InputError
from contracts.request import MESH_SUFFIXES
from tasks.geometry.meshing import mesh_from_field, split_largest
from tasks.geometry.raster import lattice_winding

SUPPORTED = MESH_SUFFIXES
REMESH_RESOLUTION = 128  # voxels along the longest extent when a voxel remesh is needed
MAX_DETACHED_SHARE = 0.05  # separate bodies beyond this share of the volume make a mesh several objects [-]


def load_mesh_file(path: Path) -> trimesh.Trimesh:
    """Read a mesh file into one Trimesh with per-vertex colours (textures sampled at the UVs)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"mesh file not found: {path}")
    if path.suffix.lower() not in SUPPORTED:
        raise InputError(f"unsupported mesh format '{path.suffix}'; use one of {', '.join(SUPPORTED)}")
    try:
        loaded = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types on corrupt files
        raise InputError(f"cannot read mesh {path.name}: {type(exc).__name__}: {exc}".split("\n")[0]) from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0 or len(loaded.vertices) < 4:
        raise InputError(f"{path.name} holds no triangles")
    if not np.all(np.isfinite(loaded.vertices)):
        raise InputError(f"{path.name} has non-finite vertex coordinates")
    colors = _vertex_colors(loaded)
    mesh = trimesh.Trimesh(np.asarray(loaded.vertices, np.float64), np.asarray(loaded.faces), process=False)
    mesh.visual = trimesh.visual.ColorVisuals(mesh, vertex_colors=colors)
    return mesh


def _vertex_colors(mesh: trimesh.Trimesh) -> np.ndarray:
    """RGBA uint8 per vertex from whatever visual the file had (grey when none)."""
    try:
        vis = mesh.visual
        if vis.kind == "texture":
            vis = vis.to_color()
        vc = np.asarray(vis.vertex_colors)
        if vc.shape == (len(mesh.vertices), 4):
            return vc.astype(np.uint8)
    except Exception:  # noqa: BLE001 - a broken texture falls back to grey
        pass
    return np.tile(np.array([190, 190, 190, 255], np.uint8), (len(mesh.vertices), 1))


def repair_mesh(mesh: trimesh.Trimesh) -> tuple[trimesh.Trimesh, list[str]]:
    """Merge seams, fix winding and fill small holes; voxel-remesh overlapping or broken bodies; refuse separate
    objects (detached fragments up to MAX_DETACHED_SHARE of the volume are dropped). Returns notes."""
    notes: list[str] = []
    colors = np.asarray(mesh.visual.vertex_colors)
    m = trimesh.Trimesh(mesh.vertices, mesh.faces, process=True, validate=True)
    m.visual = trimesh.visual.ColorVisuals(m, vertex_colors=_transfer(mesh.vertices, colors, m.vertices))
    m.merge_vertices(merge_tex=True, merge_norm=True)
    m.remove_unreferenced_vertices()
    if np.linalg.matrix_rank(m.vertices - m.vertices.mean(axis=0), tol=1e-9 * max(float(m.extents.max()), 1e-12)) < 3:
        raise InputError("the mesh is flat (zero volume): all vertices lie in one plane or line")
    if not m.is_watertight:
        trimesh.repair.fill_holes(m)
        if m.is_watertight:
            notes.append("filled small holes")
    trimesh.repair.fix_normals(m, multibody=True)
    if m.is_watertight and m.body_count == 1:
        if m.volume <= 0:
            raise InputError("the mesh encloses no volume")
        return m, notes
    if not m.is_watertight:
        open_edges = len(trimesh.grouping.group_rows(m.edges_sorted, require_count=1))
        _, unbalanced = lattice_winding(m.vertices, m.faces, m.bounds[0], float(m.extents.max()) / 64 + 1e-12, (65, 65, 65))
        if unbalanced > 0.02:
            raise InputError(
                f"the mesh is open ({open_edges} boundary edges) and encloses no well-defined volume; close it first"
            )
        notes.append(f"{open_edges} boundary edges closed by voxel remeshing")
    out, detached, share = split_largest(voxel_remesh(m, REMESH_RESOLUTION))
    if share > MAX_DETACHED_SHARE:
        raise InputError(
            f"the mesh holds {detached + 1} separate bodies (the largest has {100 * (1 - share):.0f} % of the volume); "
            "an asset is one object: join the parts, or give them one file each"
        )
    if m.is_watertight and m.body_count > detached + 1:
        notes.append(f"{m.body_count - detached} overlapping bodies merged by voxel remeshing")
    if detached:
        notes.append(f"dropped {detached} detached fragment(s) holding {100 * share:.2g} % of the volume")
    if out.volume <= 0:
        raise InputError("the mesh encloses no volume")
    return out, notes


def voxel_remesh(mesh: trimesh.Trimesh, resolution: int) -> trimesh.Trimesh:
    """Union of all bodies as a watertight mesh (every separate body kept): winding-number occupancy -> marching
    cubes, colours carried over."""
    dx = float(mesh.extents.max()) / resolution
    lo = mesh.bounds[0] - 1.5 * dx
    shape = tuple(int(n) for n in np.ceil(mesh.extents / dx).astype(int) + 4)
    winding, _ = lattice_winding(mesh.vertices, mesh.faces, lo + 1e-4 * dx, dx, shape)
    occ = (winding > 0).astype(np.float64)
    from scipy.ndimage import gaussian_filter

    out = mesh_from_field(0.5 - gaussian_filter(occ, 0.6), lo, dx, one_body=False)
    out.visual = trimesh.visual.ColorVisuals(out, vertex_colors=_transfer(mesh.vertices, np.asarray(mesh.visual.vertex_colors), out.vertices))
    return out


def _transfer(src_v: np.ndarray, src_c: np.ndarray, dst_v: np.ndarray) -> np.ndarray:
    """Colours of the nearest source vertex."""
    if len(src_c) != len(src_v):
        return np.tile(np.array([190, 190, 190, 255], np.uint8), (len(dst_v), 1))
    _, idx = cKDTree(src_v).query(dst_v)
    return np.asarray(src_c)[idx].astype(np.uint8)


def import_mesh(path: Path) -> tuple[trimesh.Trimesh, list[str]]:
    """Load and repair a mesh file (units taken as metres); returns the mesh and repair notes."""
    mesh, notes = repair_mesh(load_mesh_file(path))
    return mesh, notes
