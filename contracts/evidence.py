"""Attempt records: every proposal, where it came from, what it was tested with, and the verdict."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from contracts.base import Model
from contracts.stage import StageName


class AgentSource(Model):
    """Which backend produced a proposal or judgement."""

    backend: Literal["rule", "litellm", "user", "fallback_rule"] = "rule"
    model: str | None = Field(default=None, description="model string for litellm backends")
    prompt_tokens: int = 0
    completion_tokens: int = 0
    cost_usd: float = 0.0
    retries: int = Field(default=0, description="invalid answers fed back before this one")
    errors: list[str] = Field(default_factory=list, description="the validation errors fed back, in order")
    fallback_reason: str | None = Field(default=None, description="why the rule backend stood in, if it did")


class GateResult(Model):
    """One hard gate evaluated on one candidate."""

    gate: str
    metric: str
    value: float | None
    passed: bool


class EvidenceRecord(Model):
    """The probes behind a verdict: their cache keys, metrics and recordings."""

    probe_keys: list[str] = Field(default_factory=list, description="cache keys of the probe results")
    metrics: dict[str, float] = Field(default_factory=dict)
    recordings: list[str] = Field(default_factory=list, description=".rrd paths")
    sim_calls: int = 0
    not_measured: dict[str, str] = Field(default_factory=dict,
                                         description="target metric -> why the probes did not measure it")


class Attempt(Model):
    """One iteration of a stage's harness loop."""

    stage: StageName
    iteration: int = Field(ge=0)
    action: str = Field(description="the Planner's permitted action / revision route")
    proposal: dict[str, Any] = Field(description="the candidate's editable fields")
    source: AgentSource
    rationale: str = ""
    rejected_before_probe: str | None = Field(default=None, description="why the proposal never ran, if it did not")
    evidence: EvidenceRecord = Field(default_factory=EvidenceRecord)
    gates: list[GateResult] = Field(default_factory=list)
    score: float | None = Field(default=None, description="agreement with the target behaviour, higher is better")
    verdict: Literal["accepted", "revise", "rejected", "rolled_back", "best_so_far", "escalated"]
    diagnosis: str | None = Field(default=None, description="Critic's category: action | material | numerical | geometry")
    critique: str = ""
    parent_iteration: int | None = Field(default=None, description="the attempt this one revised")
    directions: dict[str, str] = Field(default_factory=dict, description="Critic's suggested direction per field")
    planner_source: AgentSource | None = Field(default=None, description="which backend chose the action")
    critic_source: AgentSource | None = Field(default=None, description="which backend judged the evidence")


class StageTally(Model):
    """What one stage spent and how it ended, derived from its attempt records (`inspect` and `evidence` print it)."""

    stage: StageName
    status: str = Field(description="the harness outcome (accepted | best_valid | ...); L0: passed | failed")
    passed: bool = Field(description="a valid candidate came out (best_valid counts: see unmet_targets)")
    attempts: int = Field(ge=0, description="harness iterations: the stage's lines in evidence/attempts.jsonl")
    loop_sim_calls: int = Field(ge=0, description="simulations of those attempts (their evidence.sim_calls)")
    extra_sim_calls: dict[str, int] = Field(default_factory=dict,
                                            description="simulations outside the loop by role: screening, held_out, "
                                                        "robustness, confirmation, other")
    unmet_targets: list[str] = Field(default_factory=list,
                                     description="target bands the kept candidate was measured outside of")
    not_measured: dict[str, str] = Field(default_factory=dict,
                                         description="target bands not measured on the kept candidate -> why")
    message: str = ""

    @property
    def sim_calls(self) -> int:
        """Every simulation the stage ran: the loop's and the ones outside it."""
        return self.loop_sim_calls + sum(self.extra_sim_calls.values())
