"""MPM particles on a lattice inside the mesh; per-particle volumes sum exactly to the mesh volume."""

from __future__ import annotations

import numpy as np
import trimesh
from pydantic import Field
from scipy.spatial import cKDTree

from contracts.base import Model
from contracts.errors import InputError
from tasks.geometry.raster import lattice_winding

_SUB = 2  # sub-samples per cell edge used to measure each cell's inside fraction
_OFFSET = np.array([0.3183098861837907, 0.2718281828459045, 0.1414213562373095]) * 1e-3  # breaks exact edge hits


class ParticleSettings(Model):
    """Lattice resolution for one quality preset."""

    cells_per_longest_extent: int = Field(gt=1, description="lattice cells along the longest extent [-]")
    min_cells_through_thinnest: int = Field(default=4, gt=0, description="cells across the thinnest extent [-]")
    max_particles: int = Field(gt=0, description="particle budget [-]")
    min_particles: int = Field(default=1000, ge=0, description="refine the lattice until at least this many [-]")


def inside_lattice(mesh: trimesh.Trimesh, origin: np.ndarray, spacing: float, shape: tuple[int, ...]) -> np.ndarray:
    """Boolean occupancy of lattice points origin + i*spacing (winding number > 0); shape (nx, ny, nz)."""
    winding, _ = lattice_winding(mesh.vertices, mesh.faces, origin, spacing, shape)
    return winding > 0


def _lattice(mesh: trimesh.Trimesh, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    lo, hi = mesh.bounds
    n = np.maximum(np.ceil((hi - lo) / dx).astype(int), 1)
    origin = lo + 0.5 * ((hi - lo) - n * dx)  # centre the lattice on the bounding box
    h = dx / _SUB
    fine = inside_lattice(mesh, origin + 0.5 * h + _OFFSET * dx, h, tuple(int(v) for v in n * _SUB))
    blocks = fine.reshape(n[0], _SUB, n[1], _SUB, n[2], _SUB)
    count = blocks.sum(axis=(1, 3, 5))
    cells = np.argwhere(count > 0)
    sub = np.argwhere(np.ones((_SUB,) * 3, dtype=bool))
    # centroid of the inside sub-samples of each cell
    occ = blocks.transpose(0, 2, 4, 1, 3, 5)[cells[:, 0], cells[:, 1], cells[:, 2]].reshape(len(cells), -1)
    centroid_sub = (occ[:, :, None] * sub[None]).sum(axis=1) / occ.sum(axis=1, keepdims=True)
    pos = origin + (cells * _SUB + centroid_sub + 0.5) * h + _OFFSET * dx
    frac = count[cells[:, 0], cells[:, 1], cells[:, 2]] / float(_SUB**3)
    return pos, frac, cells


def sample_particles(
    mesh: trimesh.Trimesh, settings: ParticleSettings
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """Positions [m] (N, 3), volumes [m^3] (N,) summing to the mesh volume, RGB uint8 (N, 3), spacing [m], raw fill ratio."""
    ext = mesh.extents
    dx = min(float(ext.max()) / settings.cells_per_longest_extent, float(ext.min()) / settings.min_cells_through_thinnest)
    pos = frac = np.zeros(0)
    for _ in range(8):
        pos, frac, _ = _lattice(mesh, dx)
        if len(pos) > settings.max_particles:
            dx *= (len(pos) / settings.max_particles) ** (1.0 / 3.0) * 1.02
        elif len(pos) < settings.min_particles and len(pos) > 0:
            dx *= (len(pos) / settings.min_particles) ** (1.0 / 3.0) * 0.98
        else:
            break
    if len(pos) == 0:
        raise InputError("no particles fit inside the mesh (is it closed and not paper-thin?)")
    if len(pos) > settings.max_particles:
        raise InputError(f"{len(pos)} particles exceed the budget of {settings.max_particles}")
    volume = float(mesh.volume)
    vol = frac * dx**3
    fill_ratio = float(vol.sum() / volume)  # lattice estimate of the volume before normalisation
    vol = vol * (volume / vol.sum())
    colors = nearest_vertex_colors(mesh, pos)
    return pos, vol, colors, dx, fill_ratio


def nearest_vertex_colors(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """RGB uint8 colour of the nearest mesh vertex for each point."""
    vc = np.asarray(mesh.visual.vertex_colors)[:, :3] if mesh.visual.kind == "vertex" else None
    if vc is None or len(vc) != len(mesh.vertices):
        return np.full((len(points), 3), 200, dtype=np.uint8)
    _, idx = cKDTree(mesh.vertices).query(points)
    return vc[idx].astype(np.uint8)
