"""`bench realworld`: every object of the real-world set (contracts/measured/realworld.yaml) built from its plain name
through L0-L2 at draft, its regulation drop simulated at the rule's impact speed, our figures beside the published
ones (tasks.realworld). Every layer's work is a cached task: a rerun costs hits."""

from __future__ import annotations

import math
import re
import shutil
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import cache
from contracts.errors import DeformSmithError, StageFailure
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.realworld import ObjectReport, OurFigures, RealWorldObject, RealWorldReport, RuleDrop
from contracts.request import AssetRequest
from contracts.sim import Device, SimConfig
from flows import l0_geometry, l1_physical, l2_material
from tasks.agents.intent import concept_of
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import L0Asset, load_l0
from tasks.realworld.compare import compare, summarise
from tasks.realworld.impact import impact
from tasks.realworld.physics import (damped_impact_speed_m_per_s, damped_rise_height_m, impact_speed_m_per_s,
                                     rise_height_m, terminal_speed_m_per_s)


def slug(name: str) -> str:
    """A directory name for an object's asset."""
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def rule_rebound(rule: RuleDrop, asset: L0Asset, physical: PhysicalModel, material: Material,
                 sim: SimConfig) -> dict[str, Any]:
    """The rule's drop as the asset does it in our engine: the fall under the material's damping (closed form, the
    engine's world-frame velocity decay), the impact at that speed in the MPM (tasks.realworld.impact: the loss in the
    material, its Kelvin-Voigt viscosity, acts here), the rise under the same damping; rebound ratio = rise / drop. Beside it, the impact's restitution as a real ball would show it
    (rebound_ratio_air: the same restitution with a fall and rise through air, no engine damping)."""
    d = material.damping_rate_per_s
    v_in = damped_impact_speed_m_per_s(rule.drop_height_m, d)
    raw = impact(asset.particles_m, asset.volumes_m3, physical, material, v_in, sim)
    e = raw.get("restitution", math.nan)
    ok = math.isfinite(e) and raw["finite"] == 1.0
    vt = terminal_speed_m_per_s(physical.mass_kg, rule.diameter_m)
    v_air = impact_speed_m_per_s(rule.drop_height_m, vt)
    return {"impact_speed_m_per_s": v_in, "restitution": e if ok else None,
            "rebound_ratio_vacuum": e * e if ok else None,
            "rebound_ratio": damped_rise_height_m(e * v_in, d) / rule.drop_height_m if ok else None,
            "rebound_ratio_air": rise_height_m(e * v_air, vt) / rule.drop_height_m if ok else None,
            "rebound_sim": {k: float(v) for k, v in raw.items() if math.isfinite(v)}}


def build_figures(obj: RealWorldObject, work: Path, sim: SimConfig, priors_only: bool,
                  hollow_shell: bool = False) -> OurFigures:
    """L0 -> L1 -> L2 (draft) of the object's plain name in `work`, and its rule drop; priors_only: L0, L1 and L2's
    priors (the first proposal), no MPM; hollow_shell: a hollow concept's particles as its wall (with its gas, where
    the lexicon records a pressure), as `deformsmith geometry --hollow-shell`."""
    request = AssetRequest(text=obj.name, quality="draft")
    contract = l0_geometry.with_hollow_particles("shell") if hollow_shell else None
    l0 = l0_geometry.run_l0(request, quality="draft", contract=contract)
    if not l0.checks.passed:
        raise StageFailure("L0", f"geometry gates failed: {', '.join(l0.checks.failed)}")
    if work.exists():
        shutil.rmtree(work)
    l0_geometry.write_l0(l0, work, request=request)
    asset = load_l0(work)
    concept = concept_of(asset.record)
    physical, o1 = l1_physical.run_l1(work, obj.name)
    if physical is None:
        raise StageFailure("L1", o1.message)
    targets = l2_material.l2_targets(asset, request)
    base: dict[str, Any] = {"concept": concept.concept if concept else None,
                            "material_class": concept.default_material if concept else None,
                            "mass_kg": physical.mass_kg, "density_kg_per_m3": physical.density_kg_per_m3}
    if priors_only:
        p = targets.priors
        return OurFigures(**base, youngs_modulus_pa=p.get("youngs_modulus_pa"), poisson_ratio=p.get("poisson_ratio"),
                          damping_rate_per_s=p.get("damping_rate_per_s"))
    material, o2 = l2_material.run_l2(work, request, sim=sim, physical=physical)
    if material is None:
        raise StageFailure("L2", o2.message)
    metrics = AssetDir(work).material().metrics
    figures: dict[str, Any] = {**base, "youngs_modulus_pa": material.youngs_modulus_pa,
                               "poisson_ratio": material.poisson_ratio,
                               "damping_rate_per_s": material.damping_rate_per_s,
                               "viscosity_pa_s": material.viscosity_pa_s,
                               "effective_modulus_pa": metrics.get("effective_modulus_pa"),
                               "object_effective_modulus_pa": metrics.get("object_effective_modulus_pa")}
    if obj.rebound is not None:
        figures.update(rule_rebound(obj.rebound, asset, physical, material, sim))
    return OurFigures(**figures)


def run_object(obj: RealWorldObject, root: Path, sim: SimConfig, priors_only: bool = False,
               hollow_shell: bool = False) -> ObjectReport:
    """One object's report; a layer that says no (or bad input) is the object's error, not the bench's."""
    t0 = time.perf_counter()
    try:
        ours = build_figures(obj, root / slug(obj.name), sim, priors_only, hollow_shell)
        status, error = "ok", None
    except DeformSmithError as exc:
        ours, status, error = OurFigures(), "failed", f"{type(exc).__name__}: {exc}"
    return ObjectReport(name=obj.name, kind=obj.kind, expected_concept=obj.concept, status=status, error=error,
                        ours=ours, comparisons=compare(obj, ours), wall_s=time.perf_counter() - t0)


def run_realworld(objects: Sequence[RealWorldObject], root: Path, device: Device = "cpu", priors_only: bool = False,
                  on_result: Callable[[ObjectReport], None] | None = None,
                  hollow_shell: bool = False) -> RealWorldReport:
    """Every object in turn (assets under `root`), against the local Prefect runtime."""
    sim = SimConfig(device=device)
    reports = []
    with cache.local_runtime():
        for obj in objects:
            r = run_object(obj, Path(root), sim, priors_only, hollow_shell)
            reports.append(r)
            if on_result is not None:
                on_result(r)
    return RealWorldReport(device=device, quality="draft", simulated=not priors_only, summary=summarise(reports),
                           objects=reports)
