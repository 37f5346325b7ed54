"""The object as the robot trial sees it: particles at the trial's lattice, its mass, surface samples and Gaussians.

Resampling the L0 volume at a finer lattice is a NUMERICAL choice of L3 (the pads build grip force only on a grid
of <= ~5 mm): the physical model (density, mass, friction) and the material stay those of L1 / L2. The particle
volumes are the mesh volume shared equally, so sum V_i = mesh volume and m = rho V as in L1 (a hollow object's shell
keeps L0's particles and volumes, summing to the shell's volume). The L0 Gaussians are
re-bound to the trial particles (same kernel as L0) so replay can drive them from the recorded particle states.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from contracts.errors import InputError
from tasks.geometry.gaussians import bind_to_particles, rest_covariances
from tasks.geometry.particles import inside_lattice
from tasks.mpm.scene import box_particles


@dataclass(frozen=True)
class TrialBody:
    """Rest state of the object in the asset frame (z up, on z = 0), SI units."""

    particles_m: np.ndarray          # (N, 3)
    volumes_m3: np.ndarray           # (N,)
    spacing_m: float                 # lattice spacing of the trial particles [m]
    source_spacing_m: float          # L0 lattice spacing [m] (recorded: the resampling is a numerical choice)
    surface_points_m: np.ndarray     # (S, 3) for grasp selection
    surface_normals: np.ndarray      # (S, 3) outward unit normals
    height_m: float                  # top of the object [m]
    gaussians: dict[str, np.ndarray]  # positions_m, covariances_m2, colors, particle_index, particle_weight

    @property
    def volume_m3(self) -> float:
        """Total volume [m^3]."""
        return float(np.sum(self.volumes_m3))


def auto_trial_spacing(extents_m: np.ndarray, quality: str = "draft", pad_face_m: float | None = None) -> float:
    """Trial particle spacing [m]: a grid (dx = 2 x spacing) of at most half the gripper pad's face (the Franka Hand's
    17 mm: 4 mm; a larger pad allows pad_face / 4), so the pad covers >= 2 x 2 nodes, and >= 12 particles across the
    smallest extent; standard quality halves the cap."""
    cap = max(0.004, (pad_face_m or 0.0) / 4.0)
    cap = cap if quality == "draft" else cap / 2.0
    return float(min(cap, float(np.min(extents_m)) / 12.0))


def lattice_inside(mesh: trimesh.Trimesh, spacing_m: float) -> np.ndarray:
    """Lattice points [m] at ``spacing_m`` inside a watertight mesh (winding-number raster: memory grows with the
    lattice, not with lattice x triangles as trimesh's ray test does; 1e5 points in a 50k-face mesh stay small)."""
    lo, hi = mesh.bounds
    n = np.maximum(np.ceil((hi - lo) / spacing_m).astype(int), 1)
    origin = lo + 0.5 * ((hi - lo) - (n - 1) * spacing_m)  # the lattice centred on the bounding box
    occupied = inside_lattice(mesh, origin, spacing_m, tuple(int(v) for v in n))
    return origin + np.argwhere(occupied) * spacing_m


def trial_body(mesh: trimesh.Trimesh, l0_particles_m: np.ndarray, l0_spacing_m: float, gaussians: dict[str, np.ndarray],
               spacing_m: float | None = None, surface_samples: int = 2000, max_gaussians: int = 100_000,
               seed: int = 0, shell_volumes_m3: np.ndarray | None = None) -> TrialBody:
    """The trial's object: the L0 particles, or the mesh volume resampled at ``spacing_m`` when that differs. A hollow
    object's shell (shell_volumes_m3: L0's particle volumes, summing to the shell's) is always L0's particles and
    volumes: its lattice already resolves the wall (at most half the wall apart), which a coarser trial lattice would
    not, and a finer one is not needed for the pads."""
    if not mesh.is_watertight:
        raise InputError("the trial body needs a watertight mesh")
    if shell_volumes_m3 is not None:
        pts, spacing = np.asarray(l0_particles_m, dtype=np.float64), float(l0_spacing_m)
        volumes = np.asarray(shell_volumes_m3, dtype=np.float64)
    elif spacing_m is None or abs(spacing_m - l0_spacing_m) <= 0.01 * l0_spacing_m:
        pts, spacing = np.asarray(l0_particles_m, dtype=np.float64), float(l0_spacing_m)
    else:
        pts, spacing = lattice_inside(mesh, spacing_m), float(spacing_m)
        if len(pts) < 8:
            raise InputError(f"a {spacing_m * 1000:.1f} mm lattice puts only {len(pts)} particles inside the mesh")
    if shell_volumes_m3 is None:
        volumes = np.full(len(pts), float(mesh.volume) / len(pts))
    surf, faces = trimesh.sample.sample_surface_even(mesh, surface_samples, seed=seed)
    normals = np.asarray(mesh.face_normals[faces], dtype=np.float64)
    g_pos = np.asarray(gaussians["positions_m"], dtype=np.float64)
    keep = np.arange(len(g_pos))
    if len(keep) > max_gaussians:
        keep = np.sort(np.random.default_rng(seed).choice(len(g_pos), max_gaussians, replace=False))
    cov = rest_covariances(np.asarray(gaussians["scales_m"])[keep], np.asarray(gaussians["rotations_wxyz"])[keep])
    idx, w = bind_to_particles(g_pos[keep], pts, spacing)
    g = {"positions_m": g_pos[keep], "covariances_m2": cov,
         "colors": np.asarray(gaussians["colors"], dtype=np.float32)[keep],
         "particle_index": idx, "particle_weight": w}
    return TrialBody(pts, volumes, spacing, float(l0_spacing_m), np.asarray(surf, dtype=np.float64), normals,
                     float(mesh.bounds[1][2]), g)


def box_body(edge_m: float, spacing_m: float, gaussians_per_face: int = 200, seed: int = 0) -> TrialBody:
    """A cube resting on the table (tests, benchmarks): particles, surface samples and coloured surface Gaussians."""
    mesh = trimesh.creation.box((edge_m,) * 3)
    mesh.apply_translation((0.0, 0.0, edge_m / 2.0))
    rng = np.random.default_rng(seed)
    pts, faces = trimesh.sample.sample_surface_even(mesh, 6 * gaussians_per_face, seed=seed)
    s = float(np.sqrt(mesh.area / len(pts) / np.pi))
    colors = np.clip(0.35 + 0.5 * (pts - pts.min(0)) / edge_m + 0.05 * rng.standard_normal(pts.shape), 0, 1)
    gaussians = {"positions_m": pts, "scales_m": np.full((len(pts), 3), s), "colors": colors,
                 "rotations_wxyz": np.tile([1.0, 0.0, 0.0, 0.0], (len(pts), 1))}
    lattice, _ = box_particles((-edge_m / 2, -edge_m / 2, 0.0), (edge_m / 2, edge_m / 2, edge_m), spacing_m)
    return trial_body(mesh, lattice, spacing_m, gaussians, None, seed=seed)
