"""Exports of an asset to other simulators: the material as exported and one manifest per export (SI units)."""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field, field_validator

from contracts.material import Material

UNITS = "SI: metres, kilograms, seconds, pascals (N/m^2), kg/m^3; frame z up, object resting on z = 0"


class ExportMaterial(Material):
    """The validated material (L2: E, nu, damping, and its Lame parameters) with what L1 adds, as exported."""

    density_kg_per_m3: float = Field(gt=0, description="bulk density rho [kg/m^3]")
    ground_friction: float = Field(ge=0, description="Coulomb friction object-table [-]")
    gripper_friction: float = Field(ge=0, description="Coulomb friction object-finger pad [-]")
    mass_kg: float = Field(gt=0, description="total mass [kg]")
    constitutive_model: str = Field(default="neo-hookean", description="the model E and nu belong to")

    @field_validator("density_kg_per_m3", "ground_friction", "gripper_friction", "mass_kg")
    @classmethod
    def _finite_physical(cls, v: float) -> float:
        if not math.isfinite(v):
            raise ValueError("must be a finite number")
        return v


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
