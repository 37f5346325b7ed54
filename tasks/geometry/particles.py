"""MPM particles on a lattice inside the mesh; per-particle volumes sum exactly to the mesh volume (a hollow object's
shell: the particles within its wall of the surface, their volumes summing to the shell's)."""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import trimesh
from pydantic import Field
from scipy.spatial import cKDTree

from contracts.base import Model
from contracts.errors import InputError
from tasks.geometry.raster import lattice_winding

_SUB = 2  # sub-samples per cell edge used to measure each cell's inside fraction
MIN_WALL_SPACINGS = 2.0  # a shell's wall spans at least this many particle spacings (the MPM grid's dx is two)
_SHELL_SAMPLES_PER_WALL2 = 64.0  # surface samples per wall^2 of area for the wall distance (spacing ~ wall / 8)
_SHELL_SAMPLES = (40_000, 400_000)  # fewest and most surface samples for the wall distance
_SHELL_FILLS = 0.98  # a wall that holds this share of the solid's lattice is the solid (nothing hollow to resolve)
_OFFSET = np.array([0.3183098861837907, 0.2718281828459045, 0.1414213562373095]) * 1e-3  # breaks exact edge hits


class ParticleSettings(Model):
    """Lattice resolution for one quality preset."""

    cells_per_longest_extent: int = Field(gt=1, description="lattice cells along the longest extent [-]")
    min_cells_through_thinnest: int = Field(default=4, gt=0, description="cells across the thinnest extent [-]")
    max_particles: int = Field(gt=0, description="particle budget [-]")
    min_particles: int = Field(default=1000, ge=0, description="refine the lattice until at least this many [-]")
    hollow_particles: Literal["solid", "shell"] = Field(
        default="solid", description="a hollow concept's particles: 'solid' (the whole volume, the default) or 'shell' "
        "(its wall alone, where the lattice resolves it): the L0 contract's hollow_particles")


def inside_lattice(mesh: trimesh.Trimesh, origin: np.ndarray, spacing: float, shape: tuple[int, ...]) -> np.ndarray:
    """Boolean occupancy of lattice points origin + i*spacing (winding number > 0); shape (nx, ny, nz)."""
    winding, _ = lattice_winding(mesh.vertices, mesh.faces, origin, spacing, shape)
    return winding > 0


def _fine_grid(mesh: trimesh.Trimesh, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, np.ndarray]:
    """The lattice of cells dx across centred on the mesh's box: (cells per axis, its corner [m], the first
    sub-sample's centre [m], the sub-sample spacing [m], which sub-samples (_SUB per cell per axis) lie inside)."""
    lo, hi = mesh.bounds
    n = np.maximum(np.ceil((hi - lo) / dx).astype(int), 1)
    origin = lo + 0.5 * ((hi - lo) - n * dx)  # centre the lattice on the bounding box
    h = dx / _SUB
    o_fine = origin + 0.5 * h + _OFFSET * dx
    return n, origin, o_fine, h, inside_lattice(mesh, o_fine, h, tuple(int(v) for v in n * _SUB))


def _cell_centroids(keep: np.ndarray, n: np.ndarray, origin: np.ndarray, dx: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per cell holding any kept sub-sample: the kept sub-samples' centroid [m], their share of the cell, the cell."""
    h = dx / _SUB
    blocks = keep.reshape(n[0], _SUB, n[1], _SUB, n[2], _SUB)
    count = blocks.sum(axis=(1, 3, 5))
    cells = np.argwhere(count > 0)
    sub = np.argwhere(np.ones((_SUB,) * 3, dtype=bool))
    occ = blocks.transpose(0, 2, 4, 1, 3, 5)[cells[:, 0], cells[:, 1], cells[:, 2]].reshape(len(cells), -1)
    centroid_sub = (occ[:, :, None] * sub[None]).sum(axis=1) / occ.sum(axis=1, keepdims=True)
    pos = origin + (cells * _SUB + centroid_sub + 0.5) * h + _OFFSET * dx
    frac = count[cells[:, 0], cells[:, 1], cells[:, 2]] / float(_SUB**3)
    return pos, frac, cells


def _lattice(mesh: trimesh.Trimesh, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n, origin, _, _, fine = _fine_grid(mesh, dx)
    return _cell_centroids(fine, n, origin, dx)


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


class ShellUnresolved(ValueError):
    """The lattice cannot resolve a hollow object's wall within the particle budget (the message says why)."""


def surface_distance(mesh: trimesh.Trimesh, points: np.ndarray, wall_m: float, upper_m: float = np.inf,
                     seed: int = 0) -> np.ndarray:
    """Distance [m] of each point to the mesh surface, from dense surface samples (about wall / 8 apart): at a depth
    near the wall it overestimates by under a few percent of the wall (the nearest sample's offset along the surface,
    squared, over twice the depth); inf beyond upper_m."""
    n = int(np.clip(_SHELL_SAMPLES_PER_WALL2 * float(mesh.area) / wall_m**2, *_SHELL_SAMPLES))
    samples, _ = trimesh.sample.sample_surface(mesh, n, seed=seed)
    d, _ = cKDTree(samples).query(points, distance_upper_bound=upper_m)  # inf beyond: a deep point costs little
    return np.asarray(d)


def _shell_lattice(mesh: trimesh.Trimesh, dx: float, wall_m: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The lattice cells holding the wall: positions (centroids of the cell's sub-samples inside the mesh and within
    wall_m of its surface), the cells' filled fractions, and the wall's share of the inside sub-samples."""
    n, origin, o_fine, h, fine = _fine_grid(mesh, dx)
    idx = np.argwhere(fine)
    if len(idx) == 0:
        return np.zeros((0, 3)), np.zeros(0), 0.0
    near = surface_distance(mesh, o_fine + idx * h, wall_m, upper_m=wall_m) < wall_m
    wall = np.zeros_like(fine)
    wall[tuple(idx[near].T)] = True
    pos, frac, _ = _cell_centroids(wall, n, origin, dx)
    return pos, frac, float(near.sum()) / float(len(idx))


def shell_estimate(mesh: trimesh.Trimesh, settings: ParticleSettings, wall_m: float) -> tuple[float, int]:
    """The spacing a wall of wall_m asks for (the solid lattice's, refined to wall / MIN_WALL_SPACINGS) [m] and the
    particles it would take (the wall's volume, at most area x wall, over the spacing cubed) [-]."""
    ext = mesh.extents
    dx = min(float(ext.max()) / settings.cells_per_longest_extent,
             float(ext.min()) / settings.min_cells_through_thinnest, wall_m / MIN_WALL_SPACINGS)
    return dx, int(math.ceil(min(float(mesh.area) * wall_m, float(mesh.volume)) / dx**3))


def sample_shell(
    mesh: trimesh.Trimesh, settings: ParticleSettings, wall_m: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float, float]:
    """A hollow object's particles: those of the lattice within wall_m of the surface, at a spacing of at most
    wall_m / MIN_WALL_SPACINGS (the object's lattice refined when coarser). Positions [m] (N, 3), volumes [m^3] (N,)
    summing to the shell's volume (the mesh volume x the wall's share of the fine lattice inside it), RGB uint8
    (N, 3), spacing [m], raw fill ratio and the shell's volume [m^3]. ShellUnresolved when the wall needs more
    particles than the budget, or fills the body."""
    dx_wall = wall_m / MIN_WALL_SPACINGS
    dx, estimate = shell_estimate(mesh, settings, wall_m)
    if estimate > settings.max_particles:
        raise ShellUnresolved(
            f"a {wall_m * 1e3:.3g} mm wall needs a particle spacing of at most {dx_wall * 1e3:.3g} mm: about "
            f"{estimate} particles, over the budget of {settings.max_particles}")
    pos = frac = np.zeros(0)
    share = 0.0
    for _ in range(8):
        pos, frac, share = _shell_lattice(mesh, dx, wall_m)
        if len(pos) > settings.max_particles and dx < dx_wall * (1.0 - 1e-9):
            dx = min(dx * (len(pos) / settings.max_particles) ** (1.0 / 3.0) * 1.02, dx_wall)
        elif 0 < len(pos) < settings.min_particles:
            dx *= (len(pos) / settings.min_particles) ** (1.0 / 3.0) * 0.98
        else:
            break
    if len(pos) > settings.max_particles:
        raise ShellUnresolved(f"a {wall_m * 1e3:.3g} mm wall at a spacing of {dx * 1e3:.3g} mm takes {len(pos)} "
                              f"particles, over the budget of {settings.max_particles}")
    if len(pos) == 0:
        raise ShellUnresolved("no lattice point lies within the wall")
    if share >= _SHELL_FILLS:
        raise ShellUnresolved(f"a {wall_m * 1e3:.3g} mm wall fills {share:.0%} of the body: nothing hollow to resolve")
    shell_m3 = float(mesh.volume) * share
    vol = frac * dx**3
    fill_ratio = float(vol.sum() / shell_m3)
    vol = vol * (shell_m3 / vol.sum())
    return pos, vol, nearest_vertex_colors(mesh, pos), dx, fill_ratio, shell_m3


def nearest_vertex_colors(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """RGB uint8 colour of the nearest mesh vertex for each point."""
    vc = np.asarray(mesh.visual.vertex_colors)[:, :3] if mesh.visual.kind == "vertex" else None
    if vc is None or len(vc) != len(mesh.vertices):
        return np.full((len(points), 3), 200, dtype=np.uint8)
    _, idx = cKDTree(mesh.vertices).query(points)
    return vc[idx].astype(np.uint8)
