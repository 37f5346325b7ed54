"""Kinematic measures of a particle body used by the deformable probes (SI units, numpy only).

Definitions shared by every MPM probe:
  finite               1 if every sampled particle state was finite and the engine reported no NaN/inf, else 0
  in_domain            1 if no particle left the simulation domain (engine health), else 0
  j_min, j_max         smallest / largest det(F) over all particles and all sampled frames [-]
  ground_tunnelling_m  deepest particle below the ground plane over all sampled frames [m] (0 if none)
  engine_health_ok     1 if the engine's health checks (non-finite, domain, J bounds, energy blow-up) all passed
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


def center_of_mass(x: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Mass-weighted mean position [m]."""
    return (x.astype(np.float64) * m[:, None]).sum(axis=0) / m.sum()


def kinetic_energy(v: np.ndarray, m: np.ndarray) -> float:
    """Total kinetic energy 1/2 sum m |v|^2 [J]."""
    v64 = v.astype(np.float64)
    return float(0.5 * np.sum(m * np.einsum("ij,ij->i", v64, v64)))


def det_f(F: np.ndarray) -> np.ndarray:
    """Volume ratio J = det(F) per particle [-]."""
    return np.linalg.det(F.astype(np.float64))


_STRETCH_CHUNK = 1 << 18  # deformation gradients per pass of extreme_stretches (bounds its float64 temporaries)


def extreme_stretches(F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest singular value of each deformation gradient (..., 3, 3), in float64.

    The square roots of the extreme eigenvalues of the symmetric C = F^T F by the trigonometric closed form (Smith
    1961), written out per component: ~15x faster than a batched SVD and ~10x faster than the same form through
    einsum and det on (N, 3, 3) stacks. Absolute error below 1e-12, and ~1e-9 where two singular values coincide
    (the arccos there loses half the digits)."""
    F = np.asarray(F)
    shape = F.shape[:-2]
    flat = F.reshape(-1, 9)
    lo, hi = np.empty(len(flat)), np.empty(len(flat))
    for a in range(0, len(flat), _STRETCH_CHUNK):
        f = flat[a:a + _STRETCH_CHUNK].astype(np.float64).T  # f[3 i + j] = F_ij
        c00 = f[0] * f[0] + f[3] * f[3] + f[6] * f[6]
        c11 = f[1] * f[1] + f[4] * f[4] + f[7] * f[7]
        c22 = f[2] * f[2] + f[5] * f[5] + f[8] * f[8]
        c01 = f[0] * f[1] + f[3] * f[4] + f[6] * f[7]
        c02 = f[0] * f[2] + f[3] * f[5] + f[6] * f[8]
        c12 = f[1] * f[2] + f[4] * f[5] + f[7] * f[8]
        q = (c00 + c11 + c22) / 3.0
        d0, d1, d2 = c00 - q, c11 - q, c22 - q
        p = np.sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (c01 * c01 + c02 * c02 + c12 * c12)) / 6.0)
        round_ = p > 1e-300  # C = q I (p = 0): every eigenvalue is q
        safe = np.where(round_, p, 1.0)
        det_b = (d0 * d1 * d2 + 2.0 * c01 * c12 * c02 - d0 * c12 * c12 - d1 * c02 * c02 - d2 * c01 * c01) / safe ** 3
        phi = np.arccos(np.clip(det_b / 2.0, -1.0, 1.0)) / 3.0
        e_max = np.where(round_, q + 2.0 * p * np.cos(phi), q)
        e_min = np.where(round_, q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0), q)
        lo[a:a + len(q)] = np.sqrt(np.maximum(e_min, 0.0))
        hi[a:a + len(q)] = np.sqrt(np.maximum(e_max, 0.0))
    return lo.reshape(shape), hi.reshape(shape)


def compressive_strain(F: np.ndarray) -> np.ndarray:
    """Largest compressive principal (engineering) strain per particle: max(0, 1 - smallest singular value of F)."""
    return np.maximum(0.0, 1.0 - extreme_stretches(F)[0])


def top_bottom_layers(x0: np.ndarray, spacing_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Masks of the top and bottom particle layers of a rest pose (within 0.75 spacing of the extreme z)."""
    z = x0[:, 2]
    return z > z.max() - 0.75 * spacing_m, z < z.min() + 0.75 * spacing_m


def layer_height(x: np.ndarray, top: np.ndarray, bottom: np.ndarray) -> float:
    """Mean z of the top layer minus mean z of the bottom layer [m]."""
    return float(x[top, 2].mean() - x[bottom, 2].mean())


def cross_section_area(x0: np.ndarray, volumes_m3: np.ndarray, spacing_m: float, z_m: float) -> float:
    """Horizontal cross-section [m^2] at height z: volume of the particles in a slab of two layers / its thickness."""
    slab = np.abs(x0[:, 2] - z_m) < spacing_m
    thickness = 2.0 * spacing_m
    if not np.any(slab):
        return 0.0
    return float(volumes_m3[slab].sum() / thickness)


@dataclass
class GateTracker:
    """Accumulates the gate measures (finite, J range, ground tunnelling) over sampled frames."""

    ground_z_m: float = 0.0
    finite: bool = True
    j_min: float = math.inf
    j_max: float = -math.inf
    tunnelling_m: float = 0.0
    frames: int = 0
    issues: list[str] = field(default_factory=list)

    def sample(self, x: np.ndarray, F: np.ndarray, on_ground: bool = True) -> None:
        """Update with one frame of positions [m] and deformation gradients."""
        self.frames += 1
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(F))):
            self.finite = False
            return
        J = det_f(F)
        self.j_min = min(self.j_min, float(J.min()))
        self.j_max = max(self.j_max, float(J.max()))
        if on_ground:
            self.tunnelling_m = max(self.tunnelling_m, float(self.ground_z_m - x[:, 2].min()))

    def metrics(self, health_ok: bool, checks: list[str]) -> dict[str, float]:
        """Gate metrics of the sampled frames combined with the engine's health checks (by check name)."""
        finite = self.finite and "nonfinite" not in checks
        j_min = self.j_min if math.isfinite(self.j_min) else 0.0
        j_max = self.j_max if math.isfinite(self.j_max) else 1.0e9
        if not finite:  # an unknown state: both J gates fail
            j_min, j_max = min(j_min, 0.0), max(j_max, 1.0e9)
        return {
            "finite": 1.0 if finite else 0.0,
            "in_domain": 0.0 if "left_domain" in checks else 1.0,
            "j_min": j_min,
            "j_max": j_max,
            "ground_tunnelling_m": max(0.0, self.tunnelling_m),
            "engine_health_ok": 1.0 if health_ok else 0.0,
        }


__all__ = [
    "GateTracker", "center_of_mass", "compressive_strain", "cross_section_area", "det_f", "extreme_stretches",
    "kinetic_energy", "layer_height", "top_bottom_layers",
]
