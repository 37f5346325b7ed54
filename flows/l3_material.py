"""The L3 -> L2 edge: L2's revalidation of a material revision L3 asks for (tasks.manipulation.material_revision:
what the robot's feedback asks of the material, kept inside what L2 measured and allowed), run as L2's
l2-revalidation flow, a subflow of l3-manipulation, so a Prefect UI shows the edge."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from contracts.manipulation import L2Check
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from contracts.stage import load_contract
from flows.l2_material import evaluate_material
from tasks.manipulation.material_revision import MaterialLimits

if TYPE_CHECKING:
    from tasks.geometry.outputs import L0Asset


def revalidate_in_l2(asset_dir: Path, material: Material, physical: PhysicalModel,
                     limits: MaterialLimits | None = None, sim: SimConfig | None = None,
                     asset: L0Asset | None = None, held_out: bool = False) -> L2Check:
    """L2 revalidation of a revised material (L2's l2-revalidation flow, a subflow of l3-manipulation: its selection
    probes, cached, under `sim`: L3's device and CPU threads): passes when every L2 hard gate holds and every target
    band that held for the L2 material still holds. asset: the L0 data L3 already loaded (else read again).
    held_out: L2's held-out tests too (a calibrated material, flows.calibrate): every hard gate must hold on their
    metrics as well."""
    l2 = load_contract("L2")
    result = evaluate_material(asset_dir, material, contract=l2, sim=sim, held_out=held_out, physical=physical,
                               asset=asset)
    metrics = result["metrics"]
    gates = {g.name: bool(g.passes(metrics.get(g.metric))) for g in l2.hard_gates}
    bands = {b.metric: bool(b.contains(metrics.get(b.metric))) for b in (limits.held_bands() if limits else [])}
    check = L2Check(material=material, passed=all(gates.values()) and all(bands.values()), gates=gates, bands=bands,
                    metrics=metrics, probe_keys=[r.cache_key for r in result["selection"] if r.cache_key])
    if not held_out:
        return check
    held = result["held_out_metrics"]
    held_gates = {g.name: bool(g.passes(held[g.metric])) for g in l2.hard_gates if g.metric in held}  # what they
    # measure (the long rollout is the stability probe's, not a held-out test's)
    if not held_gates:  # held-out tests that measured none of the gates' metrics are no check
        held_gates = {"held-out tests measured": False}
    return check.model_copy(update={"passed": check.passed and all(held_gates.values()), "held_out_gates": held_gates,
                                    "held_out_metrics": held,
                                    "held_out_probes": [r.spec.kind for r in result["held_out"]]})


__all__ = ["revalidate_in_l2"]
