"""L2 material flow: intent -> targets -> batched screening -> harness (cached MPM probes) -> held-out -> material.json.

The L0 particles and the frozen L1 model are read from the asset directory and never edited. Each probe is a
content-cached task keyed by (particles, physical model, material, probe settings, numerics), so a material set from
outside (as L3 does) re-executes exactly the L2 probes. Held-out tests (the contract's other strain and drop height)
run only on the selected material and are stored apart from the selection metrics.

The target bands (effective modulus, recovery, rebound) are material properties, so they are measured on a specimen
of the material (tasks.probes.specimen: a cube at the object's spacing, density and friction) by the same compression
and drop probes; the screening runs on the specimen too. The object's own probes (compress, drop, lift, stability)
are the structural checks: their hard-gate metrics count, and their other compression / drop metrics are reported as
``object_<name>`` (object_effective_modulus_pa is the structure's stiffness, not the material's).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


import cache
from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig, StageOutcome, TargetBehaviour
from contracts.asset_dir import DEFAULT_KEEP, MATERIAL_JSON, KeepTrials
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.request import AssetRequest
from contracts.sim import SimConfig
from contracts.stage import StageContract, load_contract
from flows.harness import run_harness
from flows.probe_tasks import probe_task, run_probes
from prefect import flow
from tasks.agents.intent import asset_material, asset_targets, concept_of
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import L0Asset, load_l0
from tasks.physical.plan import physical_for
from tasks.probes.l2_record import l2_metrics, material_record, object_view
from tasks.probes.probe import ProbeContext
from tasks.probes.registry import by_kind, stage_probes
from tasks.probes.screening import (l2_probe, probe_parameters, screen, screen_dampings, screen_moduli,
                                    specimen_arrays)
from tasks.probes.workers import probe_workers
from tasks.realworld.inflation import shell_inflation
from tasks.realworld.loss import material_loss
from tasks.publish import write_text_atomic
from tasks.record.keep import keep_recording
from tasks.agents.orchestrator import initial_values

# -- the probes: registered in tasks/probes/deformable_probes/, listed in the contract's parameters.probes; the
# screening and its cached task: tasks/probes/screening.py ------------------------------------------------------------
# -- inputs ----------------------------------------------------------------------------------------------------------
def probe_inputs(kind: str, asset: L0Asset, physical: PhysicalModel, material: Material, contract: StageContract,
                 sim: SimConfig, held_out: bool = False) -> dict[str, Any]:
    """Keyword inputs of one probe task (what its cache key is made of): the probe module's `inputs`."""
    return l2_probe(kind).inputs(ProbeContext(asset, contract, physical, material, sim, held_out))


def intent_text(asset: L0Asset, intent: str | None) -> str:
    """The words the material comes from: the given intent, else the request L0 stored (its material intent or text),
    else the name L0 recorded (tasks.agents.intent.asset_targets)."""
    return asset_targets(asset.record, intent).intent


def l2_targets(asset: L0Asset, request_or_intent: AssetRequest | str | None) -> TargetBehaviour:
    """Target bands and priors from a request (material_intent / text / overrides), an intent string, or (None) the
    request L0 stored in the asset; the concept L0 built gives the material when the words name none."""
    return asset_targets(asset.record, request_or_intent)


def load_physical_model(asset_dir: Path) -> PhysicalModel:
    """The frozen L1 model of the asset (tasks.asset_dir.AssetDir.physical_model)."""
    return AssetDir(asset_dir).physical_model()


# -- harness pieces --------------------------------------------------------------------------------------------------
class _Runner:
    """The L2 Prober: every selection probe of one candidate as cached tasks; counts simulation calls and misses."""

    def __init__(self, asset: L0Asset, physical: PhysicalModel, contract: StageContract, sim: SimConfig,
                 fixed: dict[str, float] | None = None) -> None:
        self.asset, self.physical, self.contract, self.sim = asset, physical, contract, sim
        self.fixed = dict(fixed or {})  # material fields L2 sets but does not edit (the class's viscosity)
        self.recording_kinds: dict[str, str] = {}  # recording path -> ProbeSpec.kind of every probe it ran

    def __call__(self, values: dict[str, float], action: str) -> list[ProbeResult]:
        ctx = ProbeContext(self.asset, self.contract, self.physical, Material(**{**values, **self.fixed}), self.sim)
        probes = stage_probes(self.contract)
        out = run_probes(probes, ctx, probe_workers(len(probes), self.sim.device))
        self.recording_kinds.update({r.recording: r.spec.kind for r in out if r.recording})
        return object_view(out, self.contract)


def held_out_probes(asset: L0Asset, physical: PhysicalModel, material: Material, contract: StageContract,
                    sim: SimConfig) -> list[ProbeResult]:
    """The held-out tests of one material (the contract's held-out probes, in its order; cached tasks, run side by side
    on the CPU)."""
    probes = stage_probes(contract, held_out=True)
    ctx = ProbeContext(asset, contract, physical, material, sim, held_out=True)
    return run_probes(probes, ctx, probe_workers(len(probes), sim.device), keys=False)


def evaluate_material(asset_dir: Path, material: Material, contract: StageContract | None = None,
                      sim: SimConfig | None = None, held_out: bool = True,
                      physical: PhysicalModel | None = None, asset: L0Asset | None = None) -> dict[str, Any]:
    """Probe a material given from outside (as L3 does): the l2-revalidation flow against the local Prefect runtime.
    asset: the L0 data when the caller has it loaded (else read from asset_dir)."""
    with cache.local_runtime():
        return l2_revalidation(asset_dir, material, contract, sim, held_out, physical, asset)


@lean_flow(name="l2-revalidation", validate_parameters=False, persist_result=False)  # the L0 data: by name
def l2_revalidation(asset_dir: Path, material: Material, contract: StageContract | None = None,
                    sim: SimConfig | None = None, held_out: bool = True,
                    physical: PhysicalModel | None = None, asset: L0Asset | None = None) -> dict[str, Any]:
    """L2's selection probes and (held_out) held-out tests of a material set from outside, cached: called from L3's
    material revision, a subflow of l3-manipulation."""
    asset_dir = Path(asset_dir)
    asset = asset if asset is not None else load_l0(asset_dir)
    physical = physical or load_physical_model(asset_dir)
    contract = contract or load_contract("L2")
    sim = sim or SimConfig()
    sel = _Runner(asset, physical, contract, sim)(material.model_dump(), "propose_material")
    ho = held_out_probes(asset, physical, material, contract, sim) if held_out else []
    return {"material": material, "selection": sel, "held_out": ho, "metrics": l2_metrics(sel, contract),
            "held_out_metrics": l2_metrics(ho, contract) if ho else {}}


def run_l2(asset_dir: Path, request_or_intent: AssetRequest | str | None = None, agents: AgentConfig | None = None,
           contract: StageContract | None = None, sim: SimConfig | None = None, physical: PhysicalModel | None = None,
           screen_first: bool = True, keep: KeepTrials = DEFAULT_KEEP) -> tuple[Material | None, StageOutcome]:
    """Run L2 on an asset directory holding L0 (+ L1 physical.json, or `physical` given): the l2-material flow against
    the local Prefect runtime; write material.json."""
    with cache.local_runtime():
        return l2_material(asset_dir, request_or_intent, agents, contract, sim, physical, screen_first, keep)


@flow(name="l2-material", validate_parameters=False, persist_result=False)
def l2_material(asset_dir: Path, request_or_intent: AssetRequest | str | None = None,
                agents: AgentConfig | None = None, contract: StageContract | None = None, sim: SimConfig | None = None,
                physical: PhysicalModel | None = None, screen_first: bool = True,
                keep: KeepTrials = DEFAULT_KEEP) -> tuple[Material | None, StageOutcome]:
    """L2: targets, the screening (cached tasks), the harness stage over the MPM probes (a subflow), the held-out
    tests of the chosen material, material.json. keep: 'all' copies the chosen material's probe recordings into the
    asset; 'adopted' (the default) leaves them in the cache, material.json naming each (cached_recordings)."""
    asset_dir = Path(asset_dir)
    asset = load_l0(asset_dir)
    physical = physical or load_physical_model(asset_dir)
    contract = contract or load_contract("L2")
    sim = sim or SimConfig()
    targets = l2_targets(asset, request_or_intent)

    start = initial_values(contract, targets, None)
    # a pressurised ball built as its shell: its gas as a modulus added to the wall's (tasks.realworld.inflation), at the
    # start's nu; fixed through L2, in the object's probes and the loss calibration, never in a specimen's
    inflation = shell_inflation(getattr(asset, "body", None), float(start["poisson_ratio"]))  # stand-ins: none
    gas = {"gas_modulus_pa": float(inflation["gas_modulus_pa"])} if inflation else {}
    # a bouncy class's loss in the material: its prior restitution as a Kelvin-Voigt viscosity, calibrated on this
    # object's impact at the reference speed with the start E and nu (tasks.realworld.loss); fixed through L2
    # (the concept's own restitution when the lexicon gives one, a ball's rebound rule, at its rule's drop speed; the
    # record's "source" and "calibration_drop_m" say which)
    fixed, loss = material_loss(asset.particles_m, asset.volumes_m3, physical, Material(**start, **gas), targets.priors,
                                sim, concept_of(asset.record), asset_material(asset.record, targets))
    initial, screening = (screen(asset, physical, contract, targets, start, sim, fixed) if screen_first
                          else (start, dict[str, Any](sim_calls=0)))
    if loss:
        screening["restitution_loss"] = loss
        screening["sim_calls"] += int(float(loss.get("impacts", 1)))  # the calibration's impacts are simulation calls too
    runner = _Runner(asset, physical, contract, sim, {**fixed, **gas})
    outcome = run_harness(contract, runner, targets, agents=agents, record_dir=asset_dir, initial=initial)
    material = Material(**outcome.values, **fixed, **gas) if outcome.passed and outcome.values else None
    recordings: dict[str, str | None] = {}
    cached: dict[str, str] = {}  # keep 'adopted': the recordings left in the cache
    held: list[ProbeResult] = []
    if material is not None:
        chosen = next(a for a in outcome.attempts if a.iteration == outcome.best_iteration)
        for src in chosen.evidence.recordings:
            kind = runner.recording_kinds[src]
            recordings[kind] = keep_recording(src, asset_dir, by_kind("L2", kind).recording_name(), keep, cached)
        held = held_out_probes(asset, physical, material, contract, sim)
        for p, r in zip(stage_probes(contract, held_out=True), held):
            recordings[f"{p.kind}_held_out"] = keep_recording(r.recording, asset_dir, p.recording_name(True), keep,
                                                              cached)
    record = material_record(outcome, targets, material, physical, contract, screening, held, recordings, cached,
                             keep, inflation)
    (asset_dir / "evidence").mkdir(parents=True, exist_ok=True)
    lines = "".join(a.model_dump_json() + "\n" for a in outcome.attempts)
    write_text_atomic(asset_dir / "evidence" / "L2_attempts.jsonl", lines)
    AssetDir(asset_dir).write_material(record)
    return material, outcome


def load_material(asset_dir: Path) -> Material:
    """The L2 material of an asset directory (InputError when L2 has not run or found no valid material): AssetDir's."""
    return AssetDir(asset_dir).material_model()


def run_probe(kind: str, asset_dir: Path, material: Material, physical: PhysicalModel | None = None,
              sim: SimConfig | None = None, held_out: bool = False) -> ProbeResult:
    """Run one deformable probe (cached) on an asset with a given material."""
    asset_dir = Path(asset_dir)
    asset = load_l0(asset_dir)
    physical = physical or load_physical_model(asset_dir)
    contract = load_contract("L2")
    kw = probe_inputs(kind, asset, physical, material, contract, sim or SimConfig(), held_out)
    with cache.local_runtime():
        return probe_task(l2_probe(kind))(**kw)


__all__ = ["MATERIAL_JSON", "evaluate_material", "l2_material", "l2_revalidation", "l2_targets", "load_material",
           "probe_inputs", "run_l2", "run_probe",
           # the screening's, served here too (benchmarks/l2_schedule.py, eval_arms, tests): tasks/probes/screening.py
           "l2_probe", "probe_parameters", "screen", "screen_dampings", "screen_moduli", "specimen_arrays",
           # the physical model `deformsmith probe` runs a probe with: tasks/physical/plan.py
           "physical_for"]
