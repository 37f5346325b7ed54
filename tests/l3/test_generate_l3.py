"""L3 inside `generate`: its line in the validation summary, the manifest's outcome, the attempt the video shows."""

from __future__ import annotations

from flows.generate import l3_summary, manipulation_outcome, shown_attempt
from tasks.manipulation.trial import TrialResult


def _record(passed: bool, labels: list[dict[str, float]], chosen: int | None) -> dict:
    attempts = [{"attempt": i, "labels": lab} for i, lab in enumerate(labels)]
    return {"passed": passed, "attempt": chosen, "labels": labels[chosen] if chosen is not None else {},
            "attempts": attempts}


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
    rec = {"passed": False, "attempt": None, "attempts": [{"attempt": None, "labels": {"plan_failed": 1.0}}]}
    s = l3_summary(rec)
    assert s.sim_calls == 0 and manipulation_outcome(s.metrics) is None and shown_attempt(rec) is None
