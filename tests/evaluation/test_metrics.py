"""Table III aggregation and the report on synthetic records (no simulation)."""

from __future__ import annotations

import json
from pathlib import Path


from contracts.evaluation import ArmResult, Condition, ConditionResult
from tasks.evaluation.flat import flat_contract
from tasks.evaluation.metrics import aggregate, direction_ok, meets_target, wilson


def _rec(ablation: str, arm: str, case: str, **kw) -> ArmResult:
    return ArmResult(ablation=ablation, arm=arm, case_id=case, case_kind="text", **kw)


def test_hierarchy_missing_assets_count_as_failures() -> None:
    recs = [_rec("hierarchy", "flat", "a", delivered=False, sim_calls=0),
            _rec("hierarchy", "flat", "b", delivered=True, physics_pass=False, sim_calls=20),
            _rec("hierarchy", "hierarchical", "a", delivered=True, physics_pass=True, sim_calls=10),
            _rec("hierarchy", "hierarchical", "b", delivered=True, physics_pass=True, sim_calls=14),
            _rec("hierarchy", "hierarchical", "c", delivered=True, physics_pass=True, sim_calls=99)]  # c: flat missing
    f = aggregate(recs)["hierarchy"]
    assert f["flat"]["delivery"].value == 0.5 and f["flat"]["physics_pass"].value == 0.0
    assert f["hierarchical"]["delivery"].n == 2  # only cases both arms ran
    assert f["hierarchical"]["sim_calls"].value == 12.0 and f["flat"]["sim_calls"].value == 20.0
    assert direction_ok("delivery", 0.5, 1.0) and direction_ok("sim_calls", 20, 12)


def test_harness_rates() -> None:
    recs = [_rec("harness", "one_shot", "a", delivered=True, target_satisfied=False, hard_failure=True, sim_calls=4),
            _rec("harness", "one_shot", "b", delivered=False, hard_failure=True),
            _rec("harness", "harness", "a", delivered=True, target_satisfied=True, hard_failure=False, sim_calls=12),
            _rec("harness", "harness", "b", delivered=True, target_satisfied=True, hard_failure=False, sim_calls=14)]
    f = aggregate(recs)["harness"]
    assert f["one_shot"]["hard_failure"].value == 1.0 and f["one_shot"]["target_satisfaction"].value == 0.0
    assert f["harness"]["target_satisfaction"].value == 1.0 and f["harness"]["sim_calls"].value == 13.0
    assert meets_target("hard_failure", 0.0) and not meets_target("target_satisfaction", 0.5)


def test_manipulation_counts_trials() -> None:
    c = Condition(target_xy_m=(0.0, 0.1))
    trials = [ConditionResult(condition=c, task_success=s, material_pass=m) for s, m in
              ((True, True), (True, False), (False, True), (True, True), (False, False))]
    recs = [_rec("manipulation", "no_feedback", "a", delivered=True, conditions=trials[:3] + trials[4:]),
            _rec("manipulation", "full", "a", delivered=True, conditions=trials[:1] * 4 + trials[2:3])]
    f = aggregate(recs)["manipulation"]
    assert f["no_feedback"]["task_success"].n == 4 and f["no_feedback"]["joint_success"].value == 0.25
    assert f["full"]["task_success"].value == 0.8 and f["full"]["material_pass"].value == 1.0
    assert f["full"]["joint_success"].sources[0] == "a#0"


def test_wilson_bounds() -> None:
    lo, hi = wilson(9, 10)
    assert 0.55 < lo < 0.9 < hi <= 1.0
    assert wilson(0, 5)[0] == 0.0
    # all-successes / no-successes intervals end exactly at the rate (round-off gave 0.9999999999999999 at 6/6, and
    # the report's error bars went negative: matplotlib refused to plot a 44-case run)
    assert all(wilson(n, n)[1] == 1.0 and wilson(0, n)[0] == 0.0 for n in range(1, 200))


def test_report_is_traceable(tmp_path: Path) -> None:
    from contracts.evaluation import Suite, SuiteCase
    from tasks.evaluation.runs import EvalOptions, write_record
    from tasks.evaluation.report import write_report

    recs = [_rec("harness", "one_shot", "a", delivered=True, target_satisfied=False, hard_failure=True, sim_calls=4),
            _rec("harness", "harness", "a", delivered=True, target_satisfied=True, hard_failure=False, sim_calls=12,
                 evidence={"cache_keys": {"l2.compress.held_out": "k" * 64}})]
    for r in recs:
        write_record(tmp_path, r)
    suite = Suite(name="t", cases=[SuiteCase(id="a", kind="text", text="a sponge", intent="sponge")])
    s = write_report(tmp_path / "report", recs, suite, tmp_path / "s.yaml", EvalOptions(ablations=("harness",)), 1.0, [])
    md = Path(s["report"]).read_text()
    assert "B. One-shot vs Harness" in md and "73 %" in md and "100 % (1/1)" in md
    assert (tmp_path / "report" / "harness.png").stat().st_size > 1000
    traced = json.loads(Path(s["figures_json"]).read_text())
    assert traced["harness"]["harness"]["target_satisfaction"]["records"] == ["records/harness/harness/a.json"]
    assert (tmp_path / "records/harness/harness/a.json").is_file()


def test_flat_contract_joins_l1_and_l2() -> None:
    from contracts.stage import load_contract
    from tasks.agents.vocab import stage_routes

    l1, l2 = load_contract("L1"), load_contract("L2")
    c = flat_contract(l1, l2)
    assert 1 + c.revision_budget == (1 + l1.revision_budget) + (1 + l2.revision_budget)
    assert {f.name for f in c.editable_fields} == {f.name for f in (*l1.editable_fields, *l2.editable_fields)}
    assert len(c.hard_gates) == len(l1.hard_gates) + len(l2.hard_gates)
    routes = stage_routes(c.stage, c.parameters)
    assert routes.fields_of("propose_all", [f.name for f in c.editable_fields]) == [f.name for f in c.editable_fields]
    assert "mass_kg" in routes.couplings and "effective_modulus_pa" in routes.couplings
    assert routes.gates["slide_below_sticks"].directions == {"ground_friction": "increase"}


def test_resume_skips_recorded_cases_inside_the_prefect_flow(tmp_path: Path, prefect_api: str) -> None:
    from flows.evaluate import evaluation_flow
    from tasks.evaluation.runs import EvalOptions, write_record

    suite = tmp_path / "s.json"
    suite.write_text(json.dumps({"name": "s", "cases": [{"id": "a", "kind": "text", "text": "a sponge 10 cm",
                                                         "intent": "sponge"}]}))
    out = tmp_path / "eval"
    for arm, sat in (("one_shot", False), ("harness", True)):
        write_record(out, _rec("harness", arm, "a", delivered=True, target_satisfied=sat, hard_failure=not sat,
                               sim_calls=5))
    summary = evaluation_flow(EvalOptions(suite=str(suite), ablations=("harness",), out=out))
    assert summary["figures"]["harness"]["harness"]["target_satisfaction"]["value"] == 1.0
    assert summary["figures"]["harness"]["one_shot"]["hard_failure"]["value"] == 1.0
    assert (out / "report" / "report.md").is_file() and not (out / "cases").exists()  # nothing re-ran
