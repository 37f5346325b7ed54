"""Stage contracts: declarative rules the Orchestrator enforces at each layer, loaded from YAML."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import Field, ValidationError, model_validator

from contracts.base import Model
from contracts.errors import ContractError, validation_message

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
    def _bounds_match_op(self) -> "HardGate":
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
    def _ordered(self) -> "EditableField":
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
    def _gates_observed(self) -> "StageContract":
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


def _format_errors(path: Path, exc: ValidationError) -> str:
    return f"{path}: invalid stage contract: " + validation_message(exc)


def load_contract_file(path: Path) -> StageContract:
    """Read and validate one contract YAML; errors name the file and the field."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
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


def load_contract(stage: StageName, directory: Path | None = None) -> StageContract:
    """The contract of a stage, from the packaged files or a user directory holding the same file names."""
    path = (directory or STAGES_DIR) / STAGE_FILES[stage]
    contract = load_contract_file(path)
    if contract.stage != stage:
        raise ContractError(f"{path}: stage: file declares {contract.stage}, expected {stage}")
    return contract
