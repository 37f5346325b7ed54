"""A specimen of the material: the cube on which L2 measures the material's target bands.

The target bands (effective modulus, recovery, rebound) are material properties: the vocabulary takes them from
material tables. Probed on the object itself they measure the structure as much as the material (a plush dog on four
legs under a plate gives 0.024 x E at 10 % strain; a duck tips over and 'recovers' negatively). So L2 tests the bands
on a cube of the material, at the object's particle spacing, density and ground friction, with the same compression
and drop probes; the object's own probes stay as the structural checks (hard gates, sag, stability).
"""

from __future__ import annotations

import numpy as np

from contracts.errors import InputError

SPECIMEN_PARTICLES_PER_AXIS = 10  # 5 grid cells per side; 8 is the least the compression probe measures well


def specimen_particles(spacing_m: float, per_axis: int = SPECIMEN_PARTICLES_PER_AXIS) -> tuple[np.ndarray, np.ndarray]:
    """Rest positions (N, 3) [m] and volumes (N,) [m^3] of a cube of per_axis^3 particles at `spacing_m`, centred on
    the z axis and resting on z = 0 (lowest particle centres at spacing/2, as L0 places its objects)."""
    if not (np.isfinite(spacing_m) and spacing_m > 0):
        raise InputError(f"specimen particle spacing must be a positive number of metres, got {spacing_m}")
    if per_axis < 8:
        raise InputError(f"a specimen needs at least 8 particles per axis, got {per_axis}")
    s = float(spacing_m)
    c = (np.arange(per_axis) + 0.5) * s
    x, y, z = np.meshgrid(c - 0.5 * per_axis * s, c - 0.5 * per_axis * s, c, indexing="ij")
    pos = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return pos, np.full(len(pos), s ** 3)


__all__ = ["SPECIMEN_PARTICLES_PER_AXIS", "specimen_particles"]
