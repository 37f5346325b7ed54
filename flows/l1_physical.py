"""L1 physical model flow: density + friction (Designer) -> mass model -> rigid probes in pybullet -> gates.

Reads an L0 asset directory, writes `physical.json` (the frozen PhysicalModel, probe metrics and gates),
`evidence/attempts.jsonl` (L1 lines) and `recordings/L1_*.rrd` into it. Each probe is a content-cached task.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import cache
from cache import cache_relative, cache_resolve
from contracts.agents import AgentConfig, StageOutcome, TargetBand, TargetBehaviour
from contracts.asset_dir import DEFAULT_KEEP, KeepTrials, PhysicalRecord
from contracts.errors import InputError
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, ProbeSpec
from contracts.stage import StageContract, StageProbes, load_contract
from flows.harness import run_harness
from flows.probe_tasks import probe_task, run_probes
from prefect import flow
from tasks.agents.intent import asset_material, asset_targets, concept_of, explicit_numbers
from tasks.agents.vocab import load_material_vocab
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset, load_l0
from tasks.physical.mass import MassCheck, mass_check
from tasks.physical.model import build_physical_model, mass_plausible
from tasks.probes.probe import ProbeContext
from tasks.probes.registry import by_kind, stage_probes
from tasks.probes.registry import probe as find_probe
from tasks.publish import copy_file_atomic

@dataclass(frozen=True)
class L1Plan:
    """What L1 starts from: target behaviour and priors, the material class and the mass check."""

    targets: TargetBehaviour
    material: str
    mass: MassCheck


def longest_extent_m(asset: L0Asset) -> float:
    """Longest side of the asset's bounding box [m] (the size a typical mass is scaled to)."""
    return float(np.max(asset.mesh.extents))


def l1_plan(asset: L0Asset, intent: str | None, contract: StageContract | None = None) -> L1Plan:
    """Priors (density, friction) from the asset's request (or the intent given) and its mass check: the material's
    density range x volume, and the typical mass of the concept L0 built when it has one (tasks.physical.mass)."""
    vocab = load_material_vocab()
    contract = contract or load_contract("L1")
    words = asset_targets(asset.record, intent, vocab)
    material = asset_material(asset.record, words, vocab)
    entry = vocab.materials[material]
    priors = {k: words.priors[k] for k in ("density_kg_per_m3", "ground_friction", "gripper_friction")
              if k in words.priors}
    rho = priors["density_kg_per_m3"]
    drange = entry.prior_ranges.get("density_kg_per_m3", (rho / 2, rho * 2))
    field = contract.field("density_kg_per_m3")
    mass = mass_check(float(np.sum(asset.volumes_m3)), longest_extent_m(asset), float(asset.mesh.area), material,
                      rho, drange, concept_of(asset.record), entry.shell_wall_thickness_m,
                      "density_kg_per_m3" in explicit_numbers(words.intent)[1], (field.low, field.high))
    priors["density_kg_per_m3"] = mass.density_kg_per_m3
    lo, hi = mass.band_kg
    bands = [TargetBand(metric="mass_kg", unit="kg", low=lo, high=hi, scale="log", source=mass.source)]
    targets = TargetBehaviour(bands=bands, priors=priors, matched_words=words.matched_words, intent=words.intent)
    return L1Plan(targets, material, mass)


def l1_targets(asset: L0Asset, intent: str | None) -> tuple[TargetBehaviour, str, tuple[float, float]]:
    """Priors, the material class and the density range the mass gate admits (l1_plan without the mass record)."""
    plan = l1_plan(asset, intent)
    return plan.targets, plan.material, plan.mass.density_range_kg_per_m3


def physical_from_values(asset: L0Asset, values: dict[str, float], category: str) -> PhysicalModel:
    """The PhysicalModel of a candidate's density and friction."""
    return build_physical_model(asset.particles_m, asset.volumes_m3, asset.spacing_m, values["density_kg_per_m3"],
                                values["ground_friction"], values["gripper_friction"], category)


def _mass_result(phys: PhysicalModel, density_range: tuple[float, float]) -> ProbeResult:
    """The mass model's observations (no simulation)."""
    ok = mass_plausible(phys.mass_kg, phys.density_kg_per_m3, density_range)
    return ProbeResult(spec=ProbeSpec(kind="mass"), sim_calls=0,
                       metrics={"mass_kg": phys.mass_kg, "mass_plausibility": float(ok), "volume_m3": phys.volume_m3})


def l1_runner(asset: L0Asset, contract: StageContract, category: str, density_range: tuple[float, float],
              recording_kinds: dict[str, str] | None = None):
    """The L1 probe runner: candidate values -> [mass, the contract's rigid probes] results (probes cached, one after
    another); recording_kinds, when given, collects each recording's probe kind (recording path -> ProbeSpec.kind)."""
    probes = stage_probes(contract)

    def run(values: dict[str, float], action: str) -> list[ProbeResult]:
        phys = physical_from_values(asset, values, category)
        ctx = ProbeContext(asset, contract, phys)
        results = [_mass_result(phys, density_range), *run_probes(probes, ctx, device=None)]
        if recording_kinds is not None:
            recording_kinds.update({r.recording: r.spec.kind for r in results if r.recording})
        return results

    return run


def _copy_recordings(outcome: StageOutcome, asset_dir: Path, kinds: dict[str, str],
                     keep: KeepTrials = DEFAULT_KEEP) -> tuple[list[str], dict[str, str]]:
    """The chosen candidate's probe recordings, named by their probe kind (kinds: recording path -> ProbeSpec.kind,
    as the runner saw them): copied into the asset's recordings/ folder under keep 'all', else left in the cache
    (#38: an asset a fleet can store). Returns (the asset's paths, asset name -> cache path of those left there)."""
    if outcome.best_iteration is None:
        return [], {}
    chosen = next(a for a in outcome.attempts if a.iteration == outcome.best_iteration)
    out, cached = [], {}
    for src in chosen.evidence.recordings:
        p = cache_resolve(src)
        if p.suffix == ".rrd" and p.is_file():
            dest = asset_dir / "recordings" / by_kind("L1", kinds[src]).recording_name()
            if keep != "all":
                dest.unlink(missing_ok=True)  # (an earlier run's copy, on a rerun of the layer)
                cached[str(dest.relative_to(asset_dir))] = cache_relative(p)
                continue
            copy_file_atomic(p, dest)  # a new file: a hard link of a working copy (tasks.publish) is never rewritten
            out.append(str(dest.relative_to(asset_dir)))
    return out, cached


def run_l1(asset_dir: Path, intent: str | None = None, agents: AgentConfig | None = None,
           contract: StageContract | None = None,
           keep: KeepTrials = DEFAULT_KEEP) -> tuple[PhysicalModel | None, StageOutcome]:
    """Run L1 on an L0 asset directory (the l1-physical flow against the local Prefect runtime); write physical.json;
    return the frozen model (None if L1 failed)."""
    with cache.local_runtime():
        return l1_physical(asset_dir, intent, agents, contract, keep)


@flow(name="l1-physical", validate_parameters=False, persist_result=False)
def l1_physical(asset_dir: Path, intent: str | None = None, agents: AgentConfig | None = None,
                contract: StageContract | None = None,
                keep: KeepTrials = DEFAULT_KEEP) -> tuple[PhysicalModel | None, StageOutcome]:
    """L1: priors and mass check, the harness stage over the rigid probes (a subflow), physical.json. keep: 'all'
    copies the chosen candidate's probe recordings into the asset; 'adopted' (the default) leaves them in the cache,
    physical.json naming each (cached_recordings)."""
    asset_dir = Path(asset_dir)
    asset = load_l0(asset_dir)
    contract = contract or load_contract("L1")
    plan = l1_plan(asset, intent, contract)
    targets, material = plan.targets, plan.material
    category = geometry_info(asset.record).category
    kinds: dict[str, str] = {}
    runner = l1_runner(asset, contract, category, plan.mass.density_range_kg_per_m3, kinds)
    outcome = run_harness(contract, runner, targets, agents=agents, record_dir=asset_dir)
    phys = physical_from_values(asset, outcome.values, category) if outcome.passed and outcome.values else None
    recordings, cached = _copy_recordings(outcome, asset_dir, kinds, keep) if phys is not None else ([], {})
    record = PhysicalRecord(
        passed=outcome.passed, status=outcome.status, message=outcome.message, material_class=material,
        intent=targets.intent, mass_check=plan.mass.model_dump(mode="json"), targets=targets, physical_model=phys,
        metrics=outcome.metrics, sim_calls=outcome.sim_calls, attempts=outcome.attempts_used, recordings=recordings,
        **({"cached_recordings": cached} if cached else {}))
    AssetDir(asset_dir).write_physical(record)
    return phys, outcome


def load_physical(asset_dir: Path) -> PhysicalModel:
    """The frozen L1 model of an asset directory (InputError when L1 has not run or failed): AssetDir's."""
    return AssetDir(asset_dir).physical_model()


def run_rigid_probe(kind: str, asset_dir: Path, rho: float | None = None, friction: float | None = None) -> ProbeResult:
    """Run one rigid probe of the L1 contract (place | drop | slide) on an asset, with its L1 model or overridden
    density/friction."""
    contract = load_contract("L1")
    kinds = StageProbes.of(contract).names()
    if kind not in kinds:
        raise InputError(f"unknown rigid probe '{kind}'; choose one of {', '.join(kinds)}")
    asset = load_l0(Path(asset_dir))
    if AssetDir(asset_dir).has("physical"):
        base = load_physical(Path(asset_dir))
        values = {"density_kg_per_m3": base.density_kg_per_m3, "ground_friction": base.ground_friction,
                  "gripper_friction": base.gripper_friction}
    else:
        values = dict(l1_targets(asset, None)[0].priors)
    if rho is not None:
        values["density_kg_per_m3"] = rho
    if friction is not None:
        values["ground_friction"] = friction
    for name, v in values.items():
        if not contract.field(name).contains(float(v)):
            f = contract.field(name)
            raise InputError(f"{name}={v} is outside the L1 contract's bounds [{f.low}, {f.high}] {f.unit}")
    phys = physical_from_values(asset, values, geometry_info(asset.record).category)
    probe = find_probe("L1", kind)
    with cache.local_runtime():
        return probe_task(probe)(**probe.inputs(ProbeContext(asset, contract, phys)))
