"""Gaussians bound to particles (tasks.geometry.gaussians's binding: each Gaussian follows up to k particles with
weights), deformed by one recorded state after another: what does not change between states (each Gaussian's offsets
from its particles at rest, the weights and indices) is set up once, and a state is one Warp CPU launch
(tasks.render.binding_kernels) instead of numpy's gathers and einsums over (G, k, 3, 3) arrays.

    binding = Binding.of(rest_positions_m, rest_covariances_m2, particle_index, particle_weight, rest_particles_m)
    state = binding.deform(particles_m, deformation_gradients)   # centres, covariances and blended gradients F_g
    normals = binding.normals(rest_normals, state.gradients)     # F_g^-T n, unit (tasks.render.shading's light)

The centres are x_g = sum_j w_j (x_j + F_j (X_g - X_j)), the covariances F_g Σ F_gᵀ with F_g = sum_j w_j F_j
(tasks.render.splats.deform_gaussians is this), all in float64. Lengths in metres.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class DeformedGaussians:
    """The Gaussians in one state: centres [m] (G, 3), covariances [m²] (G, 3, 3) and the blended deformation
    gradient F_g (G, 3, 3) of each (for its normal: Binding.normals)."""

    centres_m: np.ndarray
    covariances_m2: np.ndarray
    gradients: np.ndarray


def blended_gradients(particle_index: np.ndarray, particle_weight: np.ndarray,
                      deformation_gradients: np.ndarray) -> np.ndarray:
    """F_g = sum_j w_j F_j (G, 3, 3) of each Gaussian's particles (numpy: one state, no set-up)."""
    F = np.asarray(deformation_gradients, np.float64)[np.asarray(particle_index)]  # (G, k, 3, 3)
    return np.einsum("gk,gkij->gij", np.asarray(particle_weight, np.float64), F)


def _kernels() -> Any:
    """tasks.render.binding_kernels, on first use."""
    from tasks.render import binding_kernels  # lazy: Warp (1.3 s), only when a video is drawn

    return binding_kernels


def _f64(a: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, np.float64).reshape(shape))


class Binding:
    """Gaussians bound to particles: rest covariances [m²] (G, 3, 3), particle indices and weights (G, k), and the
    offsets X_g - X_j [m] (G, k, 3) of each Gaussian's rest centre from its particles' rest positions."""

    def __init__(self, rest_covariances_m2: np.ndarray, particle_index: np.ndarray, particle_weight: np.ndarray,
                 offsets_m: np.ndarray) -> None:
        g = len(rest_covariances_m2)
        self.rest_covariances_m2 = _f64(rest_covariances_m2, (g, 3, 3))
        idx = np.asarray(particle_index)
        self.particle_index = np.ascontiguousarray(idx[:, None] if idx.ndim == 1 else idx, np.int32)
        k = self.particle_index.shape[1]
        self.particle_weight = _f64(particle_weight, (g, k))
        self.offsets_m = _f64(offsets_m, (g, k, 3))
        self._arrays: dict[str, Any] | None = None  # the same, as Warp arrays (made at the first state)

    @classmethod
    def of(cls, rest_positions_m: np.ndarray, rest_covariances_m2: np.ndarray, particle_index: np.ndarray,
           particle_weight: np.ndarray, rest_particles_m: np.ndarray) -> Binding:
        idx = np.asarray(particle_index)
        offsets = (np.asarray(rest_positions_m, np.float64)[:, None, :]
                   - np.asarray(rest_particles_m, np.float64)[idx])
        return cls(rest_covariances_m2, idx, particle_weight, offsets)

    def __len__(self) -> int:
        return len(self.rest_covariances_m2)

    def _warp(self) -> dict[str, Any]:
        import warp as wp

        if self._arrays is None:
            self._arrays = {
                "index": wp.array(self.particle_index, dtype=int, device="cpu"),
                "weight": wp.array(self.particle_weight, dtype=wp.float64, device="cpu"),
                "offsets": wp.array(self.offsets_m, dtype=wp.vec3d, device="cpu"),
                "rest_cov": wp.array(self.rest_covariances_m2, dtype=wp.mat33d, device="cpu")}
        return self._arrays

    def deform(self, particles_m: np.ndarray, deformation_gradients: np.ndarray) -> DeformedGaussians:
        """The Gaussians in the state of particles at particles_m [m] (N, 3) with gradients F (N, 3, 3)."""
        import warp as wp

        kern = _kernels()

        g = len(self)
        x = _f64(particles_m, (-1, 3))
        F = _f64(deformation_gradients, (-1, 3, 3))
        centres, cov, blended = np.empty((g, 3)), np.empty((g, 3, 3)), np.empty((g, 3, 3))
        if g:
            arrays = self._warp()
            wp.launch(kern.deform, dim=g, device="cpu", inputs=[
                arrays["index"], arrays["weight"], arrays["offsets"],
                wp.array(x, dtype=wp.vec3d, device="cpu", copy=False),
                wp.array(F, dtype=wp.mat33d, device="cpu", copy=False), arrays["rest_cov"],
                wp.array(centres, dtype=wp.vec3d, device="cpu", copy=False),
                wp.array(cov, dtype=wp.mat33d, device="cpu", copy=False),
                wp.array(blended, dtype=wp.mat33d, device="cpu", copy=False)])
        return DeformedGaussians(centres, cov, blended)

    @staticmethod
    def normals(rest_normals: np.ndarray, gradients: np.ndarray) -> np.ndarray:
        """Unit normals (G, 3) F_g^-T n under the blended gradients (DeformedGaussians.gradients); a zero rest normal
        stays zero (an interior blob), and a singular or non-finite F_g leaves the rest normal as it was."""
        import warp as wp

        kern = _kernels()

        n = _f64(rest_normals, (-1, 3))
        out = np.empty_like(n)
        if len(n):
            wp.launch(kern.normals, dim=len(n), device="cpu", inputs=[
                wp.array(_f64(gradients, (-1, 3, 3)), dtype=wp.mat33d, device="cpu", copy=False),
                wp.array(n, dtype=wp.vec3d, device="cpu", copy=False),
                wp.array(out, dtype=wp.vec3d, device="cpu", copy=False)])
        return out
