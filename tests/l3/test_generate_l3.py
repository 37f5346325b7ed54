"""L3 inside `generate`: its line in the validation summary, the manifest's outcome, the attempt the video shows,
the reason in words and the progress lines."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path
from typing import Any

import pytest

from contracts.manipulation import BestAttempt, ManipulationRecord, TrialRow
from contracts.stage import load_contract
from tasks.manifest_summary import (
    cache_keys, finite_metrics, l3_summary, manipulation_outcome, reported_plan, shown_attempt,
)
from tasks.manipulation.report import best_attempt, trial_reason
from tasks.manipulation.outcome import TrialTolerances
from tasks.manipulation.trial import TrialResult
from tests.asset_records import manipulation_record


def _record(passed: bool, labels: list[dict[str, float]], chosen: int | None) -> ManipulationRecord:
    attempts = [TrialRow(attempt=i, role="selection", action="", labels=lab) for i, lab in enumerate(labels)]
    return manipulation_record(passed, attempts, attempt=chosen, labels=labels[chosen] if chosen is not None else {})


def test_a_revised_and_accepted_l3_is_summarised_with_its_trials(firm_trial: TrialResult,
                                                                  weak_trial: TrialResult) -> None:
    rec = _record(True, [weak_trial.metrics, firm_trial.metrics], 1)
    s = l3_summary(rec)
    assert s.stage == "L3" and s.passed and s.sim_calls == 2 and s.attempts == 2 and not s.failed_gates
    assert s.metrics["lifted"] == 1.0 and shown_attempt(rec) == 1
    out = manipulation_outcome(s.metrics)
    assert out is not None and out.lifted and out.transported and not out.slipped
    assert out.max_finger_force_n == (firm_trial.metrics["max_finger_force_0_n"],
                                      firm_trial.metrics["max_finger_force_1_n"])


def test_a_failed_l3_names_its_failed_gates_and_shows_the_last_trial(weak_trial: TrialResult) -> None:
    rec = _record(False, [weak_trial.metrics, weak_trial.metrics], None)
    s = l3_summary(rec)
    assert not s.passed and {"lifted", "transported", "released in target"} <= set(s.failed_gates)
    assert shown_attempt(rec) == 1
    out = manipulation_outcome(s.metrics)
    assert out is not None and out.slipped and not out.lifted


def test_a_failed_l3_summary_round_trips_through_asset_json(weak_trial: TrialResult) -> None:
    """A trial that never held has NaN hold forces: the manifest must still load (it wrote null and broke inspect)."""
    from contracts.manifest import AssetManifest, Provenance
    from contracts.request import AssetRequest

    labels = dict(weak_trial.metrics, hold_normal_force_n=float("nan"))
    s = l3_summary(_record(False, [labels], None))
    assert "hold_normal_force_n" not in s.metrics and "lifted" in s.metrics
    m = AssetManifest(request=AssetRequest(text="a cube"), validation=[s], manipulation=manipulation_outcome(s.metrics),
                      provenance=Provenance(deformsmith_version="test"))
    assert AssetManifest.model_validate_json(m.model_dump_json()) == m


def test_an_unexecutable_plan_has_no_outcome() -> None:
    rec = manipulation_record(False, [TrialRow(attempt=None, role="selection", action="", labels={"plan_failed": 1.0})])
    s = l3_summary(rec)
    assert s.sim_calls == 0 and manipulation_outcome(s.metrics) is None and shown_attempt(rec) is None


# --- how L3's result reaches the user: reasons in words, progress, the reported attempt (issue 24) ---

@pytest.fixture(scope="module")
def small_cube(foam_cube_template: Path) -> Path:
    """A 3 cm foam cube (L0 + L1): graspable by every gripper."""
    return foam_cube_template


def _tol() -> TrialTolerances:
    from tasks.manipulation.context import tolerances_from

    return tolerances_from(load_contract("L3"))


def test_a_trial_that_slips_says_what_happened_from_its_own_data(weak_trial: TrialResult,
                                                                  firm_trial: TrialResult) -> None:
    """The reason says what the trial's data show (the gel cube slid down the pads or the fingers lost it as the hand
    rose), with the measured rises, and never a force comparison that reads as a success (#36)."""
    from tasks.manipulation.diagnosis import diagnose

    contract = load_contract("L3")
    m = weak_trial.metrics
    why = trial_reason(m, contract, _tol())
    d = diagnose(m, _tol())
    assert d is not None and d.mode in ("slipped_at_lift", "lost_contact") and m[f"mode_{d.mode}"] == 1
    assert why.startswith(d.words) and "also failed: transported" in why, why
    assert "m g / (2 mu)" not in why and ">=" not in why
    assert m["lift_rise_m"] < 0.5 * m["hand_rise_m"]  # the hand went up, the cube did not follow
    assert (f"the object rose {m['lift_rise_m'] * 1000:.0f} mm while the hand rose {m['hand_rise_m'] * 1000:.0f} mm"
            in why)
    assert trial_reason(firm_trial.metrics, contract, _tol()) == ""
    over = dict(firm_trial.metrics, max_finger_force_n=25.0, force_budget_violated=1.0)
    assert trial_reason(over, contract, _tol()).startswith("force budget exceeded: peak finger force 25 N > 20 N")


def test_a_failed_l3_reports_its_best_trial_under_the_assets_material(cube: Any, weak_trial: TrialResult,
                                                                     firm_trial: TrialResult) -> None:
    """A material revision that was tried but not adopted (here its confirmation still failed one gate) must not give
    the manifest its figures: the asset keeps its material, so the figures, plan and key are the selection trial's."""
    contract = load_contract("L3")
    confirm = dict(firm_trial.metrics, settled=0.0)  # fewer failed gates than the selection trial, but not adopted
    attempts = [TrialRow(attempt=0, role="selection", action="", values={"squeeze_depth_m": 0.001},
                         labels=weak_trial.metrics, cache_key="k0"),
                TrialRow(attempt=1, role="confirmation", action="", values={"squeeze_depth_m": 0.001}, labels=confirm,
                         cache_key="k1")]
    best = best_attempt(attempts, contract)
    assert best is attempts[0]
    reason = trial_reason(best.labels, contract, _tol())
    rec = manipulation_record(False, attempts, reason=reason, best_attempt=BestAttempt(
        attempt=best.attempt, role=best.role, values=best.values, labels=best.labels, plan=cube.plan(0.001),
        cache_key=best.cache_key, failed_gates=["lifted", "transported"], reason=reason))
    s = l3_summary(rec)
    assert s.metrics == finite_metrics(weak_trial.metrics) and s.reason == rec.reason
    assert s.failed_gates == ["lifted", "transported"]
    assert shown_attempt(rec) == 0 and reported_plan(rec) is not None
    assert cache_keys(Path("/nonexistent"), rec) == {"l3.trial": "k0"}


def test_one_failed_trial_reaches_the_manifest_with_its_reason_progress_and_key(
        small_cube: Path, tmp_path: Path, prefect_api: str) -> None:
    """A real trial that fails a (tightened) deformation bound: progress lines while it runs, the reason in words, and
    the manifest's figures, plan and cache key are those of that trial in manipulation.json."""
    from flows.l3_manipulation import L3Options, run_l3

    asset = shutil.copytree(small_cube, tmp_path / "cube")
    base = load_contract("L3")
    gates = [g.model_copy(update={"threshold": 1e-9}) if g.metric == "strain_p99" else g  # any squeeze fails it
             for g in base.hard_gates]
    contract = base.model_copy(update={"hard_gates": gates, "revision_budget": 0,
                                       "parameters": {**base.parameters, "lift_height_m": 0.05}})
    lines: list[str] = []
    # a 4 mm trial lattice (the draft cap for the Franka Hand's pads; 2.5 mm by default for this 3 cm cube): any
    # squeeze fails the tightened bound at any resolution
    record, _ = run_l3(asset, L3Options(squeeze_depth_m=0.003, held_out=(), material_fallback=False,
                                        particle_spacing_m=0.004),
                       contract=contract, recordings=False, progress=lines.append)
    assert any(re.fullmatch(r"L3 trial 1 of at most 3: selection \(revise_squeeze\), grasp 0, squeeze [0-9.]+ mm "
                            r"\(\d+ s\)", ln) for ln in lines), lines  # 1 harness trial + 2 robustness yaws
    assert any(ln.startswith("L3 trial 1: deformation bound exceeded: strain (1 % of volume)") for ln in lines), lines
    assert lines[-1].startswith("L3 did not pass: deformation bound exceeded")
    stored = json.loads((asset / "manipulation.json").read_text())
    assert not stored["passed"] and stored["reason"].startswith("deformation bound exceeded: strain")
    trial = stored["attempts"][0]
    assert stored["best_attempt"]["attempt"] == trial["attempt"] == 0 and trial["reason"] == stored["reason"]
    typed = ManipulationRecord.model_validate(stored)
    assert typed == record  # what run_l3 returned is what manipulation.json holds
    s = l3_summary(typed)
    assert s.metrics == finite_metrics(trial["labels"]) and s.failed_gates == ["deformation bounded"]
    assert s.reason == stored["reason"]
    plan = reported_plan(typed)
    assert plan is not None and plan.squeeze_depth_m == pytest.approx(trial["values"]["squeeze_depth_m"])
    assert cache_keys(asset, typed)["l3.trial"] == trial["cache_key"] is not None


@pytest.mark.slow  # two real trials and their revision: ~10-15 min on the loaded 2-core CPU (2026-11-29)
@pytest.mark.timeout(1800)
def test_a_default_l3_keeps_the_reported_trials_states_alone_and_record_all_keeps_every_trial(
        small_cube: Path, tmp_path: Path, prefect_api: str, cache_dir: Path) -> None:
    """#38 item 5 on real trials: two failing trials (a tightened deformation bound, one revision); by default the
    asset holds the reported trial's interaction folder and recording alone, the other trial's are
    in the cache under the key its row names; `keep='all'` (--record all) keeps both (the trials are cache hits)."""
    from cache import CacheStore, cache_resolve
    from flows.l3_manipulation import L3Options, run_l3
    from tasks.manipulation.data import attempt_indices

    base = load_contract("L3")
    gates = [g.model_copy(update={"threshold": 1e-9}) if g.metric == "strain_p99" else g for g in base.hard_gates]
    contract = base.model_copy(update={"hard_gates": gates, "revision_budget": 1,
                                       "parameters": {**base.parameters, "lift_height_m": 0.05}})
    options = L3Options(squeeze_depth_m=0.003, held_out=(), material_fallback=False)
    runs = {}
    for keep in ("adopted", "all"):
        asset = shutil.copytree(small_cube, tmp_path / keep)
        runs[keep] = (asset, run_l3(asset, options, contract=contract, keep=keep)[0])
    asset, record = runs["adopted"]
    assert len(record.attempts) >= 2 and not record.passed and record.best_attempt is not None
    reported = record.best_attempt.attempt
    assert attempt_indices(asset) == [reported]
    assert sorted(p.name for p in (asset / "recordings").glob("L3_*.rrd")) == [f"L3_trial_{reported + 1:02d}.rrd"]
    store = CacheStore(cache_dir)
    for row in record.attempts:
        if row.attempt == reported:
            assert row.kept_in == "asset" and row.recording
            continue
        assert row.kept_in == "cache" and row.recording is None and row.labels  # its metrics stay
        assert row.data_key and store.get(row.data_key).is_dir()
        assert row.recording_in_cache and cache_resolve(row.recording_in_cache).is_file()
    full, all_record = runs["all"]
    assert attempt_indices(full) == [a.attempt for a in all_record.attempts if a.attempt is not None]
    assert len(list((full / "recordings").glob("L3_trial_*.rrd"))) == len(all_record.attempts)
    assert all(a.kept_in == "asset" for a in all_record.attempts)
    assert json.dumps([a.labels for a in all_record.attempts]) == json.dumps([a.labels for a in record.attempts])
    # one trial's data fewer (not under 20 MB: this 3 cm cube's draft L0 alone, particles and Gaussians, is ~11 MB)
    size = {k: sum(p.stat().st_size for p in a.rglob("*") if p.is_file()) for k, (a, _) in runs.items()}
    assert size["adopted"] < size["all"] - 4 * 2**20
