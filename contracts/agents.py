"""Role I/O of the harness: Planner, Designer, Critic, and the target behaviour they aim for (SI units)."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from contracts.base import Model
from contracts.evidence import Attempt, GateResult
from contracts.stage import EditableField, StageName

Diagnosis = Literal["action", "material", "numerical", "geometry", "none"]
Direction = Literal["increase", "decrease", "keep", "next"]
BandScale = Literal["linear", "log"]
OutcomeStatus = Literal["accepted", "best_valid", "no_valid_candidate", "escalated"]


class TargetBand(Model):
    """A wanted range of one probe metric: low <= metric <= high, with the unit in the metric's name."""

    metric: str = Field(description="probe metric, unit in the name, e.g. 'effective_modulus_pa'")
    unit: str = Field(default="-", description="SI unit of the metric")
    low: float
    high: float
    weight: float = Field(default=1.0, ge=0, description="importance in the agreement score [-]")
    scale: BandScale = Field(default="linear", description="'log' for metrics spanning decades (moduli)")
    source: str = Field(default="vocab", description="where the band came from: vocab:<word> | request:<text> | override")

    @model_validator(mode="after")
    def _ordered(self) -> TargetBand:
        if not (math.isfinite(self.low) and math.isfinite(self.high)) or self.low > self.high:
            raise ValueError("need finite low <= high")
        if self.scale == "log" and self.low <= 0:
            raise ValueError("a log-scale band needs low > 0")
        return self

    @property
    def center(self) -> float:
        """The aim point: geometric mean for log bands, midpoint otherwise."""
        if self.scale == "log":
            return math.sqrt(self.low * self.high)
        return 0.5 * (self.low + self.high)

    def contains(self, value: float | None) -> bool:
        """True when value is finite and inside the band."""
        return value is not None and math.isfinite(value) and self.low <= value <= self.high

    def point(self, u: float) -> float:
        """The value a fraction u of the way from low (0) to high (1), in the band's scale."""
        if self.scale == "log":
            return self.low * (self.high / self.low) ** u
        return self.low + u * (self.high - self.low)

    def contains_inner(self, value: float | None, margin: float = 0.1) -> bool:
        """True when value lies inside the band less a margin (a fraction of its width, in its scale) at each end."""
        return value is not None and math.isfinite(value) and self.point(margin) <= value <= self.point(1.0 - margin)

    def deviation(self, value: float | None) -> float:
        """Distance outside the band: decades for log bands, band widths (or |centre|) otherwise; inf if missing."""
        if value is None or not math.isfinite(value):
            return math.inf
        if self.contains(value):
            return 0.0
        nearest = self.low if value < self.low else self.high
        if self.scale == "log":
            return abs(math.log10(max(value, 1e-300) / nearest))
        width = max(self.high - self.low, 0.05 * abs(self.center), 1e-12)
        return abs(value - nearest) / width

    def signed_residual(self, value: float) -> float:
        """Value minus the aim point, in the band's scale (log10 for log bands)."""
        if self.scale == "log":
            return math.log10(max(value, 1e-300)) - math.log10(self.center)
        return value - self.center


def _measured(value: float | None) -> bool:
    return value is not None and math.isfinite(value)


class TargetBehaviour(Model):
    """What the requested material should do in the probes, plus priors that seed the first proposal."""

    bands: list[TargetBand] = Field(default_factory=list)
    priors: dict[str, float] = Field(
        default_factory=dict, description="initial values per field, e.g. youngs_modulus_pa, density_kg_per_m3"
    )
    matched_words: list[str] = Field(default_factory=list, description="vocabulary words found in the intent")
    intent: str = Field(default="", description="the words the targets were derived from")

    def band(self, metric: str) -> TargetBand | None:
        """The band on a metric, if any."""
        return next((b for b in self.bands if b.metric == metric), None)

    def not_measured(self, metrics: dict[str, float]) -> list[str]:
        """The weighted bands' metrics that were not measured (absent, or not a finite number): neither met nor
        missed (#36); contracts.probes.not_measured_reason says why."""
        return [b.metric for b in self.bands if b.weight > 0 and not _measured(metrics.get(b.metric))]

    def unmet(self, metrics: dict[str, float]) -> list[str]:
        """The weighted bands' metrics that were measured outside their band."""
        return [b.metric for b in self.bands
                if b.weight > 0 and _measured(metrics.get(b.metric)) and not b.contains(metrics.get(b.metric))]

    def _judged(self, metrics: dict[str, float]) -> bool:
        """Whether there is anything to judge: no weighted band, or at least one of them measured."""
        weighted = [b for b in self.bands if b.weight > 0]
        return not weighted or any(_measured(metrics.get(b.metric)) for b in weighted)

    def met(self, metrics: dict[str, float]) -> bool:
        """True when every weighted band that was measured holds (a target not measured is no miss: see
        not_measured; the stage's hard gates and required observations decide what must be measured). False when
        none of the weighted bands was measured."""
        return self._judged(metrics) and not self.unmet(metrics)

    def score(self, metrics: dict[str, float]) -> float:
        """Agreement in [0, 1] over the measured bands: weighted mean of exp(-deviation); 1.0 when every measured band
        holds (and with no bands), 0.0 when none was measured."""
        if not self._judged(metrics):
            return 0.0
        bands = [b for b in self.bands if _measured(metrics.get(b.metric))]
        total = sum(b.weight for b in bands)
        if total <= 0:
            return 1.0
        return sum(b.weight * math.exp(-b.deviation(metrics.get(b.metric))) for b in bands) / total


class HistoryEntry(Model):
    """A compact view of one earlier attempt, as the roles see it."""

    iteration: int
    action: str
    values: dict[str, float]
    metrics: dict[str, float] = Field(default_factory=dict)
    valid: bool = Field(description="passed every hard gate")
    probed: bool = Field(description="False when rejected before any probe ran")
    score: float | None = None
    directions: dict[str, Direction] = Field(default_factory=dict, description="the Critic's suggestion per field")
    failed_gates: list[str] = Field(default_factory=list, description="metrics of the hard gates that failed")
    rejection: str | None = None


class PlannerContext(Model):
    """What the Planner sees: the contract's routes, the state of the search and the last critique."""

    stage: StageName
    permitted_actions: list[str]
    action_fields: dict[str, list[str]] = Field(description="fields each action may edit (empty = escalation route)")
    editable_fields: list[EditableField]
    iteration: int = Field(ge=0)
    budget_left: int = Field(ge=0, description="attempts left, this one included")
    current_values: dict[str, float] = Field(description="the candidate a revision starts from")
    targets: TargetBehaviour
    last_critique: Critique | None = None
    history: list[HistoryEntry] = Field(default_factory=list)
    initial_action: str | None = Field(default=None, description="the layer's suggested first action")


class PlannerDecision(Model):
    """One permitted action / revision route, or stop when no route can help."""

    action: str = Field(description="one of the contract's permitted actions")
    rationale: str = ""
    stop: bool = Field(default=False, description="True: no route can improve the current version")


class DesignerRequest(Model):
    """What the Designer sees: the action, its editable fields with bounds, the current values, targets, feedback."""

    stage: StageName
    action: str
    fields: list[EditableField] = Field(description="the only fields the candidate may set")
    current_values: dict[str, float]
    targets: TargetBehaviour
    critique: Critique | None = None
    history: list[HistoryEntry] = Field(default_factory=list)
    feedback: str | None = Field(default=None, description="why the previous proposal was rejected, if it was")
    budget_left: int = Field(default=1, ge=0, description="attempts left, this one included")


class Candidate(Model):
    """A proposal: new values for editable fields only (SI units as in the field names)."""

    values: dict[str, float] = Field(description="field name -> value, inside the field's bounds")
    rationale: str = ""


class CriticRequest(Model):
    """What the Critic sees: the candidate, its evidence, the gates and the targets."""

    stage: StageName
    values: dict[str, float]
    metrics: dict[str, float]
    gates: list[GateResult]
    targets: TargetBehaviour
    editable_fields: list[EditableField]
    history: list[HistoryEntry] = Field(default_factory=list)


class Critique(Model):
    """Accept or revise, with a diagnosis category and a suggested direction per field."""

    verdict: Literal["accept", "revise"]
    diagnosis: Diagnosis = "none"
    directions: dict[str, Direction] = Field(default_factory=dict, description="field -> increase | decrease | keep | next")
    rationale: str = ""
    unmet: list[str] = Field(default_factory=list, description="metrics outside their band or failing a gate")


class StageOutcome(Model):
    """How a harness run ended: the chosen candidate (if any), why, and every attempt."""

    stage: StageName
    status: OutcomeStatus
    values: dict[str, float] | None = Field(default=None, description="the accepted / best valid candidate")
    metrics: dict[str, float] = Field(default_factory=dict)
    score: float | None = None
    best_iteration: int | None = None
    attempts: list[Attempt] = Field(default_factory=list)
    attempts_used: int = 0
    sim_calls: int = 0
    escalation: str | None = Field(default=None, description="the route handed to another stage, if escalated")
    message: str = ""

    @property
    def passed(self) -> bool:
        """True when a valid candidate came out."""
        return self.status in ("accepted", "best_valid")


class RoleConfig(Model):
    """Which backend plays a role: the offline rule code, or a litellm model string (hosted or local)."""

    backend: Literal["rule", "litellm"] = "rule"
    model: str | None = Field(default=None, description="litellm model string, e.g. 'ollama/llama3.1', 'openai/gpt-4o-mini'")
    timeout_s: float = Field(default=60.0, gt=0, description="per-call timeout [s]")
    max_answers: int = Field(default=3, ge=1, description="answers asked for before the failure policy applies")
    temperature: float = Field(default=0.0, ge=0)
    on_failure: Literal["fail", "fallback_rule"] = Field(
        default="fail", description="after max_answers invalid answers: raise, or let the rule backend answer"
    )

    @model_validator(mode="after")
    def _model_given(self) -> RoleConfig:
        if self.backend == "litellm" and not self.model:
            raise ValueError("a litellm role needs a model string")
        return self


class AgentConfig(Model):
    """Per-role backend configuration of the harness."""

    planner: RoleConfig = Field(default_factory=RoleConfig)
    designer: RoleConfig = Field(default_factory=RoleConfig)
    critic: RoleConfig = Field(default_factory=RoleConfig)

    @classmethod
    def rule(cls) -> AgentConfig:
        """Every role played by the offline rule backend."""
        return cls()

    @classmethod
    def llm(cls, model: str, on_failure: Literal["fail", "fallback_rule"] = "fallback_rule", **kw: float) -> AgentConfig:
        """Every role played by one litellm model."""
        role = RoleConfig(backend="litellm", model=model, on_failure=on_failure, **kw)
        return cls(planner=role, designer=role, critic=role)

    def describe(self) -> dict[str, str]:
        """role -> 'rule' or 'litellm/<model>' (for provenance)."""
        return {r: (c.backend if c.backend == "rule" else f"litellm/{c.model}")
                for r, c in (("planner", self.planner), ("designer", self.designer), ("critic", self.critic))}


PlannerContext.model_rebuild()
DesignerRequest.model_rebuild()

AGENT_SCHEMAS: tuple[type[Model], ...] = (
    TargetBand, TargetBehaviour, HistoryEntry, PlannerContext, PlannerDecision, DesignerRequest, Candidate,
    CriticRequest, Critique, StageOutcome, RoleConfig, AgentConfig,
)
