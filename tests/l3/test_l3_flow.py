"""The L3 flow on a real asset directory: budget gate, action revision, held-out conditions, material revision."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from cache import CacheStore
from contracts.manipulation import ConditionSummary, L2Check, TrialCondition, TrialRow
from contracts.material import Material
from contracts.stage import load_contract
from flows.l3_manipulation import L3Options, run_l3
from tasks.asset_dir import AssetDir
from tests.asset_records import material_record, physical_record
from tests.cli_in_process import cli_in_process

@pytest.fixture(scope="module")
def cube_template(foam_cube_template: Path) -> Path:
    """L0 of 'a soft foam cube 3 cm' and an L1 physical.json (foam prior: density 86 kg/m^3, mu 0.8)."""
    return foam_cube_template


@pytest.fixture
def cube_asset(cube_template: Path, tmp_path: Path) -> Path:
    """A private copy of the asset."""
    dest = tmp_path / "cube"
    shutil.copytree(cube_template, dest)
    return dest


def _contract(**updates: object):  # type: ignore[no-untyped-def]
    """The L3 contract with a 5 cm lift (draft) and overrides."""
    c = load_contract("L3")
    c = c.model_copy(update={"parameters": {**c.parameters, "lift_height_m": 0.05}})
    return c.model_copy(update=updates)


def test_a_trial_over_the_force_budget_is_labelled_and_never_accepted(cube_asset: Path, prefect_api: str) -> None:
    # position control (no hold-force target): a force-controlled closure keeps each finger at its target, which is
    # capped at half the budget, so only a position-controlled squeeze can go over a 0.05 N budget
    base = _contract(revision_budget=0)
    base = base.model_copy(update={"parameters": {**base.parameters, "hold_force_margin": None}})
    gates = [g.model_copy(update={"threshold": 0.05}) if g.metric == "max_finger_force_n" else g
             for g in base.hard_gates]
    # a 4 mm trial lattice (the draft cap for the Franka Hand's pads; 2.5 mm by default for this 3 cm cube): a 3 mm
    # squeeze in position control is newtons per finger at either resolution, far over the 0.05 N budget
    record, outcome = run_l3(cube_asset, L3Options(squeeze_depth_m=0.003, held_out=(), particle_spacing_m=0.004),
                             contract=base.model_copy(update={"hard_gates": gates}), recordings=False)
    assert not record.passed and outcome.status == "no_valid_candidate"
    assert all(a.labels["force_budget_violated"] == 1 for a in record.attempts)
    assert (cube_asset / "interaction" / "attempt_000").is_dir()  # the failed attempt is kept
    lines = (cube_asset / "evidence" / "attempts.jsonl").read_text().splitlines()
    assert lines and all(json.loads(x)["verdict"] != "accepted" for x in lines)
    stored = json.loads((cube_asset / "manipulation.json").read_text())
    assert stored["passed"] is False and stored["attempt"] is None


def test_cli_rejects_a_directory_without_an_asset(tmp_path: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    for cmd in (["manipulate", str(tmp_path)], ["replay", str(tmp_path)]):  # against the session's Prefect server
        code, err = cli_in_process(*cmd, api=prefect_api, monkeypatch=monkeypatch, capsys=capsys)
        assert code != 0 and "error:" in err


def _as_gel(asset: Path) -> Material:
    """Make the cube a soft, dense gel (E 10 kPa, 1000 kg/m^3): a 1 mm squeeze cannot carry it (2 mu N < m g)."""
    phys = AssetDir(asset).physical_model()
    phys = phys.model_copy(update={"density_kg_per_m3": 1000.0, "mass_kg": 1000.0 * phys.volume_m3,
                                   "category": "gel"})
    AssetDir(asset).write_physical(physical_record(phys))
    return Material(youngs_modulus_pa=1e4, poisson_ratio=0.3, damping_rate_per_s=5.0)


@pytest.mark.slow
def test_weak_squeeze_is_revised_then_held_out_and_cached(cube_asset: Path, prefect_api: str,
                                                          cache_dir: Path) -> None:
    gel = _as_gel(cube_asset)
    record, outcome = run_l3(cube_asset, L3Options(squeeze_depth_m=0.001), contract=_contract(), material=gel)
    first = record.attempts[0]
    assert first.labels["slipped"] == 1 and first.values["squeeze_depth_m"] == pytest.approx(0.001)
    assert record.passed and record.values is not None and record.values["squeeze_depth_m"] > 0.001
    assert record.outcome["transported"] and record.outcome["released_in_target"]
    assert record.held_out.conditions and record.held_out.conditions[0].initial_yaw_deg == 30.0
    assert (cube_asset / "recordings" / "L3_pick_and_place.rrd").is_file()
    store = CacheStore(cache_dir)
    misses = len([e for e in store.events() if e["outcome"] == "miss"])
    shutil.rmtree(cube_asset / "interaction")
    run_l3(cube_asset, L3Options(squeeze_depth_m=0.001), contract=_contract(), recordings=False, material=gel)
    assert len([e for e in store.events() if e["outcome"] == "miss"]) == misses  # nothing re-executed
    r = subprocess.run([sys.executable, "-m", "flows.cli.main", "replay", str(cube_asset), "--attempt", "0",
                        "--json"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


@pytest.mark.slow
@pytest.mark.timeout(1800)  # the four L2 probes on the asset dominate (~6-8 min on 2 CPU cores)
def test_material_revision_reexecutes_l2_probes_then_the_robot(cube_asset: Path, prefect_api: str,
                                                               cache_dir: Path) -> None:
    base = _contract(revision_budget=1)
    gates = [g.model_copy(update={"threshold": 0.05}) if g.metric == "strain_p99" else g for g in base.hard_gates]
    record, outcome = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004, held_out=()),
                             contract=base.model_copy(update={"hard_gates": gates}), recordings=False)
    assert outcome.status == "escalated" and outcome.escalation == "revise_material"
    rev = record.material_revision
    assert rev is not None and rev.to.youngs_modulus_pa > rev.from_.youngs_modulus_pa
    events = CacheStore(cache_dir).events()
    misses = [e["task"] for e in events if e["outcome"] == "miss"]
    first_l2 = next(i for i, t in enumerate(misses) if t.startswith("l2."))
    after = misses[first_l2:]
    l2_probes = {"l2.compress", "l2.drop", "l2.lift", "l2.stability", "l2.specimen_compress", "l2.specimen_drop"}
    assert {t for t in after if t.startswith("l2.")} == l2_probes
    assert after[-1] == "l3.trial" and set(after) <= {*l2_probes, "l3.trial"}
    # robot confirmation under the same plan values, physical model and force budget
    assert rev.l2_revalidation.passed and rev.confirmation is not None and "strain_p99" in rev.confirmation
    confirm = next(a for a in reversed(record.attempts) if a.role == "confirmation")
    assert confirm.values == rev.plan_values
    # the L2 probes ran as task runs of L2's revalidation flow, a subflow of l3-manipulation
    from tests.flow_runs import flow_names

    l2_runs = [str(e["flow_run_id"]) for e in events if e["task"].startswith("l2.")]
    assert set(flow_names(l2_runs).values()) == {"l2-revalidation"}


PASS = {"lifted": 1.0, "transported": 1.0, "released_in_target": 1.0, "settled": 1.0, "max_finger_force_n": 2.0,
        "numerically_healthy": 1.0, "max_strain": 0.3, "strain_p99": 0.2, "slipped": 0.0}
SLIP = {**PASS, "lifted": 0.0, "transported": 0.0, "released_in_target": 0.0, "settled": 0.0, "slipped": 1.0}


def _l2_material_in_band(asset: Path, e0: float = 2.0e4):  # type: ignore[no-untyped-def]
    """material.json of an L2 material of modulus e0 whose modulus band is [10, 100] kPa; returns the targets."""
    from contracts.agents import TargetBand, TargetBehaviour

    targets = TargetBehaviour(bands=[TargetBand(metric="effective_modulus_pa", unit="Pa", low=1e4, high=1e5,
                                                scale="log")])
    AssetDir(asset).write_material(material_record(
        Material(youngs_modulus_pa=e0, poisson_ratio=0.3, damping_rate_per_s=5.0), AssetDir(asset).physical_model(),
        targets, metrics={"effective_modulus_pa": e0}))
    return targets


def _stand_in_robot(monkeypatch: pytest.MonkeyPatch, labels_of, revalidate=None) -> None:  # type: ignore[no-untyped-def]
    """The robot replaced by labels_of(material, yaw_deg) (every trial stored as an attempt, as the real one is) and
    L2's revalidation by `revalidate` (default: passes); the flow around them is L3's own."""
    import flows.l3_manipulation as l3
    from contracts.probes import ProbeResult, ProbeSpec

    def fake_trial(self, values, role, action="", material=None, target_xy_m=None, yaw_deg=0.0):  # noqa: ANN001, ANN202
        labels = dict(labels_of(material or self.material, yaw_deg))
        self.attempts.append(TrialRow(attempt=None, role=role, action=action, values=values, labels=labels,
                                      cache_key=None, condition=TrialCondition(
                                          target_xy_m=list(target_xy_m or (0.0, 0.0)), yaw_deg=yaw_deg)))
        return ProbeResult(spec=ProbeSpec(kind="pick_and_place", params={}), metrics=labels)

    def fake_under(self, values, conditions, role, action="", material=None):  # noqa: ANN001, ANN202
        return [fake_trial(self, values, role, action, material=material, target_xy_m=(x, y), yaw_deg=yaw)
                for x, y, yaw in conditions]

    monkeypatch.setattr(l3.L3Context, "trial", fake_trial)
    monkeypatch.setattr(l3.L3Context, "under", fake_under)  # the robot's conditions, one after another
    monkeypatch.setattr(l3, "revalidate_in_l2", revalidate or (lambda asset_dir, material, *a, **k: L2Check(
        material=material, passed=True, gates={}, bands={}, metrics={}, probe_keys=[])))


def test_a_plan_that_slips_under_a_perturbation_gets_the_stiffest_in_band_material(
        cube_asset: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The accepted plan is tried under the robustness conditions; one slips, so L3 asks L2 for the stiffest modulus
    its band allows, and adopts it because it passes the nominal condition and more perturbations. The robot is a
    stand-in here (a grasp holds at yaw 0, or anywhere once E >= 1.5 E0); the logic around it is the flow's own."""
    e0 = 2.0e4
    targets = _l2_material_in_band(cube_asset, e0)
    revalidated = []

    def fake_revalidate(asset_dir, material, physical, limits, sim=None, asset=None):  # noqa: ANN001, ANN202
        assert sim is not None and sim.device == "cpu"  # L3's own settings, not L2's default
        assert asset is not None and len(asset.particles_m)  # the L0 data L3 loaded, not read from disk again
        revalidated.append(material.youngs_modulus_pa)
        return L2Check(material=material, passed=True, gates={"finite": True}, bands={"effective_modulus_pa": True},
                       metrics={}, probe_keys=[])

    _stand_in_robot(monkeypatch, lambda m, yaw: PASS if yaw == 0.0 or m.youngs_modulus_pa >= 1.5 * e0 else SLIP,
                    fake_revalidate)
    record, outcome = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004), contract=_contract(), recordings=False)
    assert outcome.status == "accepted" and record.passed
    rev = record.material_revision
    ceiling = targets.bands[0].point(0.9)  # the specimen reads E here: 90 % up the band in log
    assert rev is not None and rev.trigger == "robustness" and rev.accepted
    assert revalidated == [pytest.approx(ceiling)]
    assert record.material.youngs_modulus_pa == pytest.approx(ceiling)
    assert record.material_source.startswith("L3 material revision")
    assert record.robustness is not None and record.robustness.passed == len(L3Options().robustness)
    assert record.held_out.success_rate == 1.0
    roles = [a.role for a in record.attempts]
    assert roles == ["selection", "robustness", "robustness", "confirmation", "robustness", "robustness", "held_out"]


def test_a_revision_that_is_no_more_robust_is_not_adopted(cube_asset: Path, prefect_api: str,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """When the stiffer material slips under the same perturbations, L3 keeps the L2 material (least change)."""
    _l2_material_in_band(cube_asset)
    _stand_in_robot(monkeypatch, lambda m, yaw: PASS if yaw in (0.0, 30.0) else SLIP)
    record, _ = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004), contract=_contract(), recordings=False)
    assert record.passed and record.material.youngs_modulus_pa == 2e4
    assert record.material_revision is not None and record.material_revision.accepted is False
    assert record.robustness is not None and record.robustness.passed == 0
    assert record.material_source == "L2"


def test_a_revised_material_that_fails_the_nominal_condition_is_not_tried_under_the_perturbations(
        cube_asset: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """No plan passes, so L3 asks L2 for a stiffer material; the robot still slips with it under the nominal
    condition, so the material is not adopted and the robustness conditions (which could not change that) are not
    run."""
    _l2_material_in_band(cube_asset)
    _stand_in_robot(monkeypatch, lambda m, yaw: SLIP)
    record, _ = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004), contract=_contract(), recordings=False)
    rev = record.material_revision
    assert not record.passed and rev is not None and rev.trigger == "no plan passed" and rev.accepted is False
    roles = [a.role for a in record.attempts]
    assert roles[-1] == "confirmation" and "robustness" not in roles
    assert rev.robustness == ConditionSummary(conditions=[], passed=0)


@pytest.mark.slow  # tens of seconds on 2 cores (CI time, 2026-11-29)
def test_conditions_side_by_side_give_what_they_give_one_after_another(cube_asset: Path, prefect_api: str,
                                                                        monkeypatch: pytest.MonkeyPatch,
                                                                        tmp_path: Path) -> None:
    """L3Context.under runs a plan's conditions (here the two robustness yaws) two at a time on the CPU and stores them
    as attempts in the order of the conditions: labels, cache keys and attempts are those of one at a time
    (DEFORMSMITH_PROBE_WORKERS=1), each on a cold cache."""
    import cache
    import flows.l3_manipulation as l3

    gel = _as_gel(cube_asset)
    options = L3Options(squeeze_depth_m=0.004)
    runs = {}
    for workers in ("2", "1"):
        monkeypatch.setenv("DEFORMSMITH_PROBE_WORKERS", workers)
        monkeypatch.setenv("DEFORMSMITH_CACHE", str(tmp_path / f"cache{workers}"))
        shutil.rmtree(cube_asset / "interaction", ignore_errors=True)
        ctx = l3.load_context(cube_asset, options, _contract(), gel)
        with cache.local_runtime():
            results = ctx.under(l3.initial_values(ctx), options.robustness, "robustness")
        assert len({r.cache_key for r in results}) == 2
        runs[workers] = ([(r.metrics, r.cache_key, r.recording) for r in results],
                         [(a.attempt, a.role, a.condition, a.labels) for a in ctx.attempts])
    assert runs["2"] == runs["1"]
    assert [a[2].yaw_deg for a in runs["2"][1]] == [c[2] for c in options.robustness]


def test_a_material_revision_runs_l2_revalidation_as_a_subflow_of_l3(cube_asset: Path, prefect_api: str,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """The Prefect UI's L3 -> L2 edge: a plan that slips under a perturbation asks L2 for a stiffer material, so the
    l3-manipulation run's subflows are its harness stage, then l2-revalidation, in which L2's probes run. The robot and
    L2's probes are stand-ins (the real ones take minutes); the flows around them are the real ones."""
    from prefect.context import FlowRunContext

    import flows.l2_material as l2
    from contracts.probes import ProbeResult, ProbeSpec
    from flows.l3_material import revalidate_in_l2
    from tests.flow_runs import children, latest_run

    _l2_material_in_band(cube_asset)
    probed_in: list[str] = []

    def stand_in_probes(self, values, action):  # noqa: ANN001, ANN202  (L2's selection probes)
        probed_in.append(str(FlowRunContext.get().flow_run.id))  # type: ignore[union-attr]
        return [ProbeResult(spec=ProbeSpec(kind="compress"), metrics={"effective_modulus_pa": 1.0})]

    monkeypatch.setattr(l2._Runner, "__call__", stand_in_probes)
    _stand_in_robot(monkeypatch, lambda m, yaw: PASS if yaw == 0.0 else SLIP, revalidate_in_l2)  # the real L2 call
    record, _ = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004, held_out=()), contract=_contract(),
                       recordings=False)
    assert record.material_revision is not None and record.material_revision.trigger == "robustness"
    subflows = children(latest_run("l3-manipulation").id)
    assert [name for name, _ in subflows] == ["harness-stage", "l2-revalidation"]
    assert probed_in == [str(subflows[1][1].id)]


def test_a_calibrated_material_goes_through_l3s_revise_revalidate_edge(cube_asset: Path, prefect_api: str,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """`deformsmith calibrate`'s checks (flows.calibrate.check_material) on an asset with a passed L3: L2's check (a
    stand-in here), then the robot under manipulation.json's plan with the calibrated material (a stand-in robot that
    holds only materials at least as stiff as the L2 one; the flow around it is the real one): a stiff material is
    confirmed, a soft one fails the L3 gate, and --no-l3 skips the robot."""
    import flows.calibrate as calibrate
    from contracts.sim import SimConfig

    _l2_material_in_band(cube_asset)  # E 20 kPa
    _stand_in_robot(monkeypatch, lambda m, yaw: PASS if m.youngs_modulus_pa >= 2e4 else SLIP)
    record, _ = run_l3(cube_asset, L3Options(squeeze_depth_m=0.004, robustness=()), contract=_contract(),
                       recordings=False)
    assert record.passed and record.values is not None
    checked: list[float] = []

    def l2_passes(asset_dir, material, physical, sim=None, held_out=False, **_):  # noqa: ANN001, ANN202
        assert held_out  # the calibration asks for L2's held-out tests too
        checked.append(material.youngs_modulus_pa)
        return L2Check(material=material, passed=True, gates={"finite": True}, bands={}, metrics={}, probe_keys=[],
                       held_out_gates={"finite": True}, held_out_probes=["compress"])

    monkeypatch.setattr(calibrate, "revalidate_in_l2", l2_passes)
    stiff = record.material.model_copy(update={"youngs_modulus_pa": 4e4})
    checks = calibrate.check_material(cube_asset, stiff, SimConfig(), True, lambda _: None)
    assert checks.passed and checks.l3_status == "confirmed" and checks.gates["L3 robot confirmation"]
    rev = checks.l3
    assert rev is not None and rev.trigger == "calibration" and rev.accepted and rev.to == stiff
    assert rev.from_ == record.material and rev.plan_values == record.values
    assert rev.confirmation is not None and rev.confirmation["lifted"] == 1.0
    soft = record.material.model_copy(update={"youngs_modulus_pa": 1e4})
    checks = calibrate.check_material(cube_asset, soft, SimConfig(), True, lambda _: None)
    assert not checks.passed and checks.l3_status == "failed" and checks.gates["L3 robot confirmation"] is False
    assert "lifted" in checks.l3_note and "L3 robot confirmation" in calibrate.failure_message(checks)
    checks = calibrate.check_material(cube_asset, soft, SimConfig(), False, lambda _: None)
    assert checks.passed and checks.l3 is None and "--no-l3" in checks.l3_note
    assert "L3 robot confirmation" not in checks.gates
    assert checked == [4e4, 1e4, 1e4]
