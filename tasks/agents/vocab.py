"""Typed views of the vocabulary and route tables under contracts/vocab (data, not code)."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Literal

import yaml
from contracts.yaml_io import load_yaml

import contracts
from pydantic import Field, ValidationError, model_validator

from contracts.base import Model
from contracts.errors import ContractError

VOCAB_DIR = Path(contracts.__file__).resolve().parent / "vocab"


class MetricSpec(Model):
    """How bands on one metric are scored."""

    unit: str = "-"
    scale: Literal["linear", "log"] = "linear"
    weight: float = Field(default=1.0, ge=0)


class MaterialEntry(Model):
    """One vocabulary material: its words, priors and target bands."""

    words: list[str]
    priors: dict[str, float]
    prior_ranges: dict[str, tuple[float, float]] = Field(default_factory=dict)
    bands: dict[str, tuple[float, float]]
    shell_wall_thickness_m: float | None = Field(default=None, gt=0, description="wall of a hollow object made of "
                                                 "this material (its shell's mass when no typical mass is known) [m]")


class ModifierEntry(Model):
    """A word that narrows (band_fraction) or replaces (bands) the matched material's bands."""

    words: list[str]
    band_fraction: dict[str, tuple[float, float]] = Field(default_factory=dict)
    bands: dict[str, tuple[float, float]] = Field(default_factory=dict)


class ExplicitTolerance(Model):
    """Band half-widths around a number stated in the request."""

    log_factor: float = Field(default=1.25, gt=1)
    linear_abs: float = Field(default=0.05, gt=0)


class MaterialVocab(Model):
    """contracts/vocab/materials.yaml + objects.yaml."""

    metrics: dict[str, MetricSpec]
    default_material: str
    materials: dict[str, MaterialEntry]
    modifiers: dict[str, ModifierEntry] = Field(default_factory=dict)
    explicit_tolerance: ExplicitTolerance = Field(default_factory=ExplicitTolerance)
    objects: dict[str, str] = Field(default_factory=dict)
    rigid_words: list[str] = Field(default_factory=list)
    rigid_objects: list[str] = Field(default_factory=list, description="nouns of objects that are rigid as usually "
                                     "made (refused unless a soft word is named too)")
    soft_words: list[str] = Field(default_factory=list, description="words that keep a rigid object noun allowed "
                                  "('a foam can cooler', 'a squeezable bottle')")

    def metric(self, name: str) -> MetricSpec:
        """The scoring spec of a metric (linear, weight 1, unit '-' when unlisted)."""
        return self.metrics.get(name, MetricSpec())


class Coupling(Model):
    """How one field moves one metric: slope in search coordinates (log10 where the scale is log)."""

    field: str
    slope: float


class GateRoute(Model):
    """What a failed gate suggests."""

    diagnosis: Literal["action", "material", "numerical", "geometry", "none"] = "none"
    directions: dict[str, Literal["increase", "decrease", "next"]] = Field(default_factory=dict)
    escalate: str | None = None
    priority: int = Field(default=0, description="when failed gates disagree on a field, the highest priority wins")
    after: str | None = Field(default=None, description="the gate metric of the phase before this gate's: while that "
                              "gate fails too, this failure is its consequence and suggests no direction")


class StageRoutes(Model):
    """The route table of one stage (see routes.yaml)."""

    actions: dict[str, list[str]] = Field(default_factory=dict)
    escalations: list[str] = Field(default_factory=list)
    route_order: list[str] = Field(default_factory=list)
    couplings: dict[str, list[Coupling]] = Field(default_factory=dict)
    methods: dict[str, Literal["secant", "bisection", "enumerate"]] = Field(default_factory=dict)
    integers: list[str] = Field(default_factory=list)
    # a field moved the same way again without ever overshooting goes straight to its bound, unless listed here: then
    # its step grows by this factor over the last one (a grip: a slip asks for a firmer squeeze, not the hardest one)
    expansion: dict[str, float] = Field(default_factory=dict)
    gates: dict[str, GateRoute] = Field(default_factory=dict)
    # a failure mode the stage's probe diagnosed, as a 0/1 metric (e.g. L3's mode_slipped_at_lift,
    # tasks.manipulation.diagnosis) -> its route, which replaces the failed gates' directions when the mode is seen:
    # the same failed gate ('not lifted') is answered by what went wrong, not by one fixed direction
    modes: dict[str, GateRoute] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _after_names_a_gate(self) -> StageRoutes:
        bad = {m: r.after for m, r in self.gates.items() if r.after is not None and (r.after not in self.gates or r.after == m)}
        if bad:
            raise ValueError(f"'after' must name another gate of the same table: {bad}")
        return self

    def fields_of(self, action: str, all_fields: list[str]) -> list[str]:
        """Fields an action may edit; an unlisted action may edit every editable field."""
        if action in self.actions:
            return [f for f in self.actions[action] if f in all_fields]
        return list(all_fields)

    def couplings_of_metric(self, metric: str) -> list[tuple[str, float]]:
        """(field, slope) for every field that moves this metric."""
        return [(c.field, c.slope) for c in self.couplings.get(metric, [])]

    def couplings_of(self, field: str) -> dict[str, float]:
        """metric -> slope for every metric this field moves."""
        return {m: c.slope for m, cs in self.couplings.items() for c in cs if c.field == field}


def _read(path: Path) -> dict:
    try:
        data = load_yaml(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise ContractError(f"{path}: cannot read vocabulary: {exc}") from exc
    if not isinstance(data, dict):
        raise ContractError(f"{path}: must be a YAML mapping")
    return data


@lru_cache(maxsize=4)
def load_material_vocab(directory: Path = VOCAB_DIR) -> MaterialVocab:
    """Materials, modifiers and object words (validated)."""
    data = _read(directory / "materials.yaml")
    objects = directory / "objects.yaml"
    if objects.exists():
        data["objects"] = _read(objects).get("objects", {})
    try:
        vocab = MaterialVocab.model_validate(data)
    except ValidationError as exc:
        raise ContractError(f"{directory / 'materials.yaml'}: invalid vocabulary: {exc}") from exc
    unknown = sorted({m for m in vocab.objects.values() if m not in vocab.materials})
    if vocab.default_material not in vocab.materials or unknown:
        raise ContractError(f"{directory}: vocabulary names unknown materials: {unknown or vocab.default_material}")
    return vocab


@lru_cache(maxsize=4)
def load_routes(directory: Path = VOCAB_DIR) -> dict[str, StageRoutes]:
    """Route tables per stage (validated)."""
    data = _read(directory / "routes.yaml")
    try:
        return {stage: StageRoutes.model_validate(v) for stage, v in data.items()}
    except ValidationError as exc:
        raise ContractError(f"{directory / 'routes.yaml'}: invalid routes: {exc}") from exc


def stage_routes(stage: str, parameters: dict | None = None) -> StageRoutes:
    """The routes of one stage; a contract's `parameters.harness_routes` mapping overrides keys of the table."""
    base = load_routes().get(stage, StageRoutes())
    override = (parameters or {}).get("harness_routes")
    if not override:
        return base
    try:
        return StageRoutes.model_validate({**base.model_dump(), **override})
    except ValidationError as exc:
        raise ContractError(f"{stage}: invalid parameters.harness_routes: {exc}") from exc
