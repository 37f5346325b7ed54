"""The records of the ablations' arms (`contracts.evaluation.ArmResult`) built from what an arm did, and the folders
an arm works in. flows.eval_arms runs the arms (the layers' flows, the cached probes) and hands the outcomes here.

An arm's outcome `h` is a dict: asset_dir, physical, material (None when not delivered), error, the construction
simulation counts, and tests, the independent physics tests (held_out_tests below)."""

from __future__ import annotations

import shutil
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from contracts.agents import TargetBehaviour
from contracts.asset_dir import attempt_path
from contracts.evaluation import ArmResult, Condition, ConditionResult, SuiteCase
from contracts.manipulation import ManipulationRecord
from contracts.material import Material
from contracts.probes import ProbeResult
from contracts.stage import StageContract

HIERARCHY_FILES = ["physical.json", "material.json", "evidence/attempts.jsonl", "evidence/L2_attempts.jsonl",
                   "renders/drop_front.mp4", "renders/drop_side.mp4"]


def held_out_tests(probes: list[ProbeResult], held: dict[str, float], protocol: dict[str, float], l2: StageContract,
                   targets: TargetBehaviour, keys: dict[str, str | None]) -> dict[str, Any]:
    """The independent physics tests of one (physical, material): the held-out L2 probes' metrics (`held`, merged as
    L2 merges them) judged by the L2 hard gates they report and the held-out target bands, and the drop protocol."""
    gates = {g.name: bool(g.passes(held.get(g.metric))) for g in l2.hard_gates if g.metric in held}
    bands = [b for b in targets.bands if b.metric in held]
    ho_targets = targets.model_copy(update={"bands": bands})
    return {"held_out_metrics": held, "held_out_gates": gates, "held_out_gates_ok": all(gates.values()),
            "targets_met": ho_targets.met(held), "target_bands": {b.metric: [b.low, b.high] for b in bands},
            "protocol": protocol, "plausible": bool(protocol.get("plausible", 0.0) == 1.0),
            "sim_calls": sum(p.sim_calls for p in probes) + 1, "cache_keys": keys,
            "recordings": [p.recording for p in probes if p.recording]}


def failure_kinds(tests: dict[str, Any] | None, selection_gates: dict[str, bool] | None = None) -> list[str]:
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


def independent_metrics(tests: dict[str, Any] | None) -> dict[str, float]:
    """Flat float metrics of the independent tests for the record."""
    if tests is None:
        return {}
    out = {f"held_out.{k}": float(v) for k, v in tests["held_out_metrics"].items()}
    out.update({f"protocol.{k}": float(v) for k, v in tests["protocol"].items()})
    return out


def arm_evidence(h: dict[str, Any], files: list[str]) -> dict[str, Any]:
    """Cache keys and files behind a record."""
    t = h.get("tests") or {}
    root = Path(h["asset_dir"])
    return {"cache_keys": t.get("cache_keys", {}), "files": [f for f in files if (root / f).exists()],
            "recordings": sorted(str(p.relative_to(root)) for p in (root / "recordings").glob("*.rrd"))
            if (root / "recordings").is_dir() else [], "held_out_recordings": t.get("recordings", []),
            "material": h["material"].model_dump(mode="json") if h.get("material") else None,
            "physical": h["physical"].model_dump(mode="json") if h.get("physical") else None,
            "target_bands": t.get("target_bands")}


def finite_labels(d: dict[str, Any]) -> dict[str, float]:
    """Numeric labels only, non-finite dropped (JSON-safe)."""
    return {k: float(v) for k, v in d.items() if isinstance(v, (int, float)) and np.isfinite(v)}


def fresh_dir(path: Path) -> None:
    """An empty directory (an arm's previous partial output removed)."""
    if path.exists():
        shutil.rmtree(path)
    path.parent.mkdir(parents=True, exist_ok=True)


def copy_asset(src: Path, dest: Path) -> None:
    """A private copy of a built asset for one arm (interaction data not carried over)."""
    fresh_dir(dest)
    shutil.copytree(src, dest, ignore=shutil.ignore_patterns("interaction", "manipulation.json"), dirs_exist_ok=True)


# -- A: hierarchy ---------------------------------------------------------------------------------------------------
def hierarchy_result(case: SuiteCase, h: dict[str, Any], wall_s: float) -> ArmResult:
    """Ablation A, hierarchical arm."""
    delivered = h["material"] is not None
    t = h["tests"]
    return ArmResult(ablation="hierarchy", arm="hierarchical", case_id=case.id, case_kind=case.kind,
                     delivered=delivered, physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     failure_kinds=failure_kinds(t) if delivered else [h.get("error") or "no asset"],
                     sim_calls=int(h.get("l1_sim_calls", 0)) + int(h.get("l2_sim_calls", 0)),
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=independent_metrics(t),
                     evidence=arm_evidence(h, HIERARCHY_FILES), asset_dir=h["asset_dir"], wall_s=wall_s,
                     error=h.get("error"))


def flat_result(case: SuiteCase, h: dict[str, Any], message: str, sim_calls: int, wall_s: float) -> ArmResult:
    """Ablation A, flat arm: one joint harness stage over L1 + L2 fields (`message`: how it ended), then the same
    independent tests (flat.json written beside its evidence)."""
    t = h["tests"]
    delivered = h["material"] is not None
    return ArmResult(ablation="hierarchy", arm="flat", case_id=case.id, case_kind=case.kind, delivered=delivered,
                     physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     failure_kinds=failure_kinds(t) if delivered else [f"flat: {message}"], sim_calls=sim_calls,
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=independent_metrics(t),
                     evidence=arm_evidence(h, ["flat.json", "evidence/attempts.jsonl"]), asset_dir=h["asset_dir"],
                     wall_s=wall_s, error=None if delivered else message)


# -- B: harness -----------------------------------------------------------------------------------------------------
def harness_result(case: SuiteCase, h: dict[str, Any], wall_s: float) -> ArmResult:
    """Ablation B, harness arm (the same L2 run; construction calls of L2 alone)."""
    t = h["tests"]
    delivered = h["material"] is not None
    fails = failure_kinds(t) if delivered else [h.get("error") or "no material"]
    return ArmResult(ablation="harness", arm="harness", case_id=case.id, case_kind=case.kind, delivered=delivered,
                     physics_pass=bool(t and t["plausible"] and t["held_out_gates_ok"]),
                     target_satisfied=bool(t and t["held_out_gates_ok"] and t["targets_met"]),
                     hard_failure=bool(fails), failure_kinds=fails, sim_calls=int(h.get("l2_sim_calls", 0)),
                     eval_sim_calls=int(t["sim_calls"]) if t else 0, metrics=independent_metrics(t),
                     evidence=arm_evidence(h, ["material.json", "evidence/L2_attempts.jsonl"]),
                     asset_dir=h["asset_dir"], wall_s=wall_s, error=h.get("error"))


def one_shot_missing(case: SuiteCase, h: dict[str, Any], wall_s: float) -> ArmResult:
    """Ablation B, one-shot arm, when the hierarchy's L1 gave no physical model to start from."""
    return ArmResult(ablation="harness", arm="one_shot", case_id=case.id, case_kind=case.kind, delivered=False,
                     hard_failure=True, failure_kinds=[h.get("error") or "no physical model"], wall_s=wall_s,
                     error=h.get("error"))


def one_shot_result(case: SuiteCase, h: dict[str, Any], material: Material, selection: dict[str, Any],
                    tests: dict[str, Any], l2: StageContract, wall_s: float) -> ArmResult:
    """Ablation B, one-shot arm: the initial material proposal kept, judged by the L2 selection probes once
    (`selection`: the l2-revalidation flow's result, its gates L2's hard gates) and the independent tests."""
    sel_gates = {g.name: bool(g.passes(selection["metrics"].get(g.metric))) for g in l2.hard_gates}
    fails = failure_kinds(tests, sel_gates)
    evidence = arm_evidence({**h, "material": material, "tests": tests}, [])
    evidence["selection_probe_keys"] = [r.cache_key for r in selection["selection"] if r.cache_key]
    return ArmResult(ablation="harness", arm="one_shot", case_id=case.id, case_kind=case.kind, delivered=True,
                     physics_pass=tests["plausible"] and tests["held_out_gates_ok"],
                     target_satisfied=bool(tests["held_out_gates_ok"] and tests["targets_met"]),
                     hard_failure=bool(fails), failure_kinds=fails,
                     sim_calls=sum(r.sim_calls for r in selection["selection"]), eval_sim_calls=tests["sim_calls"],
                     metrics={**independent_metrics(tests),
                              **{f"selection.{k}": float(v) for k, v in selection["metrics"].items()}},
                     evidence=evidence, asset_dir=h["asset_dir"], wall_s=wall_s)


# -- C: manipulation ------------------------------------------------------------------------------------------------
def manipulation_not_delivered(case: SuiteCase, h: dict[str, Any], conditions: list[Condition]) -> list[ArmResult]:
    """Both arms of ablation C when the hierarchy delivered no asset: every condition failed."""
    return [ArmResult(ablation="manipulation", arm=a, case_id=case.id, case_kind=case.kind, delivered=False,
                      conditions=[ConditionResult(condition=c, task_success=False, material_pass=False)
                                  for c in conditions], error=h.get("error") or "no asset")
            for a in ("no_feedback", "full")]


def _condition_key(target_xy_m: Sequence[float], yaw_deg: float) -> tuple[float, float, float]:
    return round(target_xy_m[0], 6), round(target_xy_m[1], 6), round(yaw_deg, 6)


def full_conditions(conditions: list[Condition], record: ManipulationRecord, material_pass: bool
                    ) -> list[ConditionResult]:
    """Ablation C, full arm: each held-out condition's row of the L3 record (matched by target and yaw), its trial
    named by its interaction path and cache key (a condition without a row failed: the plan failed, nothing stored)."""
    by_cond = {_condition_key(x.target_xy_m, x.initial_yaw_deg): x for x in record.held_out.conditions}
    key_of = {attempt_path(a.attempt): a.cache_key for a in record.attempts if a.attempt is not None}
    out = []
    for c in conditions:
        x = by_cond.get(_condition_key(c.target_xy_m, c.initial_yaw_deg))
        att = x.attempt if x else None
        out.append(ConditionResult(condition=c, task_success=bool(x and x.success), material_pass=material_pass,
                                   labels=finite_labels(x.labels) if x else {}, attempt=att,
                                   cache_key=key_of.get(att) if att else None))
    return out


def no_feedback_result(case: SuiteCase, h: dict[str, Any], conditions: list[ConditionResult], asset_dir: Path,
                       material_tests: dict[str, Any], plan_values: dict[str, float], wall_s: float) -> ArmResult:
    """Ablation C, no-feedback arm: the first plan under each held-out condition, the L2 material, nothing revised."""
    return ArmResult(ablation="manipulation", arm="no_feedback", case_id=case.id, case_kind=case.kind,
                     delivered=True, conditions=conditions, sim_calls=len(conditions), asset_dir=str(asset_dir),
                     evidence={"material": h["material"].model_dump(mode="json"),
                               "material_tests": material_tests["cache_keys"], "plan_values": plan_values},
                     wall_s=wall_s)


def full_result(case: SuiteCase, conditions: list[Condition], record: ManipulationRecord, material_pass: bool,
                material_tests: dict[str, Any], harness_status: str, asset_dir: Path, wall_s: float) -> ArmResult:
    """Ablation C, full arm: L3 with its revisions (`record`, manipulation.json), then the held-out conditions on the
    plan it accepted; material_pass and material_tests: the independent tests of the material L3 ended with."""
    return ArmResult(ablation="manipulation", arm="full", case_id=case.id, case_kind=case.kind,
                     delivered=record.passed, conditions=full_conditions(conditions, record, material_pass),
                     sim_calls=len(record.attempts), asset_dir=str(asset_dir),
                     evidence={"material": record.material.model_dump(mode="json"),
                               "material_source": record.material_source,
                               "material_tests": material_tests["cache_keys"], "files": ["manipulation.json"],
                               "harness_status": harness_status, "plan_values": record.values,
                               "recordings": record.recordings},
                     error=None if record.passed else record.message, wall_s=wall_s)
