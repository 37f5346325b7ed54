"""Solid particle spheres for the MPM impact tests (the material loss, the balls' rule drops)."""

from __future__ import annotations

import numpy as np

from contracts.physical import PhysicalModel
from tasks.mpm.scene import box_particles


def sphere_particles(radius_m: float, spacing_m: float, lift_m: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Particle positions and volumes of a solid sphere whose bottom is lift_m above z = 0."""
    r = radius_m
    pos, vol = box_particles((-r, -r, -r), (r, r, r), spacing_m)
    keep = np.linalg.norm(pos, axis=1) <= r
    return pos[keep] + np.array([0.0, 0.0, r + lift_m]), vol[keep]


def resting_sphere(radius_m: float, spacing_m: float, density_kg_per_m3: float
                   ) -> tuple[np.ndarray, np.ndarray, PhysicalModel]:
    """A solid sphere resting on z = 0 and its physical model (a ball)."""
    r = radius_m
    pos, vol = sphere_particles(r, spacing_m)
    phys = PhysicalModel(density_kg_per_m3=density_kg_per_m3, volume_m3=float(vol.sum()),
                         mass_kg=float(vol.sum() * density_kg_per_m3), particle_count=len(pos),
                         particle_spacing_m=spacing_m, ground_friction=0.5, gripper_friction=0.8,
                         center_of_mass_m=(0.0, 0.0, r), extents_m=(2 * r, 2 * r, 2 * r), category="ball")
    return pos, vol, phys
