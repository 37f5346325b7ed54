"""asset.json: the manifest of a generated asset directory."""

from __future__ import annotations

from typing import Any

from pydantic import Field, model_serializer

from contracts.base import Model
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.request import AssetRequest
from contracts.robot import ActionPlan, ManipulationOutcome
from contracts.sim import KernelOptions


class StageSummary(Model):
    """How one stage ended."""

    stage: str
    passed: bool
    attempts: int = Field(ge=0)
    sim_calls: int = Field(ge=0)
    metrics: dict[str, float] = Field(default_factory=dict)
    failed_gates: list[str] = Field(default_factory=list)
    reason: str | None = Field(default=None, description="why the stage did not pass, in words (e.g. L3: 'no grasp: "
                                                        "...' or 'not lifted: mean finger force ... < m g / (2 mu)')")


# the libraries whose versions a manifest's provenance records (tasks.manifest_summary)
PROVENANCE_LIBRARIES = ("numpy", "warp-lang", "prefect", "zarr", "trimesh", "coacd", "pybullet", "rerun-sdk",
                        "pydantic")


class Provenance(Model):
    """Versions and keys that reproduce the asset (no timestamps: reruns are content-identical)."""

    deformsmith_version: str
    library_versions: dict[str, str] = Field(default_factory=dict)
    backends: dict[str, str] = Field(default_factory=dict, description="role -> backend/model")
    fallbacks: list[str] = Field(default_factory=list, description="where and why the offline rule backend stood in "
                                                                   "for the configured LLM (empty: it never did)")
    cache_keys: dict[str, str] = Field(default_factory=dict, description="task -> cache key")
    device: str = "cpu"
    cpu_threads: int = Field(default=1, ge=1, description="CPU threads sharing each MPM rollout (results depend on "
                                                         "this number; 1 on CUDA)")
    kernel: KernelOptions | None = Field(default=None, description="the MPM kernel options when not the engine's "
                                                                   "defaults (SimConfig.kernel); absent: the defaults")

    @model_serializer(mode="wrap")
    def _omit_default_kernel(self, handler):
        """No `kernel` key when the defaults ran, so manifests of default runs read as they always did."""
        out = handler(self)
        if isinstance(out, dict) and out.get("kernel") is None:
            out.pop("kernel", None)
        return out


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
