"""Homogeneous isotropic neo-Hookean material (SI units)."""

from __future__ import annotations

import math

from pydantic import Field, field_validator, model_serializer

from contracts.base import Model


#: explicit Kelvin-Voigt viscosity in MLS-MPM (quadratic B-splines, 2 particles per cell per axis) is stable for
#: dt <= k rho dx^2 / eta: a block of random velocities stayed bounded at k = 0.35 and blew up at k = 0.4 (session 28,
#: tests/mpm/test_viscosity.py); the engine takes k = 0.15, a safety factor of ~2.5 (the elastic CFL step binds too).
VISCOUS_DT_FACTOR = 0.15


class Material(Model):
    """Neo-Hookean material with an optional Kelvin-Voigt viscosity (the loss in the material: hysteresis); the
    density lives in the PhysicalModel (L1 owns mass)."""

    youngs_modulus_pa: float = Field(gt=0, description="Young's modulus E [Pa]")
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-], 0 <= nu < 0.5")
    damping_rate_per_s: float = Field(
        default=0.0, ge=0.0, description="velocity damping rate [1/s], dt-independent: v *= exp(-rate*dt)"
    )

    viscosity_pa_s: float = Field(
        default=0.0, ge=0.0,
        description="Kelvin-Voigt viscosity eta [Pa s]: Cauchy stress eta (L + L^T) added to the elastic one, L the "
                    "velocity gradient; a loss in the material (impacts, vibration), none in rigid motion",
    )

    gas_modulus_pa: float = Field(
        default=0.0, ge=0.0,
        description="the modulus a pressurised ball's gas adds to its shell's wall [Pa]: the object is simulated at "
                    "youngs_modulus_pa + gas_modulus_pa (wall_modulus_pa), a specimen of the material at "
                    "youngs_modulus_pa; a homogenised equivalent of the inflation, not a gas (tasks.realworld.inflation)",
    )

    @field_validator("youngs_modulus_pa", "poisson_ratio", "damping_rate_per_s", "viscosity_pa_s", "gas_modulus_pa")
    @classmethod
    def _finite(cls, v: float) -> float:
        if not math.isfinite(v):
            raise ValueError("must be a finite number")
        return v

    @model_serializer(mode="wrap")
    def _omit_zero_viscosity(self, handler):
        """viscosity_pa_s = 0 and gas_modulus_pa = 0 (the defaults, the engine before they existed) are left out of the
        dump, so the cache keys of materials from before the fields existed still name the same results; any other
        value is in it."""
        out = handler(self)
        if isinstance(out, dict):
            for key in ("viscosity_pa_s", "gas_modulus_pa"):  # gas_modulus_pa = 0: every material but a gas shell's
                if out.get(key) == 0.0:
                    out.pop(key)
        return out

    @property
    def wall_modulus_pa(self) -> float:
        """The modulus the object is simulated at: E, plus a pressurised shell's gas_modulus_pa [Pa]."""
        return self.youngs_modulus_pa + self.gas_modulus_pa

    def specimen(self) -> Material:
        """The material itself, without a shell's gas (what a specimen cube or ball of it is tested at)."""
        return self if self.gas_modulus_pa == 0.0 else self.model_copy(update={"gas_modulus_pa": 0.0})

    @property
    def mu_pa(self) -> float:
        """Lame shear modulus mu = E_wall / (2 (1 + nu)) [Pa] (E_wall: E plus a shell's gas_modulus_pa)."""
        return self.wall_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def lambda_pa(self) -> float:
        """Lame first parameter lambda = E_wall nu / ((1 + nu)(1 - 2 nu)) [Pa] (E_wall: E plus a shell's gas_modulus_pa)."""
        e, nu = self.wall_modulus_pa, self.poisson_ratio
        return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))

    def p_wave_speed_m_per_s(self, density_kg_per_m3: float) -> float:
        """Dilatational wave speed c_p = sqrt((lambda + 2 mu) / rho) [m/s]."""
        return math.sqrt((self.lambda_pa + 2.0 * self.mu_pa) / density_kg_per_m3)

    @property
    def stiffness_damping_s(self) -> float:
        """The Kelvin-Voigt viscosity as a stiffness-proportional (Rayleigh beta) damping time eta / mu [s]: the
        deviatoric stress rate 2 eta D equals beta times the elastic 2 mu D (the volumetric part then carries
        beta K instead of 2 eta / 3: more loss in compression than ours). How exports that know only Rayleigh damping
        carry it."""
        return self.viscosity_pa_s / self.mu_pa

    def viscous_time_step_s(self, density_kg_per_m3: float, dx_m: float) -> float:
        """Largest stable explicit time step of the viscous stress, VISCOUS_DT_FACTOR rho dx^2 / eta [s] (inf when
        eta = 0)."""
        if self.viscosity_pa_s <= 0.0:
            return math.inf
        return VISCOUS_DT_FACTOR * density_kg_per_m3 * dx_m * dx_m / self.viscosity_pa_s


SHORE_A_RANGE = (10.0, 90.0)  # where Gent's relation is used (it diverges towards Shore A 100) [-]


def shore_a_youngs_modulus_pa(shore_a: float) -> float:
    """Young's modulus of a rubber from its Shore A hardness, Gent's relation (A. N. Gent, Trans. Inst. Rubber Ind.
    34, 46-57, 1958; ASTM D2240's indenter): E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa [Pa]."""
    if not SHORE_A_RANGE[0] <= shore_a <= SHORE_A_RANGE[1]:
        raise ValueError(f"Shore A {shore_a:g} is outside {SHORE_A_RANGE} where Gent's relation is used")
    return 1.0e6 * 0.0981 * (56.0 + 7.62336 * shore_a) / (0.137505 * (254.0 - 2.54 * shore_a))

