"""The arms of the three ablations on one case, each ending in a `contracts.evaluation.ArmResult`.

Independent physics tests (shared by every arm): the held-out L2 probes (compression at the contract's held-out strain,
drop from the held-out height, on the object and on the material's specimen) judged by the L2 hard gates they report,
the held-out target bands (measured on the specimen, as in L2), and the paper's drop protocol (5 s drop from a quarter height, plausibility metrics). Every probe is a cached task: a rerun costs hits.
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import cache
from contracts.agents import AgentConfig, TargetBehaviour
from contracts.evaluation import ArmResult, Condition, ConditionResult, SuiteCase
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.request import AssetRequest
from contracts.sim import SimConfig
from contracts.stage import load_contract
from flows import l0_geometry, l1_physical, l2_material, l3_manipulation, renders
from flows.harness import probe_cache_key, run_harness
from flows.probe_tasks import probe_task
from tasks.agents.orchestrator import initial_values
from tasks.asset_dir import AssetDir, geometry_info
from tasks.evaluation.arms import (
    copy_asset, finite_labels, flat_result, fresh_dir, full_result, held_out_tests, manipulation_not_delivered,
    no_feedback_result, one_shot_missing, one_shot_result,
)
from tasks.evaluation.flat import flat_contract, split_values
from tasks.geometry.outputs import load_l0
from tasks.manipulation import context as l3_context
from tasks.physical.plan import l1_targets, physical_from_values
from tasks.probes.l2_record import l2_metrics
from tasks.probes.registry import stage_probes


def physics_tests(asset_dir: Path, physical: PhysicalModel, material: Material, targets: TargetBehaviour,
                  sim: SimConfig, videos: bool = False) -> dict[str, Any]:
    """Held-out probes + gates + targets and the drop protocol of one (physical, material) on an asset's L0."""
    l2 = load_contract("L2")
    asset = load_l0(asset_dir)
    keys, probes = {}, []
    with cache.local_runtime():
        for probe in stage_probes(l2, held_out=True):
            kw = l2_material.probe_inputs(probe.name, asset, physical, material, l2, sim, True)
            keys[f"l2.{probe.name}.held_out"] = probe_cache_key(probe_task(probe), kw)
            probes.append(probe_task(probe)(**kw))
        if videos:
            protocol = renders.render_drop_protocol(asset_dir, physical, material, sim)
        else:
            _, protocol = renders.protocol_states(asset.particles_m, asset.volumes_m3, physical, material, sim)
    keys["renders.drop_protocol"] = probe_cache_key(renders.drop_protocol_task, {
        "positions_m": asset.particles_m, "volumes_m3": asset.volumes_m3, "physical": physical, "material": material,
        "sim": sim})
    return held_out_tests(probes, l2_metrics(probes, l2), protocol, l2, targets, keys)


# -- the hierarchy (ours in A and B) -----------------------------------------------------------------------------------
def run_hierarchical(case: SuiteCase, request: AssetRequest, l0: Any, arm_dir: Path, sim: SimConfig,
                     agents: AgentConfig | None, videos: bool = True) -> dict[str, Any]:
    """L0 (given) -> L1 harness -> L2 harness (screening first) -> independent tests, in arm_dir."""
    fresh_dir(arm_dir)
    l0_geometry.write_l0(l0, arm_dir, extra={"request": request.model_dump(mode="json")})
    physical, o1 = l1_physical.run_l1(arm_dir, request.material_intent or request.text, agents)
    out: dict[str, Any] = {"asset_dir": str(arm_dir), "l1_passed": physical is not None, "l1_sim_calls": o1.sim_calls,
                           "l1_attempts": o1.attempts_used, "physical": physical, "material": None, "tests": None}
    if physical is None:
        out["error"] = f"L1: {o1.message}"
        return out
    material, o2 = l2_material.run_l2(arm_dir, request, agents, sim=sim, physical=physical)
    sel = AssetDir(arm_dir).material().selection
    out.update({"l2_passed": material is not None, "material": material,
                "l2_sim_calls": sel.sim_calls + int(sel.screening["sim_calls"]),
                "l2_attempts": o2.attempts_used, "targets": l2_material.l2_targets(load_l0(arm_dir), request)})
    if material is None:
        out["error"] = f"L2: {o2.message}"
        return out
    out["tests"] = physics_tests(arm_dir, physical, material, out["targets"], sim, videos=videos)
    return out


# -- A: flat ------------------------------------------------------------------------------------------------------------
def run_flat(case: SuiteCase, request: AssetRequest, l0: Any, arm_dir: Path, sim: SimConfig,
             agents: AgentConfig | None, wall0: float) -> ArmResult:
    """One joint harness stage over L1 + L2 fields, then the same independent tests."""
    fresh_dir(arm_dir)
    l0_geometry.write_l0(l0, arm_dir, extra={"request": request.model_dump(mode="json")})
    asset = load_l0(arm_dir)
    l1c, l2c = load_contract("L1"), load_contract("L2")
    contract = flat_contract(l1c, l2c)
    t1, _, drange = l1_targets(asset, request.material_intent or request.text)
    t2 = l2_material.l2_targets(asset, request)
    targets = TargetBehaviour(bands=[*t1.bands, *t2.bands], priors={**t2.priors, **t1.priors},
                              matched_words=t2.matched_words, intent=t2.intent)
    category = geometry_info(asset.record).category
    start1 = initial_values(l1c, t1, None)
    prior_phys = physical_from_values(asset, start1, category)
    with cache.local_runtime():  # the same screening tool, at the prior density (nothing is frozen yet)
        start2, screening = l2_material.screen(asset, prior_phys, l2c, t2, initial_values(l2c, t2, None), sim)
    rigid = l1_physical.l1_runner(asset, l1c, category, drange)

    def runner(values: dict[str, float], action: str) -> list:
        v1, v2 = split_values(values, l1c, l2c)
        phys = physical_from_values(asset, v1, category)
        return [*rigid(v1, action), *l2_material._Runner(asset, phys, l2c, sim)(v2, action)]

    outcome = run_harness(contract, runner, targets, agents=agents, record_dir=arm_dir, initial={**start1, **start2})
    calls = outcome.sim_calls + int(screening["sim_calls"])
    h: dict[str, Any] = {"asset_dir": str(arm_dir), "material": None, "physical": None, "tests": None}
    if outcome.passed and outcome.values:
        v1, v2 = split_values(outcome.values, l1c, l2c)
        h["physical"] = physical_from_values(asset, v1, category)
        h["material"] = Material(**v2)
        h["tests"] = physics_tests(arm_dir, h["physical"], h["material"], t2, sim)
    record = {"status": outcome.status, "message": outcome.message, "attempts": outcome.attempts_used,
              "sim_calls": calls, "screening": screening, "values": outcome.values}
    (arm_dir / "flat.json").write_text(json.dumps(record, indent=2, sort_keys=True, default=str) + "\n")
    return flat_result(case, h, outcome.message, calls, time.perf_counter() - wall0)


# -- B: one-shot ----------------------------------------------------------------------------------------------------------
def run_one_shot(case: SuiteCase, request: AssetRequest, h: dict[str, Any], sim: SimConfig,
                 wall0: float) -> ArmResult:
    """The initial material proposal (priors) kept: the selection probes once, then the same independent tests."""
    if h.get("physical") is None:
        return one_shot_missing(case, h, time.perf_counter() - wall0)
    asset_dir = Path(h["asset_dir"])
    l2c = load_contract("L2")
    targets = l2_material.l2_targets(load_l0(asset_dir), request)
    material = Material(**initial_values(l2c, targets, None))
    ev = l2_material.evaluate_material(asset_dir, material, contract=l2c, sim=sim, held_out=False, physical=h["physical"])
    tests = physics_tests(asset_dir, h["physical"], material, targets, sim)
    return one_shot_result(case, h, material, ev, tests, l2c, time.perf_counter() - wall0)


# -- C: manipulation -------------------------------------------------------------------------------------------------------
def material_passes(asset_dir: Path, physical: PhysicalModel, material: Material, targets: TargetBehaviour,
                    sim: SimConfig) -> tuple[bool, dict[str, Any]]:
    """Material pass: the held-out L2 gates hold and the held-out targets are met."""
    t = physics_tests(asset_dir, physical, material, targets, sim)
    return bool(t["held_out_gates_ok"] and t["targets_met"]), t


def run_manipulation(case: SuiteCase, request: AssetRequest, h: dict[str, Any], base: Path,
                     conditions: list[Condition], sim: SimConfig, agents: AgentConfig | None,
                     quality: str) -> list[ArmResult]:
    """No feedback (the first plan under each held-out condition) vs Full (L3 harness, then the same conditions)."""
    if h.get("material") is None:
        return manipulation_not_delivered(case, h, conditions)
    src = Path(h["asset_dir"])
    targets = l2_material.l2_targets(load_l0(src), request)
    held = tuple((c.target_xy_m[0], c.target_xy_m[1], c.initial_yaw_deg) for c in conditions)
    opts = l3_context.L3Options(device=sim.device) if quality == "draft" else l3_context.L3Options.standard(sim.device)
    opts = replace(opts, held_out=held)
    l3c = load_contract("L3")
    base_ok, base_tests = material_passes(src, h["physical"], h["material"], targets, sim)
    results = []
    # no feedback: the first plan, the L2 material, one trial per condition, nothing revised
    t0 = time.perf_counter()
    nf_dir = base / "no_feedback"
    copy_asset(src, nf_dir)
    ctx = l3_manipulation.load_context(nf_dir, opts, l3c)
    start = l3_context.initial_values(ctx)
    conds = []
    with cache.local_runtime():
        for c in conditions:
            r = ctx.trial(dict(start), "held_out", "no_feedback", target_xy_m=c.target_xy_m, yaw_deg=c.initial_yaw_deg)
            conds.append(ConditionResult(condition=c, task_success=l3_context.accepted(r.metrics, l3c), material_pass=base_ok,
                                         labels=finite_labels(r.metrics), cache_key=r.cache_key, attempt=r.recording))
    results.append(no_feedback_result(case, h, conds, nf_dir, base_tests, start, time.perf_counter() - t0))
    # full: L3 with action / numerical / material revision, then the held-out conditions on the accepted plan
    t0 = time.perf_counter()
    full_dir = base / "full"
    copy_asset(src, full_dir)
    _, outcome = l3_manipulation.run_l3(full_dir, opts, agents, l3c)
    record = AssetDir(full_dir).manipulation()
    final = AssetDir(full_dir).adopted_material().material  # L2's, or the revision L3 passed with
    ok, tests = (base_ok, base_tests) if final == h["material"] else material_passes(
        full_dir, h["physical"], final, targets, sim)
    results.append(full_result(case, conditions, record, ok, tests, outcome.status, full_dir,
                               time.perf_counter() - t0))
    return results
