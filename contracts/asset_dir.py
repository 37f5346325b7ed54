"""The asset directory's JSON documents: their file names and typed models (data only; tasks/asset_dir.py reads and
writes them).

Each model holds exactly the keys its layer writes, so a document read and written back is the same JSON. Parts that
are records of a task's own structures (a mass check, a probe dump) stay plain JSON (`dict[str, Any]`); the parts
later layers use are typed (PhysicalModel, Material, TargetBehaviour, ...). L3's record is typed end to end
(contracts.manipulation.ManipulationRecord).
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, SerializerFunctionWrapHandler, model_serializer

from contracts.agents import OutcomeStatus, TargetBehaviour
from contracts.base import Model
from contracts.evidence import GateResult
from contracts.manifest import AssetManifest
from contracts.manipulation import ManipulationRecord
from contracts.material import Material
from contracts.physical import PhysicalModel

GEOMETRY_JSON = "geometry.json"        # L0
PHYSICAL_JSON = "physical.json"        # L1
MATERIAL_JSON = "material.json"        # L2
MANIPULATION_JSON = "manipulation.json"  # L3
ASSET_JSON = "asset.json"              # the published manifest (contracts.manifest.AssetManifest)
PARTICLES_ZARR = "particles.zarr"
RECORDINGS_DIR = "recordings"
EVIDENCE_DIR = "evidence"
INTERACTION_DIR = "interaction"

# `--record`: what an asset keeps of the probes' and trials' recordings and of L3's trial states (#38 item 5): the
# adopted (else reported) L3 trial's alone, the rest staying in the cache and named by the records; or all of them
KeepTrials = Literal["adopted", "all"]
KEEP_TRIALS: tuple[str, ...] = get_args(KeepTrials)
DEFAULT_KEEP: KeepTrials = "adopted"


def attempt_path(attempt: int) -> str:
    """Where L3 stores trial `attempt`'s interaction data, relative to the asset (manipulation.json's `attempt` paths)."""
    return f"{INTERACTION_DIR}/attempt_{attempt:03d}"


DocumentName = Literal["geometry", "physical", "material", "manipulation", "manifest"]
DOCUMENT_FILES: dict[str, str] = {"geometry": GEOMETRY_JSON, "physical": PHYSICAL_JSON, "material": MATERIAL_JSON,
                                  "manipulation": MANIPULATION_JSON, "manifest": ASSET_JSON}


class GeometryInfo(BaseModel):
    """geometry.json `info`: how L0 built the mesh (tasks.geometry.pipeline.BuildInfo as written; the fields later
    layers read are typed, the rest is kept as written)."""

    model_config = ConfigDict(extra="allow", frozen=True)

    source: str
    name: str
    category: str
    entry: str | None = None
    concept: dict[str, Any] | None = None


class ParticleBody(Model):
    """geometry.json `particles`: what the MPM particles fill. A hollow object (a tennis ball, a bath duck:
    ConceptMatch.hollow with a wall) is its shell, the particles within `wall_m` of the surface, when the lattice
    resolves the wall (at least two particle spacings, within the particle budget); else the solid, and `reason`
    says why (L1 then weighs the solid at an effective density)."""

    kind: Literal["solid", "shell"] = Field(description="the solid volume, or a hollow object's wall alone")
    wall_m: float | None = Field(default=None, gt=0, description="the shell's wall thickness (kind 'shell') [m]")
    requested_wall_m: float | None = Field(default=None, gt=0, description="the concept's wall, built or not [m]")
    spacing_m: float = Field(gt=0, description="the particle lattice's spacing [m]")
    volume_m3: float = Field(gt=0, description="what the particle volumes sum to: the mesh volume, or the shell's "
                             "(the mesh volume x the share of the fine lattice within the wall) [m^3]")
    enclosed_volume_m3: float = Field(gt=0, description="the mesh's volume [m^3]")
    reason: str | None = Field(default=None, description="why a hollow object stayed solid (None otherwise)")
    gauge_pressure_pa: float | None = Field(default=None, gt=0, description="a pressurised ball's shell: the gas it "
                                            "encloses, its gauge pressure (the lexicon's inflation_gauge_pa); L2 "
                                            "adds its stiffness to the wall (tasks.realworld.inflation); absent "
                                            "otherwise [Pa]")
    gauge_pressure_source: str | None = Field(default=None, description="where gauge_pressure_pa comes from")

    @model_serializer(mode="wrap")
    def _omit_no_gas(self, handler: SerializerFunctionWrapHandler) -> Any:
        """The gas keys are written only for a pressurised shell: a solid's record is the one of before."""
        out = handler(self)
        if isinstance(out, dict):
            for key in ("gauge_pressure_pa", "gauge_pressure_source"):
                if out.get(key, 0.0) is None:
                    out.pop(key)
        return out

    @property
    def shell(self) -> bool:
        """True when the particles are a hollow object's wall."""
        return self.kind == "shell"


class GeometryRecord(Model):
    """geometry.json: L0's checks, gates, files and build information."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"request", "particles"})  # keys older records lack
    schema_version: int = 1
    info: GeometryInfo
    metrics: dict[str, float]
    gates: list[GateResult]
    passed: bool
    failed_gates: list[str]
    warnings: list[str]
    files: dict[str, str]
    request: dict[str, Any] | None = Field(default=None, description="the whole request (records before it: absent)")
    particles: ParticleBody | None = Field(default=None, description="what the MPM particles fill: the solid or a "
                                           "hollow object's shell (records before session 32: absent, solid)")


class PhysicalRecord(Model):
    """physical.json: L1's outcome, its targets, mass check and the frozen PhysicalModel (None when L1 failed)."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"cached_recordings"})  # keys older records lack
    schema_version: int = 1
    stage: Literal["L1"] = "L1"
    passed: bool
    status: OutcomeStatus
    message: str
    material_class: str
    intent: str
    mass_check: dict[str, Any] = Field(description="tasks.physical.mass.MassCheck as written")
    targets: TargetBehaviour
    physical_model: PhysicalModel | None
    metrics: dict[str, float]
    sim_calls: int
    attempts: int
    recordings: list[str]
    cached_recordings: dict[str, str] = Field(
        default_factory=dict, description="the probe recordings the asset does not hold (#38: by default an asset "
        "keeps the adopted L3 trial's recording alone; `--record all` copies these too): the name it would have in the "
        "asset (recordings/<stage>_<kind>.rrd) -> its path under the cache root (recordings/<stage>_<kind>-<the "
        "probe's cache key, first 16 hex digits>.rrd; the full key in evidence/attempts.jsonl)")


class HeldOutSummary(Model):
    """material.json `held_out`: the selected material under the contract's held-out settings."""

    metrics: dict[str, float]
    targets_met: bool | None
    score: float | None
    bands: list[str]
    probes: list[dict[str, Any]] = Field(description="ProbeResult dumps without wall time")


class SelectionSummary(Model):
    """material.json `selection`: how the harness chose the material."""

    status: OutcomeStatus
    score: float | None
    targets_met: bool
    best_iteration: int | None
    attempts: int
    sim_calls: int
    screening: dict[str, Any]
    ranking: list[dict[str, Any]]


class MaterialRecord(Model):
    """material.json: L2's outcome, targets, the material (None when L2 found none) and its evidence; L2's record, which
    L3 never edits (the asset's final material is AdoptedMaterial: this one, or an L3 revision in manipulation.json)."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"not_measured", "cached_recordings",  # older: none
                                                                "inflation"})
    schema_version: int = 1
    stage: Literal["L2"] = "L2"
    passed: bool
    status: OutcomeStatus
    message: str
    intent: str
    targets: TargetBehaviour
    material: Material | None
    physical_model: PhysicalModel
    metrics: dict[str, float]
    not_measured: dict[str, str] = Field(default_factory=dict, description="target metrics the selection probes did "
                                         "not measure on the chosen material -> why (#36: neither met nor missed)")
    held_out: HeldOutSummary
    selection: SelectionSummary
    sim_calls: int
    recordings: dict[str, str | None] = Field(description="probe kind -> recording path in the asset")
    cached_recordings: dict[str, str] = Field(
        default_factory=dict, description="the probe recordings the asset does not hold (#38: by default an asset "
        "keeps the adopted L3 trial's recording alone; `--record all` copies these too): the name it would have in the "
        "asset (recordings/<stage>_<kind>.rrd) -> its path under the cache root (recordings/<stage>_<kind>-<the "
        "probe's cache key, first 16 hex digits>.rrd; the full key in evidence/attempts.jsonl)")
    inflation: dict[str, float | str] | None = Field(
        default=None, description="a pressurised ball built as its shell (geometry.json `particles` with a gauge "
        "pressure): the gas's pressure and source, the radius and wall, the rubber's E (the material's "
        "youngs_modulus_pa, what the specimen is tested at), the modulus the gas adds (material.gas_modulus_pa) and "
        "the wall's (the shell is simulated at their sum), and the model: a homogenised equivalent, not a gas "
        "simulation (tasks.realworld.inflation); absent otherwise")


MaterialSource = Literal["L2", "L3 revision"]


class AdoptedMaterial(Model):
    """The asset's one final material (tasks.asset_dir.AssetDir.adopted_material): L2's selection, or the L3 material
    revision that L2 revalidated and the robot confirmed when L3 passed with it."""

    material: Material
    source: MaterialSource
    document: str = Field(description="where it is recorded: material.json `material`, or manipulation.json "
                          "`material` (its `material_revision.to`)")
    reason: str = Field(description="why it is the asset's: L2's selection status, or the revision's trigger and reason")
    metrics: dict[str, float] = Field(description="L2's selection probes on this material: material.json `metrics`, "
                                      "or the revision's L2 revalidation")


DOCUMENT_MODELS: dict[str, type[BaseModel]] = {"geometry": GeometryRecord, "physical": PhysicalRecord,
                                               "material": MaterialRecord, "manipulation": ManipulationRecord,
                                               "manifest": AssetManifest}
