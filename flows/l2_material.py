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

import math
from pathlib import Path
from typing import Any

import numpy as np

import cache
from cache import cache_resolve, cached_task
from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig, StageOutcome, TargetBehaviour
from contracts.asset_dir import MATERIAL_JSON, HeldOutSummary, MaterialRecord, SelectionSummary
from contracts.errors import ContractError, InputError
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, not_measured_reason
from contracts.request import AssetRequest
from contracts.sim import SimConfig
from contracts.stage import L2Parameters, StageContract, load_contract
from flows.harness import run_harness
from flows.probe_tasks import probe_task, run_probes
from prefect import flow
from tasks.agents.intent import asset_targets
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset, load_l0
from tasks.probes.probe import Probe, ProbeContext
from tasks.probes.registry import by_kind, stage_probes
from tasks.probes.registry import probe as find_probe
from tasks.probes.rollout import DeformableBody, plan_batches, rollouts
from tasks.probes.workers import probe_workers
from tasks.publish import copy_file_atomic, write_text_atomic

TASK_VERSION = "2"  # the screening task's; each probe's own version is in its module (tasks/probes/deformable_probes/)
OBJECT_VIEW_KINDS = ("compress", "drop")  # object probes whose non-gate metrics are reported as object_<name>
SCREEN_SCHEDULE = "auto"  # how object candidates share rollouts (tasks.probes.rollout.plan_batches)
SPECIMEN_SCREEN_SCHEDULE = "batch"  # the screening's three specimen candidates in one lock-step rollout
SCREEN_KEEP_MARGIN = 0.1  # a start value is kept when its metric is inside its band less 10 % of the width at each end


# -- the probes: registered in tasks/probes/deformable_probes/, listed in the contract's parameters.probes -----------
def l2_probe(kind: str) -> Probe:
    """The registered L2 probe `kind` (InputError naming the known ones)."""
    try:
        return find_probe("L2", kind)
    except ContractError as exc:
        raise InputError(f"unknown deformable probe '{kind}': {exc}") from None


@cached_task(version=TASK_VERSION, name="l2.screen")
def screen_task(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, kind: str,
                materials: list[Material], params: dict[str, float], sim: SimConfig,
                schedule: str = SCREEN_SCHEDULE) -> list[ProbeResult]:
    """Several candidate materials of one probe, scheduled by `schedule` (tasks.probes.rollout.plan_batches);
    screen_rollouts() counts the simulation calls."""
    batch = l2_probe(kind).batch
    if batch is None:
        raise InputError(f"the probe '{kind}' cannot screen several materials at once")
    return batch(positions_m, volumes_m3, physical, materials, params, sim, False, schedule)


# -- inputs ----------------------------------------------------------------------------------------------------------
def probe_parameters(contract: StageContract) -> dict[str, float]:
    """The contract's probe settings (selection and held-out)."""
    p = L2Parameters.of(contract)
    return {"strain": p.compression_strain, "strain_held_out": p.compression_strain_held_out,
            "height_fraction": p.drop_height_fraction_of_height,
            "height_fraction_held_out": p.drop_height_fraction_held_out,
            "stability_duration_s": p.stability_duration_s,
            "specimen_particles_per_axis": float(p.specimen_particles_per_axis)}


def specimen_arrays(physical: PhysicalModel, contract: StageContract,
                    kind: str = "specimen_compress") -> tuple[np.ndarray, np.ndarray]:
    """A specimen probe's rest positions [m] and volumes [m^3] at the object's particle spacing (its module's inputs:
    the cube for the compression, the ball inscribed in it for the drop)."""
    kw = l2_probe(kind).inputs(ProbeContext(asset=None, contract=contract, physical=physical))
    return kw["positions_m"], kw["volumes_m3"]


def object_view(results: list[ProbeResult], contract: StageContract) -> list[ProbeResult]:
    """The object's compression / drop metrics renamed object_<name> except the hard-gate ones: the band metrics come
    from the specimen (the object's effective modulus is its structure's, e.g. 0.024 x E for a dog on four legs).
    Idempotent: a result already in this view is returned as it is."""
    gates = {g.metric for g in contract.hard_gates}
    out = []
    for r in results:
        if r.spec.kind in OBJECT_VIEW_KINDS:
            r = r.model_copy(update={"metrics": {(k if k in gates or k.startswith("object_") else f"object_{k}"): v
                                                 for k, v in r.metrics.items()}})
        out.append(r)
    return out


def l2_metrics(results: list[ProbeResult], contract: StageContract) -> dict[str, float]:
    """One metrics dict of L2 probes (object view + specimen), each gate metric at its worst (merge_metrics)."""
    from tasks.agents import merge_metrics

    return merge_metrics(object_view(results, contract), contract)


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


def physical_for(asset_dir: Path, asset: L0Asset, rho: float | None = None) -> PhysicalModel:
    """The asset's L1 model, else one from the intent's priors (probing before L1 ran); rho overrides the density."""
    from tasks.physical import build_physical_model

    if AssetDir(asset_dir).has("physical"):
        phys = load_physical_model(asset_dir)
    else:
        from flows.l1_physical import l1_targets

        pri = l1_targets(asset, None)[0].priors  # L1's start values, mass check included
        phys = build_physical_model(asset.particles_m, asset.volumes_m3, asset.spacing_m,
                                    float(pri["density_kg_per_m3"]), float(pri["ground_friction"]),
                                    float(pri["gripper_friction"]), geometry_info(asset.record).category)
    if rho is None:
        return phys
    if not (math.isfinite(rho) and rho > 0):
        raise InputError(f"density must be a positive finite number of kg/m^3, got {rho}")
    return phys.model_copy(update={"density_kg_per_m3": float(rho), "mass_kg": float(rho) * phys.volume_m3})


# -- harness pieces --------------------------------------------------------------------------------------------------
class _Runner:
    """The L2 Prober: every selection probe of one candidate as cached tasks; counts simulation calls and misses."""

    def __init__(self, asset: L0Asset, physical: PhysicalModel, contract: StageContract, sim: SimConfig) -> None:
        self.asset, self.physical, self.contract, self.sim = asset, physical, contract, sim
        self.recording_kinds: dict[str, str] = {}  # recording path -> ProbeSpec.kind of every probe it ran

    def __call__(self, values: dict[str, float], action: str) -> list[ProbeResult]:
        ctx = ProbeContext(self.asset, self.contract, self.physical, Material(**values), self.sim)
        probes = stage_probes(self.contract)
        out = run_probes(probes, ctx, probe_workers(len(probes), self.sim.device))
        self.recording_kinds.update({r.recording: r.spec.kind for r in out if r.recording})
        return object_view(out, self.contract)


def _fit_log(xs: list[float], ys: list[float], target: float, log_x: bool) -> float | None:
    """x where the least-squares line through (x or log x, log y) reaches log target (None if flat or undefined)."""
    pts = [(math.log(x) if log_x else x, math.log(y)) for x, y in zip(xs, ys) if y > 0 and (x > 0 or not log_x)]
    if len(pts) < 2:
        return None
    a, b = np.polyfit([p[0] for p in pts], [p[1] for p in pts], 1)
    if abs(a) < 1e-9:
        return None
    u = (math.log(target) - b) / a
    return math.exp(u) if log_x else u


def _start_in_band(start: float, xs: list[float], results: list[ProbeResult], metric: str, band: Any,
                   margin: float = SCREEN_KEEP_MARGIN) -> bool:
    """True when the start value was screened and its metric lies inside the band less `margin` at each end: the
    screening then keeps the start value instead of aiming at the band's centre (the least change that meets the
    target; a centre the solver cannot reach, e.g. a rebound of 0.6 for rubber, would otherwise drive the value to
    its bound)."""
    i = next((k for k, x in enumerate(xs) if math.isclose(x, start, rel_tol=1e-12, abs_tol=1e-15)), None)
    return i is not None and band.contains_inner(results[i].metrics.get(metric), margin)


def screen_moduli(values: dict[str, float], field: Any) -> list[float]:
    """Young's moduli the screening compresses: 1/3, 1 and 3 x the start value, clamped into the field [Pa]."""
    return [min(max(values["youngs_modulus_pa"] * k, field.low), field.high) for k in (1 / 3, 1.0, 3.0)]


def screen_dampings(values: dict[str, float], field: Any) -> list[float]:
    """Damping rates the screening drops: 0.25, 1 and 2.5 x the start value + 2, clamped, distinct, sorted [1/s]."""
    d0 = values["damping_rate_per_s"]
    return sorted({min(max(d, field.low), field.high) for d in (0.25 * d0, d0, 2.5 * d0 + 2.0)})


def screen_rollouts(physical: PhysicalModel, positions_m: np.ndarray, volumes_m3: np.ndarray,
                    materials: list[Material], sim: SimConfig, results: list[ProbeResult],
                    schedule: str = SCREEN_SCHEDULE) -> int:
    """Simulation calls of one screen_task: one per rollout (a batch of 3 is 1; 3 candidates one after another are 3)."""
    body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
    return rollouts(plan_batches(body, materials, sim, schedule), results)


def screen(asset: L0Asset, physical: PhysicalModel, contract: StageContract, targets: TargetBehaviour,
           start: dict[str, float], sim: SimConfig) -> tuple[dict[str, float], dict[str, Any]]:
    """Screening on the material's specimen: compress three stiffnesses, drop three damping rates (each set in one
    lock-step rollout, SPECIMEN_SCREEN_SCHEDULE); keep a start value whose metric is already well inside its band
    (_start_in_band), else interpolate the value that hits the band's centre. Returns (initial values, summary)."""
    p = probe_parameters(contract)
    fields = {f.name: f for f in contract.editable_fields}
    base = {"physical": physical, "sim": sim, "schedule": SPECIMEN_SCREEN_SCHEDULE}
    values = dict(start)
    summary: dict[str, Any] = {"sim_calls": 0}
    band = targets.band("effective_modulus_pa")
    if band is not None:
        f = fields["youngs_modulus_pa"]
        es = screen_moduli(values, f)
        mats = [Material(youngs_modulus_pa=e, poisson_ratio=values["poisson_ratio"],
                         damping_rate_per_s=values["damping_rate_per_s"]) for e in es]
        pos, vol = specimen_arrays(physical, contract, "specimen_compress")
        rs = screen_task(positions_m=pos, volumes_m3=vol, kind="specimen_compress", materials=mats,
                         params={"strain": p["strain"]}, **base)
        ok = [(e, r.metrics["effective_modulus_pa"]) for e, r in zip(es, rs) if "effective_modulus_pa" in r.metrics]
        kept = _start_in_band(values["youngs_modulus_pa"], es, rs, "effective_modulus_pa", band)
        guess = None if kept else _fit_log([e for e, _ in ok], [m for _, m in ok], band.center, log_x=True)
        if guess is not None:
            values["youngs_modulus_pa"] = min(max(guess, f.low), f.high)
        calls = screen_rollouts(physical, pos, vol, mats, sim, rs, SPECIMEN_SCREEN_SCHEDULE)
        summary["compress"] = {"youngs_modulus_pa": es, "effective_modulus_pa": [r.metrics.get("effective_modulus_pa")
                                                                                for r in rs], "sim_calls": calls,
                               "kept_start": kept}
        summary["sim_calls"] += calls
    band = targets.band("rebound_ratio")
    if band is not None:
        f = fields["damping_rate_per_s"]
        ds = screen_dampings(values, f)
        mats = [Material(youngs_modulus_pa=values["youngs_modulus_pa"], poisson_ratio=values["poisson_ratio"],
                         damping_rate_per_s=d) for d in ds]
        pos, vol = specimen_arrays(physical, contract, "specimen_drop")
        rs = screen_task(positions_m=pos, volumes_m3=vol, kind="specimen_drop", materials=mats,
                         params={"height_fraction": p["height_fraction"]}, **base)
        ok = [(d, r.metrics["rebound_ratio"]) for d, r in zip(ds, rs) if "rebound_ratio" in r.metrics]
        aim = max(band.center, 1e-3)
        kept = _start_in_band(values["damping_rate_per_s"], ds, rs, "rebound_ratio", band)
        guess = None if kept else _fit_log([d for d, _ in ok], [max(rb, 1e-3) for _, rb in ok], aim, log_x=False)
        if guess is not None:
            values["damping_rate_per_s"] = min(max(guess, f.low), f.high)
        calls = screen_rollouts(physical, pos, vol, mats, sim, rs, SPECIMEN_SCREEN_SCHEDULE)
        summary["drop"] = {"damping_rate_per_s": ds, "rebound_ratio": [r.metrics.get("rebound_ratio") for r in rs],
                           "sim_calls": calls, "kept_start": kept}
        summary["sim_calls"] += calls
    summary["initial"] = dict(values)
    return values, summary


def _copy(src: str | None, dest: Path) -> str | None:
    """Copy a recording into the asset; returns its path relative to the asset directory."""
    if not src or not cache_resolve(src).is_file():
        return None
    copy_file_atomic(cache_resolve(src), dest)  # a new file: a hard link of a working copy is never rewritten
    return str(Path("recordings") / dest.name)


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
           screen_first: bool = True) -> tuple[Material | None, StageOutcome]:
    """Run L2 on an asset directory holding L0 (+ L1 physical.json, or `physical` given): the l2-material flow against
    the local Prefect runtime; write material.json."""
    with cache.local_runtime():
        return l2_material(asset_dir, request_or_intent, agents, contract, sim, physical, screen_first)


@flow(name="l2-material", validate_parameters=False, persist_result=False)
def l2_material(asset_dir: Path, request_or_intent: AssetRequest | str | None = None,
                agents: AgentConfig | None = None, contract: StageContract | None = None, sim: SimConfig | None = None,
                physical: PhysicalModel | None = None, screen_first: bool = True) -> tuple[Material | None, StageOutcome]:
    """L2: targets, the screening (cached tasks), the harness stage over the MPM probes (a subflow), the held-out
    tests of the chosen material, material.json."""
    asset_dir = Path(asset_dir)
    asset = load_l0(asset_dir)
    physical = physical or load_physical_model(asset_dir)
    contract = contract or load_contract("L2")
    sim = sim or SimConfig()
    targets = l2_targets(asset, request_or_intent)
    from tasks.agents.orchestrator import initial_values

    start = initial_values(contract, targets, None)
    initial, screening = (screen(asset, physical, contract, targets, start, sim) if screen_first
                          else (start, {"sim_calls": 0}))
    runner = _Runner(asset, physical, contract, sim)
    outcome = run_harness(contract, runner, targets, agents=agents, record_dir=asset_dir, initial=initial)
    material = Material(**outcome.values) if outcome.passed and outcome.values else None
    recordings: dict[str, str | None] = {}
    held: list[ProbeResult] = []
    if material is not None:
        chosen = next(a for a in outcome.attempts if a.iteration == outcome.best_iteration)
        for src in chosen.evidence.recordings:
            kind = runner.recording_kinds[src]
            recordings[kind] = _copy(src, asset_dir / "recordings" / by_kind("L2", kind).recording_name())
        held = held_out_probes(asset, physical, material, contract, sim)
        for p, r in zip(stage_probes(contract, held_out=True), held):
            recordings[f"{p.kind}_held_out"] = _copy(r.recording, asset_dir / "recordings" / p.recording_name(True))
    held_metrics = l2_metrics(held, contract) if held else {}
    held_targets = targets.model_copy(update={"bands": [b for b in targets.bands if b.metric in held_metrics]})
    sim_calls = outcome.sim_calls + int(screening["sim_calls"]) + sum(r.sim_calls for r in held)
    record = MaterialRecord(  # no wall time: reruns must be content-identical
        passed=outcome.passed, status=outcome.status, message=outcome.message, intent=targets.intent, targets=targets,
        material=material, physical_model=physical, metrics=outcome.metrics,
        not_measured={m: not_measured_reason(m, outcome.metrics) for m in targets.not_measured(outcome.metrics)},
        held_out=HeldOutSummary(metrics=held_metrics, targets_met=held_targets.met(held_metrics) if held else None,
                                score=held_targets.score(held_metrics) if held else None,
                                bands=[b.metric for b in held_targets.bands],
                                probes=[r.model_dump(mode="json", exclude={"wall_time_s"}) for r in held]),
        selection=SelectionSummary(
            status=outcome.status, score=outcome.score, targets_met=targets.met(outcome.metrics),
            best_iteration=outcome.best_iteration, attempts=outcome.attempts_used, sim_calls=outcome.sim_calls,
            screening=screening,
            ranking=sorted(({"iteration": a.iteration, "values": a.proposal, "score": a.score, "verdict": a.verdict}
                            for a in outcome.attempts if a.score is not None), key=lambda d: -d["score"])),
        sim_calls=sim_calls, recordings=recordings)
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


__all__ = ["MATERIAL_JSON", "evaluate_material", "l2_material", "l2_metrics",
           "l2_probe", "l2_revalidation", "l2_targets", "load_material", "object_view", "probe_inputs", "run_l2",
           "run_probe",
           "screen", "specimen_arrays"]
