"""Stage contracts: declarative rules the Orchestrator enforces at each layer, loaded from YAML."""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path
from typing import Any, Literal, Self, TypeVar

import yaml
from pydantic import ConfigDict, Field, ValidationError, model_validator

from contracts.base import Model
from contracts.errors import ContractError, validation_message
from contracts.yaml_io import load_yaml

StageName = Literal["L0", "L1", "L2", "L3"]
STAGES_DIR = Path(__file__).parent / "stages"
STAGE_FILES: dict[str, str] = {"L0": "L0_geometry.yaml", "L1": "L1_physical.yaml", "L2": "L2_material.yaml", "L3": "L3_manipulation.yaml"}


class HardGate(Model):
    """A pass/fail rule on one observed metric: `metric op threshold`, or low <= metric <= high for 'within'."""

    name: str = Field(description="what the gate protects, e.g. 'watertight'")
    metric: str = Field(description="observation name, unit in the name, e.g. 'penetration_m'")
    op: Literal["<=", ">=", "<", ">", "==", "within"]
    threshold: float | None = Field(default=None, description="bound for <=, >=, <, >, ==")
    low: float | None = Field(default=None, description="lower bound for 'within'")
    high: float | None = Field(default=None, description="upper bound for 'within'")
    description: str = ""

    @model_validator(mode="after")
    def _bounds_match_op(self) -> HardGate:
        if self.op == "within":
            if self.low is None or self.high is None or self.low > self.high:
                raise ValueError("op 'within' needs low <= high")
        elif self.threshold is None:
            raise ValueError(f"op '{self.op}' needs a threshold")
        return self

    def passes(self, value: float | None) -> bool:
        """True when the value satisfies the gate; a missing or non-finite value fails."""
        if value is None or not math.isfinite(float(value)):
            return False
        v = float(value)
        if self.op == "within":
            return self.low <= v <= self.high  # type: ignore[operator]
        t = float(self.threshold)  # type: ignore[arg-type]
        return {"<=": v <= t, ">=": v >= t, "<": v < t, ">": v > t, "==": v == t}[self.op]


class EditableField(Model):
    """A field a Designer may change, with its bounds; everything else is frozen."""

    name: str = Field(description="dotted path in the candidate, e.g. 'youngs_modulus_pa'")
    low: float
    high: float
    scale: Literal["linear", "log"] = Field(default="linear", description="search scale for the rule backend")
    unit: str = Field(default="-", description="SI unit of the field")
    description: str = ""

    @model_validator(mode="after")
    def _ordered(self) -> EditableField:
        if not self.low <= self.high:
            raise ValueError("low must be <= high")
        if self.scale == "log" and self.low <= 0:
            raise ValueError("a log-scale field needs low > 0")
        return self

    def contains(self, value: float) -> bool:
        """True when value is finite and within [low, high]."""
        return math.isfinite(value) and self.low <= value <= self.high


class StageContract(Model):
    """What a stage may do, must observe, must pass, may edit, and how many revisions it gets."""

    stage: StageName
    title: str
    permitted_actions: list[str] = Field(min_length=1, description="actions / revision routes the Planner may pick")
    required_observations: list[str] = Field(description="metrics every candidate's evidence must contain")
    hard_gates: list[HardGate] = Field(min_length=1)
    editable_fields: list[EditableField] = Field(default_factory=list)
    revision_budget: int = Field(ge=0, description="revisions allowed after the first proposal")
    parameters: dict[str, Any] = Field(default_factory=dict, description="stage settings (SI units in the names)")

    @model_validator(mode="after")
    def _gates_observed(self) -> StageContract:
        missing = sorted({g.metric for g in self.hard_gates} - set(self.required_observations))
        if missing:
            raise ValueError(f"hard gates read metrics that are not required observations: {missing}")
        names = [f.name for f in self.editable_fields]
        if len(names) != len(set(names)):
            raise ValueError("editable field names repeat")
        return self

    def field(self, name: str) -> EditableField:
        """The editable field called name (ContractError if it is not editable)."""
        for f in self.editable_fields:
            if f.name == name:
                return f
        raise ContractError(f"{self.stage}: field '{name}' is not editable")

    def failed_gates(self, observations: dict[str, float]) -> list[HardGate]:
        """Gates that the observations do not pass (missing metrics fail)."""
        return [g for g in self.hard_gates if not g.passes(observations.get(g.metric))]

    def typed_parameters(self, model: type[P]) -> P:
        """`parameters` as a stage's parameter model: a setting this contract leaves out takes the packaged
        contract's value (the packaged stage YAML is the one place defaults live); ContractError names the field."""
        given = {**packaged_parameters(self.stage), **self.parameters}
        try:
            return model.model_validate(given)
        except ValidationError as exc:
            raise ContractError(f"{self.stage}: invalid parameters: " + validation_message(exc)) from None


class StageParameters(Model):
    """Typed `parameters` of a stage contract. No field has a default here: the packaged stage YAML holds them all
    (StageContract.typed_parameters fills what a user contract leaves out). Keys of other stages are ignored (the
    flat evaluation contract carries L1's and L2's together)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    @classmethod
    def of(cls, contract: StageContract) -> Self:
        """The parameters of a contract, typed."""
        return contract.typed_parameters(cls)


P = TypeVar("P", bound=StageParameters)


class ProbeEntry(Model):
    """A probe a stage runs (its registry name, tasks/probes/registry.py), whether it is also a held-out test, and
    settings of its own (a probe that needs a setting no stage parameter holds)."""

    name: str
    held_out: bool = Field(default=False, description="also run at the held-out settings on the chosen candidate")
    settings: dict[str, float] = Field(default_factory=dict, description="the probe's own settings, unit in each name")


class StageProbes(StageParameters):
    """The `parameters.probes` list of a stage contract: which registered probes its Prober runs, in order (none for
    a stage whose contract lists none: L0's checks and L3's trials are not registered probes)."""

    probes: list[ProbeEntry] = Field(default_factory=list)

    def names(self, held_out: bool = False) -> list[str]:
        """The probes of the selection (held_out: of the held-out tests), in the contract's order."""
        return [e.name for e in self.probes if e.held_out or not held_out]

    def entry(self, name: str) -> ProbeEntry:
        """The entry of one probe (ContractError if the stage does not run it)."""
        for e in self.probes:
            if e.name == name:
                return e
        raise ContractError(f"the stage runs no probe '{name}'; it runs {', '.join(self.names())}")
PerQuality = float | dict[str, float]  # one value, or one per quality preset (draft | standard | high)


def at_quality(value: PerQuality, quality: str) -> float:
    """A per-quality parameter's value at a quality preset."""
    return value[quality] if isinstance(value, dict) else value


class L0Parameters(StageParameters):
    """L0 geometry settings (contracts/stages/L0_geometry.yaml says what each is)."""

    marching_cubes_resolution: PerQuality
    particles_per_longest_extent: PerQuality
    max_particles: PerQuality
    min_particles: int
    min_cells_through_thinnest: int
    hollow_particles: Literal["solid", "shell"] = Field(description="a hollow concept's MPM particles: 'solid' "
                                                       "(the whole volume) or 'shell' (its wall alone, opt-in)")
    gaussians_per_particle: float
    gaussian_surface_fraction: float
    max_gaussians: PerQuality
    shape_max_parts: int
    shape_part_size_m: tuple[float, float]
    shape_extent_m: tuple[float, float]
    shape_max_blend_m: float
    shape_part_scale: tuple[float, float]
    shape_check_resolution: int
    shape_max_detached_share: float
    geometry_backend_timeout_s: float
    geometry_backend_default_size_m: float


class L1Parameters(StageParameters):
    """L1 rigid-probe settings."""

    place_duration_s: float = Field(gt=0, description="placement probe's simulated time [s]")
    drop_clearance_fraction_of_height: float = Field(ge=0, description="drop height over the object's height [-]")
    drop_duration_s: float = Field(gt=0, description="drop probe's simulated time [s]")
    slide_angle_margin_deg: float = Field(gt=0, description="incline below / above atan(mu) [deg]")
    slide_measure_s: float = Field(gt=0, description="time the slide's acceleration is measured over [s]")


class L2Parameters(StageParameters):
    """L2 deformable-probe settings (selection and held-out)."""

    compression_strain: float = Field(gt=0)
    compression_strain_held_out: float = Field(gt=0)
    drop_height_fraction_of_height: float = Field(gt=0)
    drop_height_fraction_held_out: float = Field(gt=0)
    stability_duration_s: float = Field(gt=0)
    specimen_particles_per_axis: int = Field(ge=2, description="particles along each side of the specimen cube")
    harness_routes: dict[str, Any] | None = None


class L3Parameters(StageParameters):
    """L3 trial limits and the force-controlled closure."""

    lift_height_m: float = Field(gt=0, description="height the object is lifted [m]")
    place_tolerance_m: float = Field(gt=0, description="largest distance from the target that counts as placed [m]")
    slip_tolerance_m: float = Field(ge=0, description="slip allowed while held [m]")
    record_fps: int = Field(gt=0)
    hold_force_margin: float | None = Field(description="hold force = margin x m g / (2 mu); null or 0: position "
                                            "control within the squeeze field's range")
    hold_force_floor_n: float = Field(ge=0)
    grip_force_limit_n: float | None = Field(description="cap of the force target per finger [N] (null: half the "
                                             "force budget)")


def _format_errors(path: Path, exc: ValidationError) -> str:
    return f"{path}: invalid stage contract: " + validation_message(exc)


def load_contract_file(path: Path) -> StageContract:
    """Read and validate one contract YAML; errors name the file and the field."""
    path = Path(path)
    try:
        data = load_yaml(path.read_text(encoding="utf-8"))
    except FileNotFoundError as exc:
        raise ContractError(f"{path}: contract file not found") from exc
    except yaml.YAMLError as exc:
        raise ContractError(f"{path}: not valid YAML: {exc}") from exc
    if not isinstance(data, dict):
        raise ContractError(f"{path}: a stage contract must be a YAML mapping")
    try:
        return StageContract.model_validate(data)
    except ValidationError as exc:
        raise ContractError(_format_errors(path, exc)) from exc


@cache
def _packaged(stage: str) -> dict[str, Any]:
    return dict(load_contract_file(STAGES_DIR / STAGE_FILES[stage]).parameters)


def packaged_parameters(stage: str) -> dict[str, Any]:
    """The packaged contract's parameters of a stage (a copy): where every parameter's default lives."""
    return dict(_packaged(stage))


def load_contract(stage: StageName, directory: Path | None = None) -> StageContract:
    """The contract of a stage, from the packaged files or a user directory holding the same file names."""
    path = (directory or STAGES_DIR) / STAGE_FILES[stage]
    contract = load_contract_file(path)
    if contract.stage != stage:
        raise ContractError(f"{path}: stage: file declares {contract.stage}, expected {stage}")
    return contract
