"""Build the L1 PhysicalModel: m_i = rho V_i, sum V_i = mesh volume, zero initial velocity, gravity, friction."""

from __future__ import annotations

import numpy as np

from contracts.errors import InputError
from contracts.physical import PhysicalModel

# What a robot (or one person) can lift, from about the lightest object L0 admits (1 cm x 5 mm x 5 mm of the lightest
# foam, 12 kg/m^3: ~3 mg; a foam earplug is ~0.2 g) to a full sack: 25 kg (a feed or flood sandbag; the NIOSH lifting
# equation's load constant is 23 kg, industrial cobots carry 20-30 kg). Outside this, L1 fails its gate; inside it,
# plausibility is the density's (within the material's range). The floor was 2 g, which refused the catalogue's own
# foam earplug whatever its density; the ceiling was 5 kg, which planned a 15 kg flood sandbag and a 9 kg bean bag
# chair at 5 kg and refused a stated '25 kg bag of chicken feed' at L1.
MASS_RANGE_KG: tuple[float, float] = (1.0e-6, 25.0)
DENSITY_BAND_SLACK = 1.5  # a density may sit this factor outside the material's prior range and still be plausible


def particle_masses(volumes_m3: np.ndarray, density_kg_per_m3: float) -> np.ndarray:
    """Per-particle mass m_i = rho V_i [kg] (homogeneous material)."""
    if not np.isfinite(density_kg_per_m3) or density_kg_per_m3 <= 0:
        raise InputError(f"density must be a positive finite number of kg/m^3, got {density_kg_per_m3}")
    return (np.asarray(volumes_m3, dtype=np.float64) * float(density_kg_per_m3)).astype(np.float32)


def mass_plausible(mass_kg: float, density_kg_per_m3: float, density_range: tuple[float, float] | None) -> bool:
    """Mass within the everyday band and density within the material's prior range (with slack)."""
    lo, hi = MASS_RANGE_KG
    if not lo <= mass_kg <= hi:
        return False
    if density_range is None:
        return True
    dlo, dhi = density_range
    return dlo / DENSITY_BAND_SLACK <= density_kg_per_m3 <= dhi * DENSITY_BAND_SLACK


def build_physical_model(
    positions_m: np.ndarray,
    volumes_m3: np.ndarray,
    spacing_m: float,
    density_kg_per_m3: float,
    ground_friction: float,
    gripper_friction: float,
    category: str,
    gravity_m_per_s2: tuple[float, float, float] = (0.0, 0.0, -9.81),
) -> PhysicalModel:
    """The frozen L1 model of an L0 particle set (asset frame: z up, resting on z = 0)."""
    pos = np.asarray(positions_m, dtype=np.float64)
    vol = np.asarray(volumes_m3, dtype=np.float64)
    if pos.ndim != 2 or pos.shape[1] != 3 or len(pos) != len(vol) or len(vol) == 0:
        raise InputError(f"particles must be (N, 3) positions with N volumes, got {pos.shape} and {vol.shape}")
    if not (np.all(np.isfinite(pos)) and np.all(vol > 0)):
        raise InputError("particle positions must be finite and volumes positive")
    masses = particle_masses(vol, density_kg_per_m3).astype(np.float64)
    total_volume = float(vol.sum())
    com = (pos * masses[:, None]).sum(axis=0) / masses.sum()
    extents = pos.max(axis=0) - pos.min(axis=0) + spacing_m  # particles sit half a spacing inside each face
    return PhysicalModel(
        density_kg_per_m3=float(density_kg_per_m3),
        volume_m3=total_volume,
        mass_kg=float(masses.sum()),
        particle_count=len(vol),
        particle_spacing_m=float(spacing_m),
        ground_friction=float(ground_friction),
        gripper_friction=float(gripper_friction),
        gravity_m_per_s2=gravity_m_per_s2,
        center_of_mass_m=tuple(float(c) for c in com),
        extents_m=tuple(float(e) for e in extents),
        category=category,
    )
