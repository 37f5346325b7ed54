"""Exports of an asset to other simulators: the material as exported and one manifest per export (SI units)."""

from __future__ import annotations

import math
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, SerializerFunctionWrapHandler, field_validator, model_serializer

from contracts.material import Material

UNITS = "SI: metres, kilograms, seconds, pascals (N/m^2), kg/m^3; frame z up, object resting on z = 0"


class HomogenisedWall(BaseModel):
    """What an exported pressurised shell's Young's modulus is (tasks.realworld.inflation): its wall's, the rubber's E
    plus the modulus its inflation gas adds, a homogenised equivalent of the gas, not a gas simulation."""

    model_config = ConfigDict(extra="forbid")

    rubber_youngs_modulus_pa: float = Field(gt=0, description="the wall's rubber (material.json's youngs_modulus_pa)")
    gas_modulus_pa: float = Field(gt=0, description="the modulus the inflation gas adds (material.gas_modulus_pa)")
    wall_modulus_pa: float = Field(gt=0, description="their sum: the exported youngs_modulus_pa")
    gauge_pressure_pa: float | None = Field(default=None, description="the gas's gauge pressure (material.json "
                                            "`inflation`)")
    gauge_pressure_source: str | None = None
    note: str


class ExportMaterial(Material):
    """The validated material (L2: E, nu, damping, and its Lame parameters) with what L1 adds, as exported. A
    pressurised shell (a material with gas_modulus_pa) is exported at its wall's modulus: youngs_modulus_pa is the
    rubber's E plus the gas's modulus, gas_modulus_pa is 0 and `homogenised_wall` says so (absent otherwise)."""

    density_kg_per_m3: float = Field(gt=0, description="bulk density rho [kg/m^3]")
    ground_friction: float = Field(ge=0, description="Coulomb friction object-table [-]")
    gripper_friction: float = Field(ge=0, description="Coulomb friction object-finger pad [-]")
    mass_kg: float = Field(gt=0, description="total mass [kg]")
    constitutive_model: str = Field(default="neo-hookean", description="the model E and nu belong to")
    homogenised_wall: HomogenisedWall | None = Field(
        default=None, description="a pressurised shell's: youngs_modulus_pa is its wall's homogenised modulus (the "
        "rubber's E plus its gas's), not the rubber's; absent for every other material")

    @field_validator("density_kg_per_m3", "ground_friction", "gripper_friction", "mass_kg")
    @classmethod
    def _finite_physical(cls, v: float) -> float:
        if not math.isfinite(v):
            raise ValueError("must be a finite number")
        return v

    @model_serializer(mode="wrap")
    def _omit_zero_viscosity(self, handler: SerializerFunctionWrapHandler) -> Any:
        """Material's (zero viscosity and gas modulus left out), and no homogenised_wall key when there is none: a
        solid's export is what it was before the field existed."""
        out = handler(self)
        if isinstance(out, dict):
            for key in ("viscosity_pa_s", "gas_modulus_pa"):
                if out.get(key) == 0.0:
                    out.pop(key)
            if out.get("homogenised_wall") is None:
                out.pop("homogenised_wall", None)
        return out


class TargetManifest(BaseModel):
    """One target's export: its files (relative to the export root), how to load it, and what was exported."""

    model_config = ConfigDict(extra="forbid")

    target: str
    files: list[str]
    load_hint: str = Field(description="one README line: how to load it")
    material: ExportMaterial
    mapping: str = Field(default="", description="constitutive-model mapping in words ('' when identical)")
    damping_mapping: str = Field(default="", description="how our velocity damping rate maps to the target's damping")
    calibrated: dict | None = Field(default=None, description="fitted params, residuals, probes used (crosscheck)")


class ExportManifest(BaseModel):
    """export/manifest.json: every target exported from one asset."""

    model_config = ConfigDict(extra="forbid")

    asset: str
    units: str = UNITS
    tet_mesh: str = Field(description="the tet mesh (.vtk) of the asset, relative to the export root")
    targets: dict[str, TargetManifest] = Field(default_factory=dict)
