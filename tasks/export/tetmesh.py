"""Tetrahedral volume mesh of an asset's surface (fTetWild via pytetwild), its quality, its boundary and its files.

The mesh is in the asset frame (z up, resting on z = 0, metres): the frame of particles.zarr and its surface_mesh.
Tets are positively oriented: det[b - a, c - a, d - a] > 0. Files: legacy VTK 4.2 ASCII (.vtk) and Gmsh 2.2 ASCII
(.msh), both written here (a few lines each; meshio reads both).
"""

from __future__ import annotations

import contextlib
import functools
import glob
import importlib.machinery
import importlib.util
import os
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from contracts.errors import InputError, SimulationError

MIN_DIHEDRAL_DEG = 4.0        # a tet with a dihedral angle below this (or above MAX_DIHEDRAL_DEG) is a sliver or
MAX_DIHEDRAL_DEG = 176.0      # a cap: the mesh is re-optimised (next attempt)
HARD_MIN_DIHEDRAL_DEG = 2.0   # the best attempt still below this: SimulationError (no usable mesh)
MAX_VOLUME_ERROR = 0.02       # |tet volume / surface volume - 1| above this: re-meshed (next attempt)
DEFAULT_EDGE_FRACTION = 0.12  # ideal edge length = this x the bounding-box diagonal when none is given
# per attempt: (optimisation iterations, stop energy, envelope relative to the bounding-box diagonal, edge scale);
# a quick pass (seconds on the default asset), then more thorough ones only while slivers remain
ATTEMPTS = ((10, 20.0, 4e-3, 1.0), (30, 10.0, 3e-3, 1.0), (60, 8.0, 2e-3, 0.8))


@dataclass(frozen=True)
class TetMesh:
    """A linear tetrahedral mesh: nodes [m] and positively oriented tets (node indices)."""

    nodes_m: np.ndarray   # (N, 3) float64
    tets: np.ndarray      # (M, 4) int64


@functools.cache
def _fTetWild() -> ModuleType:
    """pytetwild's compiled wrapper. pytetwild 0.4's package __init__ imports pyvista (an undeclared, heavy optional
    dependency, VTK included) only for a PolyData accessor: the extension module is loaded directly instead."""
    spec = importlib.util.find_spec("pytetwild")
    if spec is None or spec.origin is None:
        raise SimulationError('the tet mesh needs pytetwild: pip install -e ".[export]"')
    found = glob.glob(os.path.join(os.path.dirname(spec.origin), "PyfTetWildWrapper*.so")) + glob.glob(
        os.path.join(os.path.dirname(spec.origin), "PyfTetWildWrapper*.pyd"))
    if not found:
        raise SimulationError("pytetwild is installed without its compiled fTetWild wrapper")
    name = "pytetwild.PyfTetWildWrapper"
    loader = importlib.machinery.ExtensionFileLoader(name, found[0])
    mod_spec = importlib.util.spec_from_file_location(name, found[0], loader=loader)
    assert mod_spec is not None
    module = importlib.util.module_from_spec(mod_spec)
    loader.exec_module(module)
    return module


@contextlib.contextmanager
def _in_scratch_dir() -> Iterator[None]:
    """Run in a temporary working directory: fTetWild writes `__tracked_surface.stl` into the current one."""
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="deformsmith-ftetwild-") as tmp:
        os.chdir(tmp)
        try:
            yield
        finally:
            os.chdir(old)


def signed_volumes_m3(nodes_m: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Signed volume of each tet [m^3] (positive when oriented)."""
    p = nodes_m[tets]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


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


def tetrahedralize(vertices_m: np.ndarray, faces: np.ndarray, *, edge_length_m: float | None = None) -> TetMesh:
    """Tet mesh of a closed triangle surface (fTetWild), re-meshed while slivers (a dihedral angle under
    MIN_DIHEDRAL_DEG or over MAX_DIHEDRAL_DEG) remain or the volume is off by over MAX_VOLUME_ERROR; the best
    attempt is kept (SimulationError when it has
    inverted tets or one under HARD_MIN_DIHEDRAL_DEG)."""
    v = np.ascontiguousarray(vertices_m, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.uint32)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise InputError("tetrahedralize needs (N, 3) vertices and (M, 3) triangle faces")
    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    if not diag > 0:
        raise InputError("tetrahedralize: the surface has zero extent")
    edge = float(edge_length_m) if edge_length_m else DEFAULT_EDGE_FRACTION * diag
    p = v[f.astype(np.int64)]
    surface_volume = float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)
    if not surface_volume > 0:
        raise InputError("tetrahedralize: the surface encloses no volume (open, or faces pointing inwards)")
    wrapper = _fTetWild()
    best: TetMesh | None = None
    best_q: dict[str, float] = {}
    for iterations, stop_energy, envelope, scale in ATTEMPTS:
        with _in_scratch_dir():
            nodes, tets = wrapper.tetrahedralize_mesh(
                v, f, True, False,  # optimise, do not skip fTetWild's surface simplification
                0.05, edge * scale, envelope, stop_energy, False,
                2, iterations, 6, True, False, False,  # 2 threads, loglevel 6, quiet, fTetWild ordering, filtered
                np.zeros((0, 3)), np.zeros((0, 4), np.int32), np.zeros(0))
        if len(tets) == 0:
            raise SimulationError("fTetWild produced no tetrahedra (is the surface closed?)")
        mesh = _clean(nodes, tets)
        q = tet_quality(mesh)
        q["bad"] = q["sliver_count"] + float(abs(q["volume_m3"] / surface_volume - 1.0) > MAX_VOLUME_ERROR)
        if best is None or (q["bad"], -q["min_dihedral_deg"]) < (best_q["bad"], -best_q["min_dihedral_deg"]):
            best, best_q = mesh, q
        if q["bad"] == 0:
            break
    assert best is not None
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
