"""Scenes shared by the MPM tests (SI units)."""

from __future__ import annotations

from contracts.material import Material
from tasks.mpm import box_collider
from tasks.mpm.scene import box_scene

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)


def pressed_and_thrown(spacing_m: float = 0.0025) -> list:
    """A cube pressed by a box moving at 0.2 m/s, and a cube thrown down and sideways onto the ground."""
    a = box_scene((0.0, 0.0, 0.001), (0.04, 0.04, 0.041), spacing_m, MAT, 400.0,
                  colliders=[box_collider((0.02, 0.05, 0.05), position_m=(-0.021, 0.02, 0.03), friction=0.6,
                                          linear_velocity_m_per_s=(0.2, 0.0, 0.0))])
    b = box_scene((0.0, 0.0, 0.002), (0.035, 0.04, 0.042), spacing_m, MAT, 400.0, velocity_m_per_s=(0.5, 0.0, -0.3))
    return [a, b]
