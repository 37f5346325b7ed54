"""L3's phase gates: a later phase's failure caused by an earlier one suggests nothing of its own."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from contracts.agents import CriticRequest, TargetBehaviour
from contracts.evidence import GateResult
from contracts.stage import load_contract
from tasks.agents.rule import RuleCritic
from tasks.agents.vocab import StageRoutes, stage_routes

PHASE_GATES = ("lifted", "transported", "released_in_target", "settled")


def _critique(failed: set[str]):  # type: ignore[no-untyped-def]
    c = load_contract("L3")
    gates = [GateResult(gate=g.name, metric=g.metric, value=0.0 if g.metric in failed else 1.0,
                        passed=g.metric not in failed) for g in c.hard_gates]
    values = {"grasp_rank": 0.0, "squeeze_depth_m": 0.004, "closing_speed_m_per_s": 0.04, "lift_duration_s": 0.5,
              "transport_duration_s": 0.6, "substeps": 1.0}
    req = CriticRequest(stage="L3", values=values, metrics={m: 0.0 for m in failed}, gates=gates,
                        targets=TargetBehaviour(), editable_fields=c.editable_fields)
    return RuleCritic(stage_routes("L3", c.parameters)).critique(req).value


def test_a_failed_lift_asks_for_squeeze_or_grasp_not_for_slower_timing() -> None:
    crit = _critique(set(PHASE_GATES))
    assert crit.verdict == "revise"
    assert crit.directions == {"squeeze_depth_m": "increase", "grasp_rank": "next"}
    assert set(crit.unmet) == set(PHASE_GATES)  # every failure is still reported


def test_a_later_phase_that_fails_on_its_own_still_suggests_its_revision() -> None:
    assert _critique({"settled"}).directions == {"lift_duration_s": "increase"}
    crit = _critique({"released_in_target", "settled"})  # lifted and carried, then put down outside and rolling
    assert crit.directions["transport_duration_s"] == "increase" and "squeeze_depth_m" not in crit.directions


def test_after_must_name_another_gate_of_the_table() -> None:
    with pytest.raises(ValidationError, match="'after' must name another gate"):
        StageRoutes.model_validate({"gates": {"settled": {"after": "lifted"}}})
