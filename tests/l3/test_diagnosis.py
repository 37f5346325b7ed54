"""A failed L3 trial says what happened from its own data, and the revision acts on that (issue #36): a slip or a
lost contact at the lift is answered by a firmer / deeper squeeze, a slower lift or another grasp; a release off target
by a lower release and a slower opening. Fast: labels as a trial records them, the rule Critic and Planner on them."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from contracts.agents import CriticRequest, HistoryEntry, PlannerContext, TargetBehaviour
from contracts.evidence import GateResult
from contracts.stage import load_contract
from tasks.manipulation.report import trial_reason
from tasks.agents.rule import RuleCritic, RulePlanner
from tasks.agents.vocab import stage_routes
from tasks.manipulation.diagnosis import MODES, diagnose, mode_flags
from tasks.manipulation.outcome import TrialTolerances, _object_rotation_deg

TOL = TrialTolerances(lift_height_m=0.10, place_tolerance_m=0.03, slip_tolerance_m=0.01)
OUTCOME = ("lifted", "transported", "released_in_target", "settled")


def labels(**kw: Any) -> dict[str, Any]:
    """A trial's labels: a full success unless kw says otherwise (SI units)."""
    base = {"lifted": 1.0, "transported": 1.0, "released_in_target": 1.0, "settled": 1.0, "slipped": 0.0,
            "numerically_healthy": 1.0, "force_budget_violated": 0.0, "max_finger_force_n": 1.5, "strain_p99": 0.02,
            "lift_rise_m": 0.098, "hand_rise_m": 0.100, "grip_force_at_lift_n": 1.0, "grip_force_min_held_n": 0.8,
            "contact_lost_hand_rise_m": math.nan, "object_rotation_deg": 2.0, "grip_force_target_n": 1.0,
            "slip_distance_m": 0.004, "transport_error_m": 0.001, "place_error_m": 0.004, "release_drop_m": 0.001,
            "release_drift_m": 0.003, "settle_com_speed_m_per_s": 0.001, "weight_n": 0.26, "gripper_friction": 1.0}
    base.update(kw)
    return base


NOT_LIFTED = dict(lifted=0.0, transported=0.0, released_in_target=0.0, lift_rise_m=0.001, place_error_m=0.10)


def test_a_success_has_no_diagnosis_and_no_mode() -> None:
    assert diagnose(labels(), TOL) is None
    assert set(mode_flags(labels(), TOL).values()) == {0.0}
    assert trial_reason(labels(), load_contract("L3"), TOL) == ""


def test_fingers_that_lose_contact_as_the_hand_rises_are_said_to_and_never_read_as_enough_force() -> None:
    """The duck of #36: 1.07 N per finger when the lift began, ~0 N after the hand rose 6 mm, the duck rose 1 mm."""
    lab = labels(**NOT_LIFTED, grip_force_at_lift_n=1.07, grip_force_min_held_n=0.0, contact_lost_hand_rise_m=0.0066)
    d = diagnose(lab, TOL)
    assert d is not None and d.mode == "lost_contact"
    assert d.words.startswith("not lifted: the fingers lost contact at the lift")
    assert "1.1 N" in d.words and "7 mm" in d.words and "rose 1 mm while the hand rose 100 mm" in d.words
    why = trial_reason(lab, load_contract("L3"), TOL)
    assert why.startswith(d.words) and ">=" not in why and "m g / (2 mu)" not in why


@pytest.mark.parametrize("kw, mode, words", [
    (dict(grip_force_at_lift_n=0.3, grip_force_target_n=1.0), "no_grip", "never gripped: 0.3 N per finger"),
    (dict(object_rotation_deg=45.0), "rotated_out", "rotated 45 deg out of the grasp"),
    (dict(grip_force_min_held_n=0.7), "slipped_at_lift", "slipped at the lift: the object slid down the pads with "
                                                         "0.7-1 N per finger"),
])
def test_each_way_a_lift_fails_is_told_apart(kw: dict[str, float], mode: str, words: str) -> None:
    d = diagnose(labels(**NOT_LIFTED, **kw), TOL)
    assert d is not None and d.mode == mode and words in d.words, d


def test_transport_and_release_failures_say_where_the_object_went() -> None:
    d = diagnose(labels(transported=0.0, released_in_target=0.0, slipped=1.0, slip_distance_m=0.015), TOL)
    assert d is not None and d.mode == "slipped_in_transport" and "slipped 15 mm in the hand" in d.words
    d = diagnose(labels(transported=0.0, released_in_target=0.0, slipped=1.0, slip_distance_m=0.08), TOL)
    assert d is not None and d.mode == "dropped_in_transport"
    d = diagnose(labels(transported=0.0, released_in_target=0.0, transport_error_m=0.05), TOL)
    assert d is not None and d.mode == "carried_off_target" and "50 mm from the target" in d.words
    # the penguin of #36: carried to the target, then off it after the fingers opened
    lab = labels(released_in_target=0.0, settled=0.0, place_error_m=0.105, transport_error_m=0.002,
                 release_drop_m=0.006, release_drift_m=0.104, settle_com_speed_m_per_s=0.085)
    d = diagnose(lab, TOL)
    assert d is not None and d.mode == "released_off_target"
    assert d.words.startswith("released off target by 105 mm (tolerance 30 mm)")
    for part in ("carried to 2 mm from the target", "fell 6 mm when the fingers opened", "moved 104 mm",
                 "still moving at 0.085 m/s"):
        assert part in d.words, d.words
    # the same penguin falling over as the fingers open
    d = diagnose({**lab, "release_rotation_deg": 86.0, "settled": 1.0}, TOL)
    assert d is not None and d.mode == "toppled" and "fell over (turned 86 deg)" in d.words, d
    d = diagnose(labels(settled=0.0, settle_com_speed_m_per_s=0.05), TOL)
    assert d is not None and d.mode == "not_settled" and "0.05 m/s" in d.words
    # in the target, its centre of mass nearly still, but the body still turning: a tall toy tipping over slowly
    d = diagnose(labels(settled=0.0, settle_com_speed_m_per_s=0.012, settle_turn_rate_deg_per_s=14.0), TOL)
    assert d is not None and d.mode == "not_settled" and "still tipping over at 14 deg/s" in d.words, d


def test_a_body_that_turns_is_not_at_rest_though_its_centre_barely_moves() -> None:
    """The `settled` label's turn rate: the rigid rotation of the particles over the window, about any axis."""
    from tasks.manipulation.outcome import frame_back, turn_rate_deg_per_s

    rng = np.random.default_rng(1)
    x = rng.normal(size=(300, 3)) * [0.03, 0.03, 0.08] + [0.0, 0.0, 0.09]
    c, s = math.cos(math.radians(1.5)), math.sin(math.radians(1.5))
    tipped = (x - [0.03, 0.0, 0.0]) @ np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]).T + [0.03, 0.0, 0.0]
    assert turn_rate_deg_per_s(x, tipped, 0.1) == pytest.approx(15.0, rel=1e-6)  # 1.5 deg in 0.1 s
    assert turn_rate_deg_per_s(x, x + [0.001, 0.0, 0.0], 0.1) == pytest.approx(0.0, abs=1e-6)
    assert turn_rate_deg_per_s(x, tipped, 0.0) == math.inf
    t = np.arange(10) / 30.0
    assert frame_back(t) == 6 and frame_back(t[:2]) == 0  # 0.1 s back at 30 fps: three frames


def test_exactly_one_mode_flag_per_failed_trial() -> None:
    for lab in (labels(**NOT_LIFTED), labels(released_in_target=0.0), labels(plan_failed=1.0, **NOT_LIFTED)):
        flags = mode_flags(lab, TOL)
        assert sorted(flags) == sorted(f"mode_{m}" for m in MODES) and sum(flags.values()) == 1.0


def test_the_object_rotation_in_the_hand_is_measured_in_the_gripper_frame() -> None:
    rng = np.random.default_rng(0)
    x = rng.normal(size=(200, 3)) * [0.03, 0.02, 0.01]
    a = np.radians(40.0)
    rz = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    eye = np.eye(3)
    assert _object_rotation_deg(x, x @ rz.T + 0.1, eye, eye) == pytest.approx(40.0, abs=1e-6)
    # the gripper turned with the object: no rotation in the hand
    assert _object_rotation_deg(x, x @ rz.T, eye, rz) == pytest.approx(0.0, abs=1e-5)


def _critique(metrics: dict[str, float]) -> Any:
    """The rule Critic on a trial's labels under the packaged L3 contract (with its routes)."""
    contract = load_contract("L3")
    routes = stage_routes("L3", contract.parameters)
    gates = [GateResult(gate=g.name, metric=g.metric, value=metrics.get(g.metric),
                        passed=g.passes(metrics.get(g.metric))) for g in contract.hard_gates]
    req = CriticRequest(stage="L3", values={}, gates=gates, metrics=metrics, targets=TargetBehaviour(),
                        editable_fields=contract.editable_fields)
    return RuleCritic(routes).critique(req).value, contract, routes


def _diagnosed(**kw: float) -> dict[str, float]:
    lab = labels(**kw)
    return {**lab, **mode_flags(lab, TOL)}


def test_a_slip_at_the_lift_asks_for_a_firmer_squeeze_and_a_slower_lift_not_the_same_plan() -> None:
    crit, contract, routes = _critique(_diagnosed(**NOT_LIFTED, grip_force_min_held_n=0.7))
    assert crit.verdict == "revise" and "mode_slipped_at_lift" in crit.rationale
    assert crit.directions["grip_force_scale"] == "increase" and crit.directions["lift_duration_s"] == "increase"
    assert crit.directions["grasp_rank"] == "next"
    assert not {"place_height_m", "release_duration_s"} & set(crit.directions)


def test_a_release_off_target_asks_for_a_lower_release_and_slower_opening() -> None:
    crit, contract, routes = _critique(_diagnosed(released_in_target=0.0, settled=0.0, place_error_m=0.105,
                                                  release_drift_m=0.1, settle_com_speed_m_per_s=0.08))
    assert crit.directions == {"place_height_m": "decrease", "release_duration_s": "increase"}, crit.directions
    # the Planner takes the release route (no squeeze, timing or grasp field is flagged)
    values = {f.name: (f.low + f.high) / 2 for f in contract.editable_fields}
    tried = HistoryEntry(iteration=0, action="revise_squeeze", values=values, probed=True, valid=False,
                         failed_gates=["released_in_target"])
    ctx = PlannerContext(stage="L3", permitted_actions=contract.permitted_actions, iteration=1, budget_left=3,
                         editable_fields=contract.editable_fields, current_values=values, history=[tried],
                         last_critique=crit, targets=TargetBehaviour(),
                         action_fields={a: routes.fields_of(a, list(values)) for a in contract.permitted_actions})
    decision = RulePlanner(routes).plan(ctx).value
    assert decision is not None and decision.action == "revise_release" and not decision.stop


def test_a_hard_limit_still_outranks_the_mode() -> None:
    crit, _, _ = _critique(_diagnosed(**NOT_LIFTED, max_finger_force_n=25.0, force_budget_violated=1.0))
    assert crit.directions.get("squeeze_depth_m") == "decrease"


def test_an_object_that_falls_over_when_let_go_is_held_another_way_first() -> None:
    """The plush penguin of #36: carried to 2 mm of the target, fell over (86 deg) once released; the loop tries
    another grasp (held across the way it leans it stands), then a lower, slower release, never the same plan."""
    crit, contract, routes = _critique(_diagnosed(released_in_target=0.0, place_error_m=0.094, release_drift_m=0.094,
                                                  release_rotation_deg=86.0))
    assert "mode_toppled" in crit.rationale
    assert crit.directions == {"grasp_rank": "next", "place_height_m": "decrease", "release_duration_s": "increase"}
    values = {f.name: (f.low + f.high) / 2 for f in contract.editable_fields}
    tried = HistoryEntry(iteration=0, action="revise_squeeze", values=values, probed=True, valid=False,
                         failed_gates=["released_in_target"])
    ctx = PlannerContext(stage="L3", permitted_actions=contract.permitted_actions, iteration=1, budget_left=3,
                         editable_fields=contract.editable_fields, current_values=values, history=[tried],
                         last_critique=crit, targets=TargetBehaviour(),
                         action_fields={a: routes.fields_of(a, list(values)) for a in contract.permitted_actions})
    decision = RulePlanner(routes).plan(ctx).value
    assert decision is not None and decision.action == "revise_grasp"


def test_the_reported_trial_ran_the_material_the_asset_carries() -> None:
    """The penguin of #36: its plan passed (trial 3), a material revision was confirmed (trial 6) but not adopted (no
    more robust); the trial L3 reports is trial 3, under the asset's own material, not the revision's trial 6."""
    from types import SimpleNamespace

    from contracts.manipulation import TrialRow
    from contracts.material import Material
    from tasks.manipulation.l3_record import chosen_attempt

    own = Material(youngs_modulus_pa=1.58e4, poisson_ratio=0.3, damping_rate_per_s=21.0)
    values = {"grasp_rank": 2.0}
    rows = [TrialRow(attempt=i, role=role, action="", values=v, labels={"lifted": 1.0})
            for i, (role, v) in enumerate([("selection", {"grasp_rank": 0.0}), ("selection", values),
                                           ("robustness", values), ("confirmation", values)])]
    ctx = SimpleNamespace(attempts=rows, material=own)
    assert chosen_attempt(ctx, values, own) is rows[1]  # type: ignore[arg-type]
    revised = own.model_copy(update={"damping_rate_per_s": 50.0})
    assert chosen_attempt(ctx, values, revised) is rows[3]  # type: ignore[arg-type]


def test_the_pass_line_says_which_conditions_held() -> None:
    """L3's pass is the nominal trial's; the console line says how the held-out and robustness conditions went."""
    from contracts.manipulation import ConditionRow, ConditionSummary
    from tasks.manipulation.l3_record import conditions_summary

    def row(success: bool) -> ConditionRow:
        return ConditionRow(target_xy_m=[0.08, 0.06], initial_yaw_deg=0.0, success=success, labels={}, attempt=None)

    held = [row(True), row(False), row(False)]
    rob = ConditionSummary(conditions=[row(False), row(False)], passed=0)
    assert conditions_summary(held, rob) == " (nominal condition; held out 1/3, robustness 0/2)"
    assert conditions_summary([], None) == ""
