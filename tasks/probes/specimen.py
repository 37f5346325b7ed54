"""Specimens of the material: the cube and the ball on which L2 measures the material's target bands.

The target bands (effective modulus, recovery, rebound) are material properties: the vocabulary takes them from
material tables. Probed on the object itself they measure the structure as much as the material (a plush dog on four
legs under a plate gives 0.024 x E at 10 % strain; a duck tips over and 'recovers' negatively). So L2 tests the bands
on specimens of the material, at the object's particle spacing, density and ground friction, with the same probes:
compression on a cube (uniaxial, as a foam coupon), the drop on a ball inscribed in that cube (the bounce of a ball:
its rebound ratio is the square of the material's coefficient of restitution, the tabulated quantity). A cube landing
flat on the grid ground is a poor rebound test: at damping 0 a 1.5 MPa rubber cube of 10^3 particles rebounds 0.32,
the ball of the same lattice 0.50. The object's own probes stay as the structural checks (hard gates, sag, stability).
"""

from __future__ import annotations

import numpy as np

from contracts.errors import InputError

SPECIMEN_PARTICLES_PER_AXIS = 10  # 5 grid cells per side; 8 is the least the compression probe measures well


SPECIMEN_SHAPES = ("cube", "ball")


def specimen_particles(spacing_m: float, per_axis: int = SPECIMEN_PARTICLES_PER_AXIS,
                       shape: str = "cube") -> tuple[np.ndarray, np.ndarray]:
    """Rest positions (N, 3) [m] and volumes (N,) [m^3] of a specimen at `spacing_m`: the cube of per_axis^3 lattice
    particles, or the ball of the lattice particles within per_axis/2 spacings of its centre; centred on the z axis and
    resting on z = 0 (lowest particle centres at spacing/2, as L0 places its objects)."""
    if not (np.isfinite(spacing_m) and spacing_m > 0):
        raise InputError(f"specimen particle spacing must be a positive number of metres, got {spacing_m}")
    if per_axis < 8:
        raise InputError(f"a specimen needs at least 8 particles per axis, got {per_axis}")
    if shape not in SPECIMEN_SHAPES:
        raise InputError(f"unknown specimen shape '{shape}'; choose one of {', '.join(SPECIMEN_SHAPES)}")
    s = float(spacing_m)
    c = (np.arange(per_axis) + 0.5) * s - 0.5 * per_axis * s
    x, y, z = np.meshgrid(c, c, c, indexing="ij")
    pos = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    if shape == "ball":
        pos = pos[np.linalg.norm(pos, axis=1) <= 0.5 * per_axis * s]
    pos[:, 2] -= pos[:, 2].min() - 0.5 * s
    return pos, np.full(len(pos), s ** 3)


__all__ = ["SPECIMEN_PARTICLES_PER_AXIS", "SPECIMEN_SHAPES", "specimen_particles"]
