"""Tetrahedral volume mesh of an asset's surface (isosurface stuffing, tasks/export/stuffing.py), its quality, its
boundary and its files.

The mesh is in the asset frame (z up, resting on z = 0, metres): the frame of particles.zarr and its surface_mesh.
Tets are positively oriented: det[b - a, c - a, d - a] > 0. Deterministic: the same surface gives the same bytes in
any process, with any thread count (no random numbers, no parallel reductions). Files: legacy VTK 4.2 ASCII (.vtk)
and Gmsh 2.2 ASCII (.msh), both written here (a few lines each; meshio reads both).
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from contracts.errors import InputError, SimulationError
from tasks.export.stuffing import stuff

MIN_DIHEDRAL_DEG = 4.0        # a tet with a dihedral angle below this (or above MAX_DIHEDRAL_DEG) is a sliver or
MAX_DIHEDRAL_DEG = 176.0      # a cap (stuffing guarantees [10.7, 164.8] deg: a check, not a retry reason)
HARD_MIN_DIHEDRAL_DEG = 2.0   # the best attempt still below this: SimulationError (no usable mesh)
MAX_VOLUME_ERROR = 0.02       # |tet volume / surface volume - 1| above this: re-meshed finer (next attempt)
DEFAULT_EDGE_FRACTION = 0.12  # ideal edge length = this x the bounding-box diagonal when none is given
# lattice spacing of each attempt, x the edge length: the first that meets every bar (volume, surface deviation,
# manifold boundary, no sliver) is kept (a coarser lattice cuts more off curved and sharp parts, or pinches thin ones)
SPACING_SCALES = (0.75, 0.65, 0.55, 0.47, 0.4, 0.34, 0.29)
# the meshed isosurface is the surface offset outwards by at most this x the bounding-box diagonal, chosen to give
# the surface's volume (an inscribed mesh is smaller: its boundary vertices lie on the surface, its faces inside)
ENVELOPE_FRACTION = 4e-3
MAX_SURFACE_DEVIATION = 0.035  # a surface vertex farther than this x the diagonal from the mesh's boundary (a thin
# part lost, a sharp corner cut): re-meshed finer (next attempt)
VOLUME_TARGET = 0.002         # the offset is corrected (at most OFFSET_STEPS times) until the volume is this close
OFFSET_STEPS = 2
OFFSET_QUANTUM_M = 1e-9       # offsets are multiples of this, so last-bit differences of a sum cannot change them


@dataclass(frozen=True)
class TetMesh:
    """A linear tetrahedral mesh: nodes [m] and positively oriented tets (node indices)."""

    nodes_m: np.ndarray   # (N, 3) float64
    tets: np.ndarray      # (M, 4) int64


def signed_volumes_m3(nodes_m: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Signed volume of each tet [m^3] (positive when oriented)."""
    p = nodes_m[tets]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def enclosed_volume_m3(vertices_m: np.ndarray, faces: np.ndarray) -> float:
    """The signed volume [m^3] a closed triangle surface encloses (divergence theorem; positive for outward faces)."""
    p = vertices_m[faces]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def dihedral_angles_deg(nodes_m: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The six interior dihedral angles of each tet [deg], shape (M, 6)."""
    p = nodes_m[tets]
    # face k is opposite vertex k; its outward normal
    faces = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
    normals = []
    for a, b, c in faces:
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        normals.append(n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300))
    out = []
    for i in range(4):
        for j in range(i + 1, 4):
            cos = np.clip(-np.einsum("ij,ij->i", normals[i], normals[j]), -1.0, 1.0)
            out.append(np.degrees(np.arccos(cos)))
    return np.stack(out, axis=1)


def tet_quality(tet: TetMesh) -> dict[str, float]:
    """min/max dihedral angle [deg], total and smallest volume [m^3], inverted (non-positive) count, sizes."""
    vol = signed_volumes_m3(tet.nodes_m, tet.tets)
    dih = dihedral_angles_deg(tet.nodes_m, tet.tets)
    return {"min_dihedral_deg": float(dih.min()), "max_dihedral_deg": float(dih.max()),
            "volume_m3": float(vol.sum()), "min_volume_m3": float(vol.min()), "inverted_count": float((vol <= 0).sum()),
            "sliver_count": float(((dih.min(axis=1) < MIN_DIHEDRAL_DEG) | (dih.max(axis=1) > MAX_DIHEDRAL_DEG)).sum()),
            "node_count": float(len(tet.nodes_m)), "tet_count": float(len(tet.tets))}


def _clean(nodes_m: np.ndarray, tets: np.ndarray) -> TetMesh:
    """Drop unreferenced nodes and orient every tet positively."""
    tets = np.asarray(tets, dtype=np.int64)
    used, inverse = np.unique(tets, return_inverse=True)
    nodes = np.ascontiguousarray(np.asarray(nodes_m, dtype=np.float64)[used])
    tets = inverse.reshape(tets.shape).astype(np.int64)
    flip = signed_volumes_m3(nodes, tets) < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return TetMesh(nodes_m=nodes, tets=np.ascontiguousarray(tets))


def _boundary_is_manifold(tet: TetMesh) -> bool:
    """Every boundary edge in exactly two boundary triangles (no pinched thin part)."""
    f = boundary_faces(tet)
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def surface_deviation_m(tet: TetMesh, vertices_m: np.ndarray, faces: np.ndarray) -> float:
    """The largest distance [m] from a vertex of the surface (vertices_m, faces) to the tet mesh's boundary."""
    import igl

    sv, sf = surface_of(tet)
    d2 = igl.point_mesh_squared_distance(np.ascontiguousarray(vertices_m, dtype=np.float64), sv, sf)[0]
    return float(np.sqrt(np.max(d2)))


def tetrahedralize(vertices_m: np.ndarray, faces: np.ndarray, *, edge_length_m: float | None = None) -> TetMesh:
    """Tet mesh of a closed, outward-oriented triangle surface by isosurface stuffing: each attempt (SPACING_SCALES)
    offsets the surface (within ENVELOPE_FRACTION) to match its volume, and re-meshes finer while the volume is off
    by over MAX_VOLUME_ERROR, the surface is farther than MAX_SURFACE_DEVIATION from the boundary, the boundary is
    not a manifold or a sliver remains; the best attempt is kept (SimulationError when it has inverted tets or one
    under HARD_MIN_DIHEDRAL_DEG)."""
    v = np.ascontiguousarray(vertices_m, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise InputError("tetrahedralize needs (N, 3) vertices and (M, 3) triangle faces")
    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    if not diag > 0:
        raise InputError("tetrahedralize: the surface has zero extent")
    edge = float(edge_length_m) if edge_length_m else DEFAULT_EDGE_FRACTION * diag
    p = v[f]
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    surface_volume = enclosed_volume_m3(v, f)
    surface_area = float(np.linalg.norm(cross, axis=1).sum() / 2.0)
    if not surface_volume > 0:
        raise InputError("tetrahedralize: the surface encloses no volume (open, or faces pointing inwards)")
    if importlib.util.find_spec("igl") is None:
        raise SimulationError('the tet mesh needs libigl: pip install -e ".[export]"')

    envelope = ENVELOPE_FRACTION * diag
    best: TetMesh | None = None
    best_key: tuple[float, ...] = ()
    for scale in SPACING_SCALES:
        offset = 0.0
        for step in range(OFFSET_STEPS + 1):
            nodes, tets = stuff(v, f, edge * scale, offset)
            if len(tets) == 0:
                break
            mesh = _clean(nodes, tets)
            q = tet_quality(mesh)
            error = q["volume_m3"] / surface_volume - 1.0
            deviation = surface_deviation_m(mesh, v, f) / diag
            bad = (q["sliver_count"] + float(abs(error) > MAX_VOLUME_ERROR) + float(not _boundary_is_manifold(mesh))
                   + float(deviation > MAX_SURFACE_DEVIATION))
            key = (bad, abs(error), -q["min_dihedral_deg"])
            if best is None or key < best_key:
                best, best_key = mesh, key
            if abs(error) <= VOLUME_TARGET or step == OFFSET_STEPS:
                break
            # the volume grows by about the surface area per unit of offset
            offset = float(np.clip(offset - error * surface_volume / surface_area, -envelope, envelope))
            offset = round(offset / OFFSET_QUANTUM_M) * OFFSET_QUANTUM_M
        if best is not None and best_key[0] == 0:
            break
    if best is None:
        raise SimulationError("isosurface stuffing produced no tetrahedra (is the surface closed?)")
    q = tet_quality(best)
    if q["min_volume_m3"] <= 0 or q["min_dihedral_deg"] < HARD_MIN_DIHEDRAL_DEG:
        raise SimulationError(f"tet mesh unusable: {int(q['inverted_count'])} inverted tets, minimum dihedral angle "
                              f"{q['min_dihedral_deg']:.2f} deg")
    return best


def boundary_faces(tet: TetMesh) -> np.ndarray:
    """Boundary triangles (K, 3), indices into tet.nodes_m, counter-clockwise seen from outside."""
    t = tet.tets
    # the four faces of a positive tet (a, b, c, d), each outward
    faces = np.concatenate([t[:, [0, 2, 1]], t[:, [0, 1, 3]], t[:, [0, 3, 2]], t[:, [1, 2, 3]]])
    key = np.sort(faces, axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    return np.ascontiguousarray(faces[np.sort(index[counts == 1])])


def surface_of(tet: TetMesh) -> tuple[np.ndarray, np.ndarray]:
    """The boundary surface: its own vertices [m] (only the nodes it uses) and outward triangles."""
    faces = boundary_faces(tet)
    used, inverse = np.unique(faces, return_inverse=True)
    return tet.nodes_m[used].copy(), inverse.reshape(faces.shape).astype(np.int64)


def write_vtk(tet: TetMesh, path: Path) -> Path:
    """Legacy VTK 4.2 ASCII unstructured grid of tets (cell type 10), coordinates in metres."""
    path = Path(path)
    n, m = len(tet.nodes_m), len(tet.tets)
    lines = ["# vtk DataFile Version 4.2", "DeformSmith tet mesh (SI: metres; z up, resting on z = 0)", "ASCII",
             "DATASET UNSTRUCTURED_GRID", f"POINTS {n} double"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in tet.nodes_m.tolist()]
    lines.append(f"CELLS {m} {5 * m}")
    lines += [f"4 {a} {b} {c} {d}" for a, b, c, d in tet.tets.tolist()]
    lines.append(f"CELL_TYPES {m}")
    lines += ["10"] * m
    path.write_text("\n".join(lines) + "\n", encoding="ascii")
    return path


def write_msh(tet: TetMesh, path: Path) -> Path:
    """Gmsh 2.2 ASCII mesh of tets (element type 4), coordinates in metres, 1-based ids."""
    path = Path(path)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$Nodes", str(len(tet.nodes_m))]
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(tet.nodes_m.tolist())]
    lines += ["$EndNodes", "$Elements", str(len(tet.tets))]
    lines += [f"{i + 1} 4 2 1 1 {a + 1} {b + 1} {c + 1} {d + 1}" for i, (a, b, c, d) in enumerate(tet.tets.tolist())]
    lines.append("$EndElements")
    path.write_text("\n".join(lines) + "\n", encoding="ascii")
    return path


def _tokens(path: Path) -> list[str]:
    try:
        return Path(path).read_text(encoding="ascii").split()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read a tet mesh: {exc}") from None


def read_vtk(path: Path) -> TetMesh:
    """Read a legacy ASCII VTK unstructured grid of tets (as write_vtk writes it)."""
    tok = _tokens(path)
    try:
        i = tok.index("POINTS")
        n = int(tok[i + 1])
        nodes = np.array(tok[i + 3:i + 3 + 3 * n], dtype=np.float64).reshape(n, 3)
        j = tok.index("CELLS", i)
        m = int(tok[j + 1])
        cells = np.array(tok[j + 3:j + 3 + 5 * m], dtype=np.int64).reshape(m, 5)
        k = tok.index("CELL_TYPES", j)
        types = np.array(tok[k + 2:k + 2 + m], dtype=np.int64)
    except (ValueError, IndexError) as exc:
        raise InputError(f"{path}: not a legacy ASCII VTK tet mesh: {exc}") from None
    if not (np.all(cells[:, 0] == 4) and np.all(types == 10)):
        raise InputError(f"{path}: only linear tetrahedra (VTK cell type 10) are supported")
    return TetMesh(nodes_m=nodes, tets=np.ascontiguousarray(cells[:, 1:]))


def read_msh(path: Path) -> TetMesh:
    """Read a Gmsh 2.2 ASCII mesh of tets (as write_msh writes it)."""
    tok = _tokens(path)
    try:
        i = tok.index("$Nodes")
        n = int(tok[i + 1])
        rows = np.array(tok[i + 2:i + 2 + 4 * n], dtype=np.float64).reshape(n, 4)
        index = {int(r[0]): k for k, r in enumerate(rows)}
        j = tok.index("$Elements", i)
        m = int(tok[j + 1])
        tets: list[list[int]] = []
        pos = j + 2
        for _ in range(m):
            etype, ntags = int(tok[pos + 1]), int(tok[pos + 2])
            ids = tok[pos + 3 + ntags:pos + 3 + ntags + 4] if etype == 4 else []
            if etype == 4:
                tets.append([index[int(x)] for x in ids])
            pos += 3 + ntags + {4: 4, 2: 3, 1: 2, 15: 1}.get(etype, 0)
    except (ValueError, IndexError, KeyError) as exc:
        raise InputError(f"{path}: not a Gmsh 2.2 ASCII tet mesh: {exc}") from None
    return TetMesh(nodes_m=rows[:, 1:].copy(), tets=np.array(tets, dtype=np.int64).reshape(-1, 4))


def tet_mesh_arrays(tet: TetMesh) -> dict[str, Any]:
    """The mesh as plain arrays (what the cache stores)."""
    return {"nodes_m": tet.nodes_m, "tets": tet.tets}
