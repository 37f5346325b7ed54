"""L1 physical model: what gives the geometry mass and contact (SI units)."""

from __future__ import annotations

from pydantic import Field

from contracts.base import Model


class PhysicalModel(Model):
    """Frozen after L1: L2 and L3 never edit it."""

    density_kg_per_m3: float = Field(gt=0, description="bulk density rho [kg/m^3]")
    volume_m3: float = Field(gt=0, description="mesh volume = sum of particle volumes [m^3]")
    mass_kg: float = Field(gt=0, description="total mass = rho * volume [kg]")
    particle_count: int = Field(gt=0, description="number of MPM particles [-]")
    particle_spacing_m: float = Field(gt=0, description="lattice spacing of the particles [m]")
    ground_friction: float = Field(ge=0, description="Coulomb friction object-table [-]")
    gripper_friction: float = Field(ge=0, description="Coulomb friction object-finger pad [-]")
    gravity_m_per_s2: tuple[float, float, float] = Field(default=(0.0, 0.0, -9.81), description="gravity [m/s^2]")
    center_of_mass_m: tuple[float, float, float] = Field(description="centre of mass in the asset frame [m]")
    extents_m: tuple[float, float, float] = Field(description="bounding-box extents [m]")
    category: str = Field(description="object category used for the priors")
