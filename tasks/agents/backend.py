"""Role protocols, replies and the contract checks every answer (rule or LLM) must pass."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Generic, Protocol, TypeVar

from contracts.agents import (
    Candidate, Critique, CriticRequest, DesignerRequest, PlannerContext, PlannerDecision,
)
from contracts.errors import DeformSmithError
from contracts.evidence import AgentSource

T = TypeVar("T")


class AgentError(DeformSmithError):
    """A role gave no valid answer and its policy is to fail."""

    exit_code = 6


@dataclass(frozen=True)
class InvalidAnswer:
    """An answer that failed validation: its text, the error fed back, and the values it proposed if parseable."""

    text: str
    error: str
    values: dict[str, float] | None = None


@dataclass
class RoleReply(Generic[T]):
    """A role's answer (None only when no valid one came), where it came from, and the invalid answers before it."""

    value: T | None
    source: AgentSource
    invalid: list[InvalidAnswer] = field(default_factory=list)


class Planner(Protocol):
    """Picks one permitted action / revision route."""

    def plan(self, ctx: PlannerContext) -> RoleReply[PlannerDecision]:
        """Decide the next action."""
        ...


class Designer(Protocol):
    """Proposes values for the action's editable fields."""

    def design(self, req: DesignerRequest) -> RoleReply[Candidate]:
        """Propose a candidate."""
        ...


class Critic(Protocol):
    """Reads evidence against targets and gates; recommends accept or revise."""

    def critique(self, req: CriticRequest) -> RoleReply[Critique]:
        """Judge one candidate."""
        ...


def check_decision(ctx: PlannerContext, decision: PlannerDecision) -> str | None:
    """Why a decision breaks the contract (None when it is fine)."""
    if decision.stop:
        return None
    if decision.action not in ctx.permitted_actions:
        return f"action '{decision.action}' is not permitted; choose one of {ctx.permitted_actions}"
    return None


def check_candidate(req: DesignerRequest, cand: Candidate) -> str | None:
    """Why a candidate breaks the contract: a field outside the action's editable fields, or a value out of bounds."""
    allowed = {f.name: f for f in req.fields}
    problems = []
    for name, value in cand.values.items():
        spec = allowed.get(name)
        if spec is None:
            problems.append(f"'{name}' is not editable under action '{req.action}' (editable: {sorted(allowed) or 'none'})")
        elif not isinstance(value, (int, float)) or not math.isfinite(value):
            problems.append(f"'{name}' = {value!r} is not a finite number")
        elif not spec.contains(float(value)):
            problems.append(f"'{name}' = {value:g} {spec.unit} is outside [{spec.low:g}, {spec.high:g}]")
    return "; ".join(problems) or None


def check_critique(req: CriticRequest, crit: Critique) -> str | None:
    """Why a critique is unusable: directions on fields that are not editable in this stage."""
    names = {f.name for f in req.editable_fields}
    bad = sorted(set(crit.directions) - names)
    if bad:
        return f"directions name fields that are not editable: {bad} (editable: {sorted(names)})"
    failed = [g.gate for g in req.gates if not g.passed]
    if crit.verdict == "accept" and failed:
        return f"cannot accept: hard gates failed: {failed}"
    return None
