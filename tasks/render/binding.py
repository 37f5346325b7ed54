"""Gaussians bound to particles (tasks.geometry.gaussians's binding: each Gaussian follows up to k particles with
weights), deformed by one recorded state after another: what does not change between states (each Gaussian's offsets
from its particles at rest, the weights in float64) is computed once.

    binding = Binding.of(rest_positions_m, rest_covariances_m2, particle_index, particle_weight, rest_particles_m)
    state = binding.deform(particles_m, deformation_gradients)   # centres, covariances and blended gradients F_g

The centres are x_g = sum_j w_j (x_j + F_j (X_g - X_j)), the covariances F_g Σ F_gᵀ with F_g = sum_j w_j F_j
(tasks.render.splats.deform_gaussians is this). Numpy only; lengths in metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DeformedGaussians:
    """The Gaussians in one state: centres [m] (G, 3), covariances [m²] (G, 3, 3) and the blended deformation
    gradient F_g (G, 3, 3) of each (for its normal: tasks.render.shading.normals_under)."""

    centres_m: np.ndarray
    covariances_m2: np.ndarray
    gradients: np.ndarray


def blended_gradients(particle_index: np.ndarray, particle_weight: np.ndarray,
                      deformation_gradients: np.ndarray) -> np.ndarray:
    """F_g = sum_j w_j F_j (G, 3, 3) of each Gaussian's particles."""
    F = np.asarray(deformation_gradients, np.float64)[np.asarray(particle_index)]  # (G, k, 3, 3)
    return np.einsum("gk,gkij->gij", np.asarray(particle_weight, np.float64), F)


@dataclass(frozen=True)
class Binding:
    """Gaussians bound to particles: rest covariances [m²] (G, 3, 3), particle indices and weights (G, k), and the
    offsets X_g - X_j [m] (G, k, 3) of each Gaussian's rest centre from its particles' rest positions."""

    rest_covariances_m2: np.ndarray
    particle_index: np.ndarray
    particle_weight: np.ndarray
    offsets_m: np.ndarray

    @classmethod
    def of(cls, rest_positions_m: np.ndarray, rest_covariances_m2: np.ndarray, particle_index: np.ndarray,
           particle_weight: np.ndarray, rest_particles_m: np.ndarray) -> Binding:
        idx = np.asarray(particle_index)
        offsets = (np.asarray(rest_positions_m, np.float64)[:, None, :]
                   - np.asarray(rest_particles_m, np.float64)[idx])
        return cls(np.asarray(rest_covariances_m2, np.float64), idx, np.asarray(particle_weight, np.float64),
                   offsets)

    def deform(self, particles_m: np.ndarray, deformation_gradients: np.ndarray) -> DeformedGaussians:
        """The Gaussians in the state of particles at particles_m [m] (N, 3) with gradients F (N, 3, 3)."""
        idx, w = self.particle_index, self.particle_weight
        F = np.asarray(deformation_gradients, np.float64)[idx]  # (G, k, 3, 3)
        moved = np.asarray(particles_m, np.float64)[idx] + np.einsum("gkij,gkj->gki", F, self.offsets_m)
        x = np.einsum("gk,gki->gi", w, moved)
        F_g = np.einsum("gk,gkij->gij", w, F)
        cov = F_g @ self.rest_covariances_m2 @ np.swapaxes(F_g, 1, 2)
        return DeformedGaussians(x, cov, F_g)
