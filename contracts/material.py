"""Homogeneous isotropic neo-Hookean material (SI units)."""

from __future__ import annotations

import math

from pydantic import Field, field_validator

from contracts.base import Model


class Material(Model):
    """Neo-Hookean material; the density lives in the PhysicalModel (L1 owns mass)."""

    youngs_modulus_pa: float = Field(gt=0, description="Young's modulus E [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-], 0 <= nu < 0.5")
    damping_rate_per_s: float = Field(
        default=0.0, ge=0.0, description="velocity damping rate [1/s], dt-independent: v *= exp(-rate*dt)"
    )

    @field_validator("youngs_modulus_pa", "poisson_ratio", "damping_rate_per_s")
    @classmethod
    def _finite(cls, v: float) -> float:
        if not math.isfinite(v):
            raise ValueError("must be a finite number")
        return v

    @property
    def mu_pa(self) -> float:
        """Lame shear modulus mu = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def lambda_pa(self) -> float:
        """Lame first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa]."""
        e, nu = self.youngs_modulus_pa, self.poisson_ratio
        return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))

    def p_wave_speed_m_per_s(self, density_kg_per_m3: float) -> float:
        """Dilatational wave speed c_p = sqrt((lambda + 2 mu) / rho) [m/s]."""
        return math.sqrt((self.lambda_pa + 2.0 * self.mu_pa) / density_kg_per_m3)
