"""The arms of the three ablations on one case, each ending in a `contracts.evaluation.ArmResult`.

Independent physics tests (shared by every arm): the held-out L2 probes (compression at the contract's held-out strain,
drop from the held-out height, on the object and on the material's specimen) judged by the L2 hard gates they report,
the held-out target bands (measured on the specimen, as in L2), and the paper's drop protocol (5 s drop from a quarter height, plausibility metrics). Every probe is a cached task: a rerun costs hits.
"""

from __future__ import annotations

import json
import shutil
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

import cache
from contracts.agents import AgentConfig, TargetBehaviour
from contracts.asset_dir import attempt_path
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
from tasks.evaluation.flat import flat_contract, split_values
from tasks.geometry.outputs import load_l0
from tasks.manipulation import context as l3_context
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
    held = l2_material.l2_metrics(probes, l2)
    gates = {g.name: bool(g.passes(held.get(g.metric))) for g in l2.hard_gates if g.metric in held}
    bands = [b for b in targets.bands if b.metric in held]
    ho_targets = targets.model_copy(update={"bands": bands})
    return {"held_out_metrics": held, "held_out_gates": gates, "held_out_gates_ok": all(gates.values()),
            "targets_met": ho_targets.met(held), "target_bands": {b.metric: [b.low, b.high] for b in bands},
            "protocol": protocol, "plausible": bool(protocol.get("plausible", 0.0) == 1.0),
            "sim_calls": sum(p.sim_calls for p in probes) + 1, "cache_keys": keys,
            "recordings": [p.recording for p in probes if p.recording]}


def _failures(tests: dict[str, Any] | None, selection_gates: dict[str, bool] | None = None) -> list[str]:
    """Hard-failure kinds: instability / implausible deformation from selection gates, held-out gates, protocol."""
    kinds = []
    for name, ok in (selection_gates or {}).items():
        if not ok:
            kinds.append(f"selection gate: {name}")
    if tests is not None:
        kinds += [f"held-out gate: {n}" for n, ok in tests["held_out_gates"].items() if not ok]
        p = tests["protocol"]
        if p.get("collapsed"):
            kinds.append("protocol: collapsed")
        if p.get("exploded"):
            kinds.append("protocol: exploded")
        if not tests["plausible"] and not p.get("collapsed") and not p.get("exploded"):
            kinds.append("protocol: implausible deformation")
    return kinds


def _metrics(tests: dict[str, Any] | None) -> dict[str, float]:
    """Flat float metrics of the independent tests for the record."""
    if tests is None:
        return {}
    out = {f"held_out.{k}": float(v) for k, v in tests["held_out_metrics"].items()}
    out.update({f"protocol.{k}": float(v) for k, v in tests["protocol"].items()})
    return out


# -- the hierarchy (ours in A and B) -----------------------------------------------------------------------------------
def run_hierarchical(case: SuiteCase, request: AssetRequest, l0: Any, arm_dir: Path, sim: SimConfig,
                     agents: AgentConfig | None, videos: bool = True) -> dict[str, Any]:
    """L0 (given) -> L1 harness -> L2 harness (screening first) -> independent tests, in arm_dir."""
    _fresh(arm_dir)
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


def hierarchy_result(case: SuiteCase, h: dict[str, Any], wall_s: float) -> ArmResult:
    """Ablation A, hierarchical arm."""
    delivered = h["material"] is not None
    t = h["tests"]
    return ArmResult(ablation="hierarchy", arm="hierarchical", case_id=case.id, case_kind=case.kind,
                     delivered=delivered, physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     failure_kinds=_failures(t) if delivered else [h.get("error") or "no asset"],
                     sim_calls=int(h.get("l1_sim_calls", 0)) + int(h.get("l2_sim_calls", 0)),
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=_metrics(t),
                     evidence=_evidence(h, ["physical.json", "material.json", "evidence/attempts.jsonl",
                                            "evidence/L2_attempts.jsonl", "renders/drop_front.mp4",
                                            "renders/drop_side.mp4"]),
                     asset_dir=h["asset_dir"], wall_s=wall_s, error=h.get("error"))


def harness_result(case: SuiteCase, h: dict[str, Any], wall_s: float) -> ArmResult:
    """Ablation B, harness arm (the same L2 run; construction calls of L2 alone)."""
    t = h["tests"]
    delivered = h["material"] is not None
    fails = _failures(t) if delivered else [h.get("error") or "no material"]
    return ArmResult(ablation="harness", arm="harness", case_id=case.id, case_kind=case.kind, delivered=delivered,
                     physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     target_satisfied=bool(t and t["held_out_gates_ok"] and t["targets_met"]),
                     hard_failure=bool(fails), failure_kinds=fails, sim_calls=int(h.get("l2_sim_calls", 0)),
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=_metrics(t),
                     evidence=_evidence(h, ["material.json", "evidence/L2_attempts.jsonl"]),
                     asset_dir=h["asset_dir"], wall_s=wall_s, error=h.get("error"))


def _evidence(h: dict[str, Any], files: list[str]) -> dict[str, Any]:
    """Cache keys and files behind a record."""
    t = h.get("tests") or {}
    root = Path(h["asset_dir"])
    return {"cache_keys": t.get("cache_keys", {}), "files": [f for f in files if (root / f).exists()],
            "recordings": sorted(str(p.relative_to(root)) for p in (root / "recordings").glob("*.rrd"))
            if (root / "recordings").is_dir() else [], "held_out_recordings": t.get("recordings", []),
            "material": h["material"].model_dump(mode="json") if h.get("material") else None,
            "physical": h["physical"].model_dump(mode="json") if h.get("physical") else None,
            "target_bands": t.get("target_bands")}


# -- A: flat ------------------------------------------------------------------------------------------------------------
def run_flat(case: SuiteCase, request: AssetRequest, l0: Any, arm_dir: Path, sim: SimConfig,
             agents: AgentConfig | None, wall0: float) -> ArmResult:
    """One joint harness stage over L1 + L2 fields, then the same independent tests."""
    _fresh(arm_dir)
    l0_geometry.write_l0(l0, arm_dir, extra={"request": request.model_dump(mode="json")})
    asset = load_l0(arm_dir)
    l1c, l2c = load_contract("L1"), load_contract("L2")
    contract = flat_contract(l1c, l2c)
    t1, _, drange = l1_physical.l1_targets(asset, request.material_intent or request.text)
    t2 = l2_material.l2_targets(asset, request)
    targets = TargetBehaviour(bands=[*t1.bands, *t2.bands], priors={**t2.priors, **t1.priors},
                              matched_words=t2.matched_words, intent=t2.intent)
    category = geometry_info(asset.record).category
    start1 = initial_values(l1c, t1, None)
    prior_phys = l1_physical.physical_from_values(asset, start1, category)
    with cache.local_runtime():  # the same screening tool, at the prior density (nothing is frozen yet)
        start2, screening = l2_material.screen(asset, prior_phys, l2c, t2, initial_values(l2c, t2, None), sim)
    rigid = l1_physical.l1_runner(asset, l1c, category, drange)

    def runner(values: dict[str, float], action: str) -> list:
        v1, v2 = split_values(values, l1c, l2c)
        phys = l1_physical.physical_from_values(asset, v1, category)
        return [*rigid(v1, action), *l2_material._Runner(asset, phys, l2c, sim)(v2, action)]

    outcome = run_harness(contract, runner, targets, agents=agents, record_dir=arm_dir, initial={**start1, **start2})
    calls = outcome.sim_calls + int(screening["sim_calls"])
    h: dict[str, Any] = {"asset_dir": str(arm_dir), "material": None, "physical": None, "tests": None}
    if outcome.passed and outcome.values:
        v1, v2 = split_values(outcome.values, l1c, l2c)
        h["physical"] = l1_physical.physical_from_values(asset, v1, category)
        h["material"] = Material(**v2)
        h["tests"] = physics_tests(arm_dir, h["physical"], h["material"], t2, sim)
    t = h["tests"]
    delivered = h["material"] is not None
    record = {"status": outcome.status, "message": outcome.message, "attempts": outcome.attempts_used,
              "sim_calls": calls, "screening": screening, "values": outcome.values}
    (arm_dir / "flat.json").write_text(json.dumps(record, indent=2, sort_keys=True, default=str) + "\n")
    return ArmResult(ablation="hierarchy", arm="flat", case_id=case.id, case_kind=case.kind, delivered=delivered,
                     physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     failure_kinds=_failures(t) if delivered else [f"flat: {outcome.message}"], sim_calls=calls,
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=_metrics(t),
                     evidence=_evidence(h, ["flat.json", "evidence/attempts.jsonl"]), asset_dir=str(arm_dir),
                     wall_s=time.perf_counter() - wall0, error=None if delivered else outcome.message)


# -- B: one-shot ----------------------------------------------------------------------------------------------------------
def run_one_shot(case: SuiteCase, request: AssetRequest, h: dict[str, Any], sim: SimConfig,
                 wall0: float) -> ArmResult:
    """The initial material proposal (priors) kept: the selection probes once, then the same independent tests."""
    if h.get("physical") is None:
        return ArmResult(ablation="harness", arm="one_shot", case_id=case.id, case_kind=case.kind, delivered=False,
                         hard_failure=True, failure_kinds=[h.get("error") or "no physical model"],
                         wall_s=time.perf_counter() - wall0, error=h.get("error"))
    asset_dir = Path(h["asset_dir"])
    l2c = load_contract("L2")
    targets = l2_material.l2_targets(load_l0(asset_dir), request)
    material = Material(**initial_values(l2c, targets, None))
    ev = l2_material.evaluate_material(asset_dir, material, contract=l2c, sim=sim, held_out=False, physical=h["physical"])
    sel_gates = {g.name: bool(g.passes(ev["metrics"].get(g.metric))) for g in l2c.hard_gates}
    tests = physics_tests(asset_dir, h["physical"], material, targets, sim)
    fails = _failures(tests, sel_gates)
    hh = {**h, "material": material, "tests": tests}
    evidence = _evidence(hh, [])
    evidence["selection_probe_keys"] = [r.cache_key for r in ev["selection"] if r.cache_key]
    return ArmResult(ablation="harness", arm="one_shot", case_id=case.id, case_kind=case.kind, delivered=True,
                     physics_pass=tests["plausible"] and tests["held_out_gates_ok"],
                     target_satisfied=bool(tests["held_out_gates_ok"] and tests["targets_met"]),
                     hard_failure=bool(fails), failure_kinds=fails,
                     sim_calls=sum(r.sim_calls for r in ev["selection"]), eval_sim_calls=tests["sim_calls"],
                     metrics={**_metrics(tests), **{f"selection.{k}": float(v) for k, v in ev["metrics"].items()}},
                     evidence=evidence, asset_dir=str(asset_dir), wall_s=time.perf_counter() - wall0)


# -- C: manipulation -------------------------------------------------------------------------------------------------------
def material_passes(asset_dir: Path, physical: PhysicalModel, material: Material, targets: TargetBehaviour,
                    sim: SimConfig) -> tuple[bool, dict[str, Any]]:
    """Material pass: the held-out L2 gates hold and the held-out targets are met."""
    t = physics_tests(asset_dir, physical, material, targets, sim)
    return bool(t["held_out_gates_ok"] and t["targets_met"]), t


def _copy_asset(src: Path, dest: Path) -> None:
    """A private copy of a built asset for one arm (interaction data not carried over)."""
    _fresh(dest)
    shutil.copytree(src, dest, ignore=shutil.ignore_patterns("interaction", "manipulation.json"), dirs_exist_ok=True)


def run_manipulation(case: SuiteCase, request: AssetRequest, h: dict[str, Any], base: Path,
                     conditions: list[Condition], sim: SimConfig, agents: AgentConfig | None,
                     quality: str) -> list[ArmResult]:
    """No feedback (the first plan under each held-out condition) vs Full (L3 harness, then the same conditions)."""
    if h.get("material") is None:
        return [ArmResult(ablation="manipulation", arm=a, case_id=case.id, case_kind=case.kind, delivered=False,
                          conditions=[ConditionResult(condition=c, task_success=False, material_pass=False)
                                      for c in conditions], error=h.get("error") or "no asset")
                for a in ("no_feedback", "full")]
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
    _copy_asset(src, nf_dir)
    ctx = l3_manipulation.load_context(nf_dir, opts, l3c)
    start = l3_context.initial_values(ctx)
    conds = []
    with cache.local_runtime():
        for c in conditions:
            r = ctx.trial(dict(start), "held_out", "no_feedback", target_xy_m=c.target_xy_m, yaw_deg=c.initial_yaw_deg)
            conds.append(ConditionResult(condition=c, task_success=l3_context.accepted(r.metrics, l3c), material_pass=base_ok,
                                         labels=_finite(r.metrics), cache_key=r.cache_key, attempt=r.recording))
    results.append(ArmResult(ablation="manipulation", arm="no_feedback", case_id=case.id, case_kind=case.kind,
                             delivered=True, conditions=conds, sim_calls=len(conds), asset_dir=str(nf_dir),
                             evidence={"material": h["material"].model_dump(mode="json"),
                                       "material_tests": base_tests["cache_keys"], "plan_values": start},
                             wall_s=time.perf_counter() - t0))
    # full: L3 with action / numerical / material revision, then the held-out conditions on the accepted plan
    t0 = time.perf_counter()
    full_dir = base / "full"
    _copy_asset(src, full_dir)
    _, outcome = l3_manipulation.run_l3(full_dir, opts, agents, l3c)
    record = AssetDir(full_dir).manipulation()
    final = AssetDir(full_dir).adopted_material().material  # L2's, or the revision L3 passed with
    ok, tests = (base_ok, base_tests) if final == h["material"] else material_passes(
        full_dir, h["physical"], final, targets, sim)
    by_cond = {(round(x.target_xy_m[0], 6), round(x.target_xy_m[1], 6), round(x.initial_yaw_deg, 6)): x
               for x in record.held_out.conditions}
    # a condition row names its trial by its interaction path (None: the plan failed, nothing was stored)
    key_of = {attempt_path(a.attempt): a.cache_key for a in record.attempts if a.attempt is not None}
    conds = []
    for c in conditions:
        x = by_cond.get((round(c.target_xy_m[0], 6), round(c.target_xy_m[1], 6), round(c.initial_yaw_deg, 6)))
        att = x.attempt if x else None
        conds.append(ConditionResult(condition=c, task_success=bool(x and x.success), material_pass=ok,
                                     labels=_finite(x.labels) if x else {}, attempt=att,
                                     cache_key=key_of.get(att) if att else None))
    results.append(ArmResult(ablation="manipulation", arm="full", case_id=case.id, case_kind=case.kind,
                             delivered=record.passed, conditions=conds, sim_calls=len(record.attempts),
                             asset_dir=str(full_dir),
                             evidence={"material": record.material.model_dump(mode="json"),
                                       "material_source": record.material_source,
                                       "material_tests": tests["cache_keys"], "files": ["manipulation.json"],
                                       "harness_status": outcome.status, "plan_values": record.values,
                                       "recordings": record.recordings},
                             error=None if record.passed else record.message,
                             wall_s=time.perf_counter() - t0))
    return results


def _finite(d: dict[str, Any]) -> dict[str, float]:
    """Numeric labels only, non-finite dropped (JSON-safe)."""
    return {k: float(v) for k, v in d.items() if isinstance(v, (int, float)) and np.isfinite(v)}


def _fresh(path: Path) -> None:
    """An empty directory (an arm's previous partial output removed)."""
    if path.exists():
        shutil.rmtree(path)
    path.parent.mkdir(parents=True, exist_ok=True)
