"""asset.json: the manifest of a generated asset directory."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from contracts.base import Model
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.request import AssetRequest
from contracts.robot import ActionPlan, ManipulationOutcome


class StageSummary(Model):
    """How one stage ended."""

    stage: str
    passed: bool
    attempts: int = Field(ge=0)
    sim_calls: int = Field(ge=0)
    metrics: dict[str, float] = Field(default_factory=dict)
    failed_gates: list[str] = Field(default_factory=list)


class Provenance(Model):
    """Versions and keys that reproduce the asset (no timestamps: reruns are content-identical)."""

    deformsmith_version: str
    library_versions: dict[str, str] = Field(default_factory=dict)
    backends: dict[str, str] = Field(default_factory=dict, description="role -> backend/model")
    cache_keys: dict[str, str] = Field(default_factory=dict, description="task -> cache key")
    device: str = "cpu"
    cpu_threads: int = Field(default=1, ge=1, description="CPU threads sharing each MPM rollout (results depend on "
                                                         "this number; 1 on CUDA)")


class AssetManifest(Model):
    """Everything a user needs to trust and reuse the asset; files are relative to the asset directory."""

    schema_version: int = 1
    request: AssetRequest
    physical_model: PhysicalModel | None = None
    material: Material | None = None
    action_plan: ActionPlan | None = None
    manipulation: ManipulationOutcome | None = None
    validation: list[StageSummary] = Field(default_factory=list)
    files: dict[str, str] = Field(default_factory=dict, description="role -> relative path")
    provenance: Provenance
    extra: dict[str, Any] = Field(default_factory=dict)
