"""L3's material revisions: what the robot's feedback asks of the material, kept inside what L2 measured and allowed.

A failed gate that no action can fix any more goes back to the material:
- ``strain_p99`` (deformation bound): a stiffer material, E x strain / bound (x 1.25);
- ``lifted`` / ``transported`` with the object slipping out of a squeeze at its limit: the stiffest E whose specimen
  modulus stays inside the L2 band (less a margin): a stiffer body gives more normal force for the same squeeze;
- ``released_in_target`` / ``settled`` with the object carried there (it rolls or bounces on): more damping, up to the
  rate whose specimen rebound stays inside the L2 band (less a margin), estimated from L2's own screening rollouts.
Every revision is then revalidated by L2 (its selection probes, cached): every hard gate must hold and every target
band that held for the L2 material must still hold; a revision that leaves a band is retried once half way (in log).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from contracts.agents import TargetBehaviour
from contracts.manipulation import L2Check
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from contracts.stage import StageContract, load_contract

if TYPE_CHECKING:
    from tasks.geometry.outputs import L0Asset

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
        from tasks.asset_dir import AssetDir

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
        ceiling = limits.modulus_ceiling()
        if ceiling is not None and ceiling > 1.05 * material.youngs_modulus_pa:
            return (material.model_copy(update={"youngs_modulus_pa": ceiling}),
                    f"slip at the squeeze limit: E {material.youngs_modulus_pa:.4g} -> {ceiling:.4g} Pa, the stiffest "
                    "the L2 modulus band allows (more normal force for the same squeeze)")
        return None
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


def halfway(original: Material, revised: Material) -> Material:
    """A revision half way back: geometric mean of E, arithmetic mean of the damping rate."""
    return revised.model_copy(update={
        "youngs_modulus_pa": math.sqrt(original.youngs_modulus_pa * revised.youngs_modulus_pa),
        "damping_rate_per_s": 0.5 * (original.damping_rate_per_s + revised.damping_rate_per_s)})


def revalidate_in_l2(asset_dir: Path, material: Material, physical: PhysicalModel,
                     limits: MaterialLimits | None = None, sim: SimConfig | None = None,
                     asset: L0Asset | None = None) -> L2Check:
    """L2 revalidation of a revised material (L2's l2-revalidation flow, a subflow of l3-manipulation: its selection
    probes, cached, under `sim`: L3's device and CPU threads): passes when every L2 hard gate holds and every target
    band that held for the L2 material still holds. asset: the L0 data L3 already loaded (else read again)."""
    from flows.l2_material import evaluate_material

    l2 = load_contract("L2")
    result = evaluate_material(asset_dir, material, contract=l2, sim=sim, held_out=False, physical=physical,
                               asset=asset)
    metrics = result["metrics"]
    gates = {g.name: bool(g.passes(metrics.get(g.metric))) for g in l2.hard_gates}
    bands = {b.metric: bool(b.contains(metrics.get(b.metric))) for b in (limits.held_bands() if limits else [])}
    return L2Check(material=material, passed=all(gates.values()) and all(bands.values()), gates=gates, bands=bands,
                   metrics=metrics, probe_keys=[r.cache_key for r in result["selection"] if r.cache_key])


__all__ = ["MaterialLimits", "failed_gates", "halfway", "revalidate_in_l2", "revise_material"]
