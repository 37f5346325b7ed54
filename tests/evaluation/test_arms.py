"""The ablations' records built from what an arm did (tasks.evaluation.arms) and an evaluation's layout on disk
(tasks.evaluation.runs): failure kinds, flat metrics, held-out conditions matched to L3's rows, resume."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any, cast

from contracts.evaluation import Condition, SuiteCase
from contracts.manipulation import ConditionRow, ManipulationRecord
from tasks.evaluation.arms import (
    copy_asset, failure_kinds, finite_labels, full_conditions, harness_result, manipulation_not_delivered,
    independent_metrics,
)
from tasks.evaluation.runs import case_done, load_records, needed_arms, not_built, write_record

CASE = SuiteCase(id="duck", kind="text", text="a rubber duck", intent="rubber", manipulation=True)
TESTS: dict[str, Any] = {"held_out_gates": {"finite": True, "no_tunnelling": False}, "held_out_gates_ok": False,
                         "held_out_metrics": {"rebound_ratio": 0.4}, "targets_met": True, "plausible": False,
                         "protocol": {"plausible": 0.0, "collapsed": 1.0}, "sim_calls": 5, "cache_keys": {"k": "v"},
                         "recordings": [], "target_bands": {}}


def test_failure_kinds_and_metrics_of_the_independent_tests() -> None:
    assert failure_kinds(TESTS, {"stable": False, "finite": True}) == [
        "selection gate: stable", "held-out gate: no_tunnelling", "protocol: collapsed"]
    assert failure_kinds({**TESTS, "protocol": {}}) == ["held-out gate: no_tunnelling",
                                                        "protocol: implausible deformation"]
    assert independent_metrics(TESTS) == {"held_out.rebound_ratio": 0.4, "protocol.plausible": 0.0,
                                     "protocol.collapsed": 1.0}
    assert independent_metrics(None) == {} and failure_kinds(None) == []
    assert finite_labels({"a": 1, "b": float("nan"), "c": "x", "d": True}) == {"a": 1.0, "d": 1.0}


def test_an_arm_record_names_what_is_behind_it(tmp_path: Path) -> None:
    (tmp_path / "recordings").mkdir()
    (tmp_path / "recordings" / "L2_drop.rrd").write_bytes(b"")
    (tmp_path / "material.json").write_text("{}")
    h = {"asset_dir": str(tmp_path), "material": None, "physical": None, "tests": TESTS, "l2_sim_calls": 7,
         "error": "L2: no valid material"}
    r = harness_result(CASE, h, 2.5)
    assert (r.delivered, r.hard_failure, r.failure_kinds, r.sim_calls, r.eval_sim_calls) == (
        False, True, ["L2: no valid material"], 7, 5)
    assert r.evidence["files"] == ["material.json"] and r.evidence["recordings"] == ["recordings/L2_drop.rrd"]
    assert [(x.arm, x.delivered, len(x.conditions)) for x in manipulation_not_delivered(
        CASE, h, [Condition(target_xy_m=(0.1, 0.0))])] == [("no_feedback", False, 1), ("full", False, 1)]


def test_held_out_conditions_are_matched_to_l3_s_rows() -> None:
    row = ConditionRow(target_xy_m=[0.06, -0.08], initial_yaw_deg=30.0, success=True, labels={"lifted": 1.0},
                       attempt="interaction/attempt_004")
    record = cast(ManipulationRecord, SimpleNamespace(
        held_out=SimpleNamespace(conditions=[row]),
        attempts=[SimpleNamespace(attempt=4, cache_key="key4"), SimpleNamespace(attempt=None, cache_key="x")]))
    got = full_conditions([Condition(target_xy_m=(0.0600000001, -0.08), initial_yaw_deg=30.0),
                           Condition(target_xy_m=(0.1, 0.0))], record, True)
    assert [(c.task_success, c.material_pass, c.attempt, c.cache_key, c.labels) for c in got] == [
        (True, True, "interaction/attempt_004", "key4", {"lifted": 1.0}), (False, True, None, None, {})]


def test_records_on_disk_and_resume(tmp_path: Path) -> None:
    needed = needed_arms(CASE, ("harness", "manipulation"))
    assert needed == [("harness", "one_shot"), ("harness", "harness"), ("manipulation", "no_feedback"),
                      ("manipulation", "full")]
    assert needed_arms(CASE.model_copy(update={"manipulation": False}), ("manipulation",)) == []
    records = not_built(CASE, needed, "L0 gates failed: watertight", 1.5)
    for r in records[:-1]:
        write_record(tmp_path, r)
    assert not case_done(tmp_path, CASE, ("harness", "manipulation"))
    write_record(tmp_path, records[-1])
    assert case_done(tmp_path, CASE, ("harness", "manipulation"))
    assert sorted((r.ablation, r.arm) for r in load_records(tmp_path)) == sorted(needed)
    assert all(r.hard_failure and r.failure_kinds == ["L0 gates failed: watertight"] for r in load_records(tmp_path))


def test_an_arm_works_on_its_own_copy(tmp_path: Path) -> None:
    src = tmp_path / "src"
    (src / "interaction").mkdir(parents=True)
    (src / "manipulation.json").write_text("{}")
    (src / "physical.json").write_text("{}")
    copy_asset(src, tmp_path / "arm")
    assert sorted(p.name for p in (tmp_path / "arm").iterdir()) == ["physical.json"]
