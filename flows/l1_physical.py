"""L1 physical model flow: density + friction (Designer) -> mass model -> rigid probes in pybullet -> gates.

Reads an L0 asset directory, writes `physical.json` (the frozen PhysicalModel, probe metrics and gates),
`evidence/attempts.jsonl` (L1 lines) and `recordings/L1_*.rrd` into it. Each probe is a content-cached task. The
priors, the mass check and a candidate's physical model: tasks.physical.plan.
"""

from __future__ import annotations

from pathlib import Path

import cache
from cache import cache_resolve
from contracts.agents import AgentConfig, StageOutcome
from contracts.asset_dir import DEFAULT_KEEP, KeepTrials, PhysicalRecord
from contracts.errors import InputError
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.stage import StageContract, StageProbes, load_contract
from flows.harness import run_harness
from flows.probe_tasks import probe_task, run_probes
from prefect import flow
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset, load_l0
from tasks.physical.plan import l1_plan, mass_result, physical_from_values, rigid_probe_values
from tasks.probes.probe import ProbeContext
from tasks.probes.registry import by_kind, stage_probes
from tasks.probes.registry import probe as find_probe
from tasks.record.keep import keep_recording


def l1_runner(asset: L0Asset, contract: StageContract, category: str, density_range: tuple[float, float],
              recording_kinds: dict[str, str] | None = None):
    """The L1 probe runner: candidate values -> [mass, the contract's rigid probes] results (probes cached, one after
    another); recording_kinds, when given, collects each recording's probe kind (recording path -> ProbeSpec.kind)."""
    probes = stage_probes(contract)

    def run(values: dict[str, float], action: str) -> list[ProbeResult]:
        phys = physical_from_values(asset, values, category)
        ctx = ProbeContext(asset, contract, phys)
        results = [mass_result(phys, density_range), *run_probes(probes, ctx, device=None)]
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
    out: list[str] = []
    cached: dict[str, str] = {}
    for src in chosen.evidence.recordings:
        if cache_resolve(src).suffix == ".rrd":
            kept = keep_recording(src, asset_dir, by_kind("L1", kinds[src]).recording_name(), keep, cached)
            out += [kept] if kept else []
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
    values = rigid_probe_values(contract, Path(asset_dir), asset, rho, friction)
    phys = physical_from_values(asset, values, geometry_info(asset.record).category)
    probe = find_probe("L1", kind)
    with cache.local_runtime():
        return probe_task(probe)(**probe.inputs(ProbeContext(asset, contract, phys)))
