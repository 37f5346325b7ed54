"""Gaussian splats from surface and interior samples, bound to particles so they follow x_p and F_p (the deformation:
tasks.render.splats.deform_gaussians); 3DGS .ply I/O."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
from plyfile import PlyData, PlyElement
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

SH_C0 = 0.28209479177387814
K_NEAREST = 4
# The surface discs are dense and small for the particle spacing: their in-plane sigma is at most this fraction of
# it (a 25 cm turtle at draft, 12.5 mm spacing: sigma <= 1.2 mm, ~17k surface discs; standard, 6 mm: ~4x as many),
# so a 720p video shows the object's parts and edges instead of a blur of 4 mm blobs.
SURFACE_SIGMA_PER_SPACING = 0.1
INTERIOR_SCALE_PER_SPACING = 0.35  # interior blobs (seen only where the surface opens), sigma / spacing


class GaussianSet(dict):
    """Arrays of a Gaussian set (rest state): positions_m, scales_m, rotations_wxyz, colors (float RGB 0..1),
    opacities, normals, is_surface, and the particle binding: particle_index (G, k) int32, particle_weight (G, k)."""


def dense_count(area_m2: float, spacing_m: float, surface_fraction: float) -> int:
    """Gaussians (surface and interior) whose surface discs have an in-plane sigma of SURFACE_SIGMA_PER_SPACING x the
    particle spacing over a surface of area_m2."""
    sigma = SURFACE_SIGMA_PER_SPACING * spacing_m
    n_surf = area_m2 / (np.pi * sigma**2)
    return int(np.ceil(n_surf / max(surface_fraction, 1e-3)))


def make_gaussians(
    mesh: trimesh.Trimesh, particles_m: np.ndarray, spacing_m: float, count: int, seed: int,
    surface_fraction: float = 0.75, max_count: int = 400_000, dense: bool = True,
) -> GaussianSet:
    """Sample at least `count` Gaussians (surface discs + interior blobs; with dense, more where the particle spacing
    asks for denser discs, see dense_count, at most max_count) with colours from the mesh's vertex colours (its
    parts', a photo's), bound to their K nearest particles."""
    rng = np.random.default_rng(seed)
    if dense:
        count = int(min(max(count, dense_count(float(mesh.area), spacing_m, surface_fraction)), max(count, max_count)))
    n_surf = max(1, int(round(count * surface_fraction)))
    n_int = max(0, count - n_surf)
    # blue-noise samples (no two closer than about the mean spacing): fewer clumps and holes than independent ones,
    # topped up with independent samples where the rejection keeps fewer than asked
    pts, fidx = trimesh.sample.sample_surface_even(mesh, n_surf, seed=seed)
    if len(pts) < n_surf:
        more, more_f = trimesh.sample.sample_surface(mesh, n_surf - len(pts), seed=seed + 1)
        pts, fidx = np.concatenate([pts, more]), np.concatenate([fidx, more_f])
    bary = trimesh.triangles.points_to_barycentric(mesh.triangles[fidx], pts)
    # smooth normals (the vertex normals across the face: a marching-cubes mesh's face normals would light as
    # blotches), but the face's own at a corner whose vertex normal turns more than ~30 degrees from it (a box's edge)
    face_n = np.asarray(mesh.face_normals)[fidx]
    corner_n = np.asarray(mesh.vertex_normals)[mesh.faces[fidx]]  # (n, 3, 3)
    smooth = np.einsum("ijk,ik->ij", corner_n, face_n) > 0.85
    corner_n = np.where(smooth[:, :, None], corner_n, face_n[:, None, :])
    normals = np.einsum("ij,ijk->ik", np.clip(bary, 0, 1), corner_n)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(length > 1e-9, normals / np.maximum(length, 1e-9), face_n)
    vc = np.asarray(mesh.visual.vertex_colors, dtype=np.float64)[:, :3] / 255.0
    surf_rgb = np.einsum("ij,ijk->ik", np.clip(bary, 0, 1), vc[mesh.faces[fidx]])
    sigma_t = float(np.sqrt(mesh.area / n_surf / np.pi))
    surf_scales = np.tile([sigma_t, sigma_t, 0.1 * sigma_t], (n_surf, 1))
    surf_rot = _frame_quaternions(normals)
    pick = rng.integers(0, len(particles_m), n_int)
    int_pts = particles_m[pick] + rng.uniform(-0.25, 0.25, (n_int, 3)) * spacing_m
    surface = cKDTree(pts)  # (built once: the surface discs are queried twice)
    depth, near = surface.query(int_pts)
    outside = np.einsum("ij,ij->i", int_pts - pts[near], normals[near]) > 0.0
    int_pts[outside] = particles_m[pick][outside]  # a jitter that left the surface: back on its particle
    depth[outside], near[outside] = surface.query(int_pts[outside])
    _, vi = cKDTree(mesh.vertices).query(int_pts)
    int_rgb = vc[vi]
    # an interior blob stays inside: its 3 sigma no deeper than it lies under the surface (no halo round the object);
    # its normal is the nearest surface disc's (lit like the surface over it, where a stretched surface opens)
    int_sigma = np.clip(depth / 3.0, 0.05 * spacing_m, INTERIOR_SCALE_PER_SPACING * spacing_m)
    int_normals = normals[near]
    positions = np.concatenate([pts, int_pts])
    g = GaussianSet(
        positions_m=positions.astype(np.float32),
        scales_m=np.concatenate([surf_scales, np.repeat(int_sigma[:, None], 3, axis=1)]).astype(np.float32),
        rotations_wxyz=np.concatenate([surf_rot, np.tile([1.0, 0, 0, 0], (n_int, 1))]).astype(np.float32),
        colors=np.concatenate([surf_rgb, int_rgb]).clip(0, 1).astype(np.float32),
        opacities=np.full(len(positions), 0.95, np.float32),
        normals=np.concatenate([normals, int_normals]).astype(np.float32),
        is_surface=np.concatenate([np.ones(n_surf, bool), np.zeros(n_int, bool)]),
    )
    idx, w = bind_to_particles(positions, particles_m, spacing_m)
    g["particle_index"], g["particle_weight"] = idx, w
    return g


def _frame_quaternions(normals: np.ndarray) -> np.ndarray:
    """Quaternions (w, x, y, z) of frames whose local z axis is the normal."""
    n = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    helper = np.where(np.abs(n[:, [0]]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(helper, n)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(n, t1)
    q = Rotation.from_matrix(np.stack([t1, t2, n], axis=2)).as_quat()  # x, y, z, w
    return np.concatenate([q[:, 3:], q[:, :3]], axis=1)


def bind_to_particles(points: np.ndarray, particles_m: np.ndarray, spacing_m: float, k: int = K_NEAREST) -> tuple[np.ndarray, np.ndarray]:
    """Indices (G, k) of the k nearest particles and normalised Gaussian-kernel weights (G, k)."""
    k = min(k, len(particles_m))
    d, idx = cKDTree(particles_m).query(points, k=k)
    d, idx = d.reshape(len(points), k), idx.reshape(len(points), k)
    w = np.exp(-((d / spacing_m) ** 2))
    w = np.where(w.sum(axis=1, keepdims=True) > 1e-30, w, np.exp(-(d - d[:, :1]) / spacing_m))
    w /= w.sum(axis=1, keepdims=True)
    return idx.astype(np.int32), w.astype(np.float32)


def rest_covariances(scales_m: np.ndarray, rotations_wxyz: np.ndarray) -> np.ndarray:
    """Covariance matrices (G, 3, 3) = R diag(s^2) R^T."""
    q = np.asarray(rotations_wxyz, dtype=np.float64)
    R = Rotation.from_quat(np.concatenate([q[:, 1:], q[:, :1]], axis=1)).as_matrix()
    s2 = np.asarray(scales_m, dtype=np.float64) ** 2
    return np.einsum("gij,gj,gkj->gik", R, s2, R)


def write_3dgs_ply(g: GaussianSet, path: Path) -> None:
    """Standard 3D Gaussian splat .ply (binary little endian, SH degree 0, logit opacity, log scales, wxyz quaternion)."""
    n = len(g["positions_m"])
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity",
             "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    arr = np.empty(n, dtype=[(k, "<f4") for k in names])
    p, nr = g["positions_m"], g["normals"]
    dc = (np.asarray(g["colors"], np.float64) - 0.5) / SH_C0
    op = np.clip(np.asarray(g["opacities"], np.float64), 1e-6, 1 - 1e-6)
    ls = np.log(np.maximum(np.asarray(g["scales_m"], np.float64), 1e-12))
    q = np.asarray(g["rotations_wxyz"], np.float64)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    cols = [p[:, 0], p[:, 1], p[:, 2], nr[:, 0], nr[:, 1], nr[:, 2], dc[:, 0], dc[:, 1], dc[:, 2],
            np.log(op / (1 - op)), ls[:, 0], ls[:, 1], ls[:, 2], q[:, 0], q[:, 1], q[:, 2], q[:, 3]]
    for k, c in zip(names, cols):
        arr[k] = c
    PlyData([PlyElement.describe(arr, "vertex")], text=False, byte_order="<").write(str(path))


def read_3dgs_ply(path: Path) -> GaussianSet:
    """Read a 3DGS .ply back into positions, scales, rotations, colours and opacities."""
    v = PlyData.read(str(path))["vertex"].data
    col = lambda *ks: np.stack([np.asarray(v[k], np.float64) for k in ks], axis=1)  # noqa: E731
    return GaussianSet(
        positions_m=col("x", "y", "z"), normals=col("nx", "ny", "nz"),
        colors=col("f_dc_0", "f_dc_1", "f_dc_2") * SH_C0 + 0.5,
        opacities=1.0 / (1.0 + np.exp(-np.asarray(v["opacity"], np.float64))),
        scales_m=np.exp(col("scale_0", "scale_1", "scale_2")), rotations_wxyz=col("rot_0", "rot_1", "rot_2", "rot_3"),
    )
