"""L3's material revisions: what the robot's feedback asks of the material, kept inside what L2 measured and allowed.

A failed gate that no action can fix any more goes back to the material:
- ``strain_p99`` (deformation bound): a stiffer material, E x strain / bound (x 1.25);
- ``lifted`` / ``transported`` with the object slipping out of a squeeze at its limit: the stiffest E whose specimen
  modulus stays inside the L2 band (less a margin): a stiffer body gives more normal force for the same squeeze;
- ``released_in_target`` / ``settled`` with the object set down upright and then falling over (a tall plush toy too
  soft to stand on its base: it tips from a lean of a few degrees): the stiffest E the L2 modulus band allows;
- ``released_in_target`` / ``settled`` with the object carried there (it rolls or bounces on): more damping, up to the
  rate whose specimen rebound stays inside the L2 band (less a margin), estimated from L2's own screening rollouts.
Every revision is then revalidated by L2 (its selection probes, cached): every hard gate must hold and every target
band that held for the L2 material must still hold; a revision that leaves a band is retried once half way (in log).
The robot then confirms it under the same plan, physical model and force budget (revise_with_l2). L2's revalidation
itself is the flow's (flows/l3_material.py: the l2-revalidation subflow), handed in as a callable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from collections.abc import Callable
from typing import Any

import numpy as np

from contracts.agents import StageOutcome, TargetBehaviour
from contracts.evidence import Attempt
from contracts.manipulation import ConditionSummary, L2Check, MaterialRevision
from contracts.material import Material
from contracts.stage import StageContract, load_contract
from tasks.asset_dir import AssetDir
from tasks.manipulation.context import L3Context, accepted
from tasks.manipulation.diagnosis import TOPPLED_DEG
from tasks.manipulation.l3_record import conditions
from tasks.manipulation.outcome import TrialTolerances

BAND_MARGIN = 0.1  # a revision aims this fraction of the band's width (in its scale) inside the band's end
SLIP_GATES = ("lifted", "transported")
REST_GATES = ("released_in_target", "settled")
MAX_DAMPING_STEP = (3.0, 3.0)  # a damping revision goes at most to 3 x rate + 3 /s


@dataclass(frozen=True)
class MaterialLimits:
    """What L2 said about the material: its targets, the metrics of the L2 material and the screening's rollouts."""

    targets: TargetBehaviour | None = None
    metrics: dict[str, float] = field(default_factory=dict)
    damping_rebound: tuple[tuple[float, float], ...] = ()  # (damping [1/s], specimen rebound [-]) pairs
    youngs_modulus_pa: float | None = None  # the L2 material's E, whose specimen modulus `metrics` holds

    @classmethod
    def from_asset(cls, asset_dir: Path) -> MaterialLimits:
        """Read material.json (empty limits when L2 has not run: the material is a vocabulary prior)."""
        adir = AssetDir(asset_dir)
        if not adir.has("material"):
            return cls()
        rec = adir.material()
        drop = rec.selection.screening.get("drop")  # absent when L2 had no rebound band to screen
        screened = zip(drop["damping_rate_per_s"], drop["rebound_ratio"]) if drop else ()
        pairs = [(float(d), float(r)) for d, r in screened if r is not None and math.isfinite(r)]
        mat = rec.material
        if "rebound_ratio" in rec.metrics and mat is not None:
            pairs.append((mat.damping_rate_per_s, rec.metrics["rebound_ratio"]))
        return cls(rec.targets, dict(rec.metrics), tuple(pairs), mat.youngs_modulus_pa if mat is not None else None)

    def held_bands(self) -> list[Any]:
        """The target bands that held for the L2 material (a revision must keep them)."""
        if self.targets is None:
            return []
        return [b for b in self.targets.bands if b.weight > 0 and b.contains(self.metrics.get(b.metric))]

    def modulus_ceiling(self) -> float | None:
        """The largest E [Pa] whose specimen modulus stays BAND_MARGIN inside the modulus band, scaled from the L2
        material's E and its measured specimen modulus (None: no band or no measurement)."""
        band = self.targets.band("effective_modulus_pa") if self.targets else None
        measured = self.metrics.get("effective_modulus_pa")
        if band is None or not self.youngs_modulus_pa or not measured or not math.isfinite(measured):
            return None
        return self.youngs_modulus_pa * band.point(1.0 - BAND_MARGIN) / measured

    def damping_ceiling(self, field_high: float) -> float | None:
        """The largest damping rate [1/s] whose specimen rebound stays BAND_MARGIN inside the rebound band, from a
        log-linear fit of L2's rollouts (the field's bound when the band reaches 0); None without a rebound band."""
        band = self.targets.band("rebound_ratio") if self.targets else None
        if band is None:
            return None
        floor = band.point(BAND_MARGIN)
        if band.low <= 0.0:
            return field_high
        pts = [(d, math.log(r)) for d, r in self.damping_rebound if r > 0]
        if len({d for d, _ in pts}) < 2:
            return None
        a, b = np.polyfit([p[0] for p in pts], [p[1] for p in pts], 1)
        if a >= 0:
            return None  # rebound does not fall with damping here: no estimate
        return min((math.log(floor) - b) / a, field_high)


def failed_gates(metrics: dict[str, float], contract: StageContract) -> list[str]:
    """Metrics of the hard gates a trial fails."""
    return [g.metric for g in contract.hard_gates if not g.passes(metrics.get(g.metric))]


def revise_material(material: Material, metrics: dict[str, float], contract: StageContract,
                    limits: MaterialLimits | None = None) -> tuple[Material, str] | None:
    """The material the failed gates of a trial ask for, with the reason; None when nothing in reach would help."""
    limits = limits or MaterialLimits()
    failed = set(failed_gates(metrics, contract))
    if "strain_p99" in failed:
        bound = next((g.threshold for g in contract.hard_gates
                      if g.metric == "strain_p99" and g.threshold is not None), 0.6)
        strain = float(metrics.get("strain_p99", bound))
        factor = min(10.0, max(1.5, 1.25 * strain / bound)) if math.isfinite(strain) else 2.0
        return (material.model_copy(update={"youngs_modulus_pa": material.youngs_modulus_pa * factor}),
                f"deformation bound: strain_p99 {strain:.3g} > {bound:.3g}, E x {factor:.3g}")
    if failed & set(SLIP_GATES) and metrics.get("plan_failed", 0.0) != 1.0:
        return _stiffest(material, limits, "slip at the squeeze limit", "more normal force for the same squeeze")
    if failed & set(REST_GATES) and not failed & set(SLIP_GATES) and fell_over(metrics):
        return _stiffest(material, limits, "fell over when let go", "a firmer body stands on its base")
    if failed & set(REST_GATES) and not failed & set(SLIP_GATES):
        field_high = next((f.high for f in load_contract("L2").editable_fields if f.name == "damping_rate_per_s"), 50.0)
        ceiling = limits.damping_ceiling(field_high)
        d = material.damping_rate_per_s
        if ceiling is not None:
            target = min(ceiling, MAX_DAMPING_STEP[0] * d + MAX_DAMPING_STEP[1])
            if target > d + 0.1:
                return (material.model_copy(update={"damping_rate_per_s": target}),
                        f"not at rest in the target: damping {d:.3g} -> {target:.3g} /s, within the L2 rebound band")
    return None


def _stiffest(material: Material, limits: MaterialLimits, trigger: str, because: str) -> tuple[Material, str] | None:
    """The stiffest E the L2 modulus band allows, when that is meaningfully stiffer than the material's."""
    ceiling = limits.modulus_ceiling()
    if ceiling is None or ceiling <= 1.05 * material.youngs_modulus_pa:
        return None
    return (material.model_copy(update={"youngs_modulus_pa": ceiling}),
            f"{trigger}: E {material.youngs_modulus_pa:.4g} -> {ceiling:.4g} Pa, the stiffest the L2 modulus band "
            f"allows ({because})")


def fell_over(metrics: dict[str, float]) -> bool:
    """The trial's object turned over after the fingers let it go, or was still tipping at the end."""
    return (metrics.get("mode_toppled", 0.0) == 1.0 or metrics.get("release_rotation_deg", 0.0) >= TOPPLED_DEG
            or metrics.get("settle_turn_rate_deg_per_s", 0.0) > TrialTolerances().settle_turn_rate_deg_per_s)


def halfway(original: Material, revised: Material) -> Material:
    """A revision half way back: geometric mean of E, arithmetic mean of the damping rate."""
    return revised.model_copy(update={
        "youngs_modulus_pa": math.sqrt(original.youngs_modulus_pa * revised.youngs_modulus_pa),
        "damping_rate_per_s": 0.5 * (original.damping_rate_per_s + revised.damping_rate_per_s)})


Revalidate = Callable[[Material, "MaterialLimits"], L2Check]
"""L2's revalidation of a revised material within the limits L2 set (the flow's: flows.l3_material.revalidate_in_l2)."""


def base_attempt(ctx: L3Context, outcome: StageOutcome, escalated: bool) -> Attempt | None:
    """The attempt a material revision starts from when no plan passed: the escalating one, else the one failing the
    fewest gates (the latest of those)."""
    probed = [a for a in outcome.attempts if a.evidence is not None and a.evidence.metrics]
    if not probed:
        return None
    if escalated:
        return probed[-1]
    return min(reversed(probed), key=lambda a: len(failed_gates(a.evidence.metrics, ctx.contract)))


def revise_with_l2(ctx: L3Context, values: dict[str, float], metrics: dict[str, float], trigger: str,
                   revalidate: Revalidate) -> MaterialRevision | None:
    """Material revision asked by a trial's failed gates (revise_material), L2 revalidation (`revalidate`: one
    half-way retry when a band is left), then the robot under the same plan: the nominal condition, and the
    robustness conditions when it passes. 'accepted' when L2 passed and the nominal condition passes; None when the
    material has nothing to give."""
    limits = MaterialLimits.from_asset(ctx.asset_dir)
    proposal = revise_material(ctx.material, metrics, ctx.contract, limits)
    if proposal is None:
        return None
    revised, reason = proposal
    checks: list[L2Check] = []
    for _ in range(2):
        ctx.progress.say(f"L3 material revision ({trigger}): L2 revalidation of E = {revised.youngs_modulus_pa:.3g} "
                         f"Pa, damping {revised.damping_rate_per_s:.3g} 1/s")
        l2 = revalidate(revised, limits)
        checks.append(l2)
        if l2.passed or not all(l2.gates.values()):
            break
        revised = halfway(ctx.material, revised)
    rev = MaterialRevision.model_validate({
        "trigger": trigger, "from": ctx.material, "to": revised, "reason": reason,
        "failed_gates": failed_gates(metrics, ctx.contract), "l2_revalidation": checks[-1], "l2_checks": checks,
        "plan_values": dict(values), "accepted": False})
    return robot_confirmation(ctx, rev) if checks[-1].passed else rev


def robot_confirmation(ctx: L3Context, rev: MaterialRevision) -> MaterialRevision:
    """The robot under the same plan (rev.plan_values), physical model and force budget with the revised material
    (rev.to), after L2 passed it: the nominal condition, and the robustness conditions when it passes. The revision
    with 'accepted' (the nominal condition passed), its labels ('confirmation') and the robustness conditions."""
    values = dict(rev.plan_values)
    confirm = [ctx.trial(values, "confirmation", "revise_material", material=rev.to)]
    confirmed = accepted(confirm[0].metrics, ctx.contract)
    if confirmed:  # the robustness conditions only matter for a material the nominal condition accepts
        confirm += ctx.under(values, ctx.options.robustness, "robustness", "revise_material", rev.to)
    return rev.model_copy(update={
        "accepted": confirmed, "confirmation": confirm[0].metrics,
        "robustness": conditions(ctx.options.robustness, confirm[1:], ctx.contract)})


def more_robust(revision: MaterialRevision | None, robustness: ConditionSummary) -> MaterialRevision | None:
    """A revision asked by a robustness failure is adopted only when the nominal condition accepts the revised
    material and it passes strictly more perturbations; otherwise it is recorded as not adopted."""
    if revision is None:
        return None
    if revision.accepted and revision.robustness is not None and revision.robustness.passed > robustness.passed:
        return revision
    return revision.model_copy(update={"accepted": False})


@dataclass(frozen=True)
class AfterHarness:
    """What L3 holds after robustness and material revision: the plan's values (None: no plan), the final material
    (the context's own object unless a revision was adopted), the revision tried (if any) and the robustness
    conditions of the final plan (None when they did not run)."""

    values: dict[str, float] | None
    material: Material
    revision: MaterialRevision | None
    robustness: ConditionSummary | None


def robustness_and_revision(ctx: L3Context, outcome: StageOutcome, contract: StageContract,
                            revalidate: Revalidate) -> AfterHarness:
    """L3's steps after its harness stage (`outcome`). 3: an accepted plan under the training perturbations
    (ctx.options.robustness); 4: a failing one asks the material for margin, adopted only when the revised material
    passes the nominal condition and strictly more perturbations (more_robust). When no plan passed (or the harness
    escalated to revise_material) and options.material_fallback: a material revision from the attempt that came
    closest (base_attempt), adopted with its plan when the robot then passes. `contract`: the stage's contract as
    given (the gates the conditions are judged by)."""
    options = ctx.options
    values, material, revision, robustness = outcome.values, ctx.material, None, None
    escalated = outcome.status == "escalated" and outcome.escalation == "revise_material"
    if outcome.passed and values is not None and options.robustness:
        rob = ctx.under(dict(values), options.robustness, "robustness")
        robustness = conditions(options.robustness, rob, contract)
        failing = [r for r in rob if not accepted(r.metrics, contract)]
        if failing:
            revision = more_robust(revise_with_l2(ctx, dict(values), failing[0].metrics, "robustness", revalidate),
                                   robustness)
            if revision is not None and revision.accepted:
                material, robustness = revision.to, revision.robustness
    elif escalated or (not outcome.passed and options.material_fallback):
        base = base_attempt(ctx, outcome, escalated)
        if base is not None and base.evidence is not None:
            revision = revise_with_l2(ctx, dict(base.proposal), base.evidence.metrics,
                                      "escalation" if escalated else "no plan passed", revalidate)
        if revision is not None and revision.accepted:
            values, material, robustness = dict(revision.plan_values), revision.to, revision.robustness
    return AfterHarness(values, material, revision, robustness)


__all__ = ["AfterHarness", "MaterialLimits", "Revalidate", "base_attempt", "failed_gates", "fell_over", "halfway",
           "more_robust", "revise_material", "revise_with_l2", "robot_confirmation", "robustness_and_revision"]
