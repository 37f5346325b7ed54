"""Light on the Gaussians: each surface disc's colour (the mesh's part or photo colour) lit by a key light and a fill
from the camera's side, with its normal carried by the deformation (n' ~ F^-T n), so a video shows the object's
shape (a shell's curve, a head's eyes) and not a flat cut-out.

    from tasks.render.shading import lit_colors

    normals = binding.normals(rest_normals, state.gradients)   # (G, 3) F_g^-T n, 0 for interior blobs (binding.py)
    colors = lit_colors(albedo, normals, cam)                   # (G, 3) in 0..1

Interior blobs (normal 0) take the mean light of a surface facing the camera. Numpy only; lengths in metres.
"""

from __future__ import annotations

import numpy as np

from tasks.render.camera import Camera

AMBIENT = 0.42  # light everywhere
KEY = 0.55  # key light: above, to the camera's left, a little towards the camera
FILL = 0.18  # fill light from the camera
# towards the key light in the camera frame (right, down, forward): up, to the left, in front of the object
TOWARD_KEY_IN_CAMERA = np.array([-0.45, -0.80, -0.40])
INTERIOR_LIGHT = AMBIENT + 0.5 * KEY + FILL


def lit_colors(albedo_rgb: np.ndarray, normals: np.ndarray, cam: Camera) -> np.ndarray:
    """Colours (G, 3) in 0..1: albedo x (ambient + key (n . l) + fill (n . v)), both terms clipped at 0; interior
    blobs (zero normal) get INTERIOR_LIGHT."""
    rot, _, _ = cam.frame()
    key = TOWARD_KEY_IN_CAMERA @ rot  # camera frame -> world
    key = key / np.linalg.norm(key)
    toward_eye = -rot[2]
    n = np.asarray(normals, np.float64)
    light = AMBIENT + KEY * np.clip(n @ key, 0.0, None) + FILL * np.clip(n @ toward_eye, 0.0, None)
    light = np.where(np.linalg.norm(n, axis=1) > 0.5, light, INTERIOR_LIGHT)
    return np.clip(np.asarray(albedo_rgb, np.float64)[:, :3] * light[:, None], 0.0, 1.0)


def normals_from_covariances(positions_m: np.ndarray, covariances_m2: np.ndarray, particle_index: np.ndarray,
                             particle_weight: np.ndarray, rest_particles_m: np.ndarray,
                             flat_ratio: float = 0.2) -> np.ndarray:
    """Rest normals (G, 3) of Gaussians recorded without them (a trial's): a flat disc's (smallest over middle
    variance below flat_ratio²) is its thinnest axis, turned away from the particles it is bound to (they lie
    inside); any other Gaussian takes its nearest disc's (none: away from the body's centre)."""
    from scipy.spatial import cKDTree

    pos = np.asarray(positions_m, np.float64)
    if not len(pos):
        return np.zeros((0, 3))
    lam, vec = np.linalg.eigh(np.asarray(covariances_m2, np.float64))  # ascending eigenvalues
    n = vec[:, :, 0]
    inside = np.einsum("gk,gki->gi", np.asarray(particle_weight, np.float64),
                       np.asarray(rest_particles_m, np.float64)[np.asarray(particle_index)])
    outward = pos - inside
    n = np.where((np.einsum("gi,gi->g", n, outward) < 0.0)[:, None], -n, n)
    flat = lam[:, 0] < flat_ratio**2 * np.maximum(lam[:, 1], 1e-30)
    if np.any(flat) and not np.all(flat):
        _, near = cKDTree(pos[flat]).query(pos[~flat])
        n[~flat] = n[flat][near]
    elif not np.any(flat):
        away = pos - pos.mean(axis=0)
        n = away / np.maximum(np.linalg.norm(away, axis=1, keepdims=True), 1e-12)
    return n
