"""The rule backend is a real search: it converges within the contract's budget across orders of magnitude."""

from __future__ import annotations

import pytest
from harness_fakes import FakeL2Probes, fake_modulus_pa, fake_rebound, l2_targets

from contracts import ProbeResult, ProbeSpec, load_contract
from contracts.agents import TargetBand, TargetBehaviour
from tasks.agents.orchestrator import run_stage


@pytest.mark.parametrize("modulus_pa", [1.2e3, 1e4, 2e5, 3e6, 5e6])
@pytest.mark.parametrize("rebound", [0.05, 0.3])
def test_converges_across_decades(l2, modulus_pa: float, rebound: float) -> None:
    probes = FakeL2Probes()
    out = run_stage(l2, probes, l2_targets(modulus_pa, rebound))
    assert out.status == "accepted", out.message
    assert out.attempts_used <= 1 + l2.revision_budget
    assert modulus_pa / 1.1 <= fake_modulus_pa(out.values["youngs_modulus_pa"]) <= modulus_pa * 1.1
    assert abs(fake_rebound(out.values["damping_rate_per_s"]) - rebound) <= 0.02
    assert out.attempts[-1].verdict == "accepted" and out.score == 1.0
    assert len(probes.calls) == out.attempts_used  # every attempt ran its probes once, nothing else ran


def test_deterministic(l2) -> None:
    a = run_stage(l2, FakeL2Probes(), l2_targets(7e5))
    b = run_stage(l2, FakeL2Probes(), l2_targets(7e5))
    assert [x.proposal for x in a.attempts] == [x.proposal for x in b.attempts]


def test_stops_early_when_priors_already_meet_targets(l2) -> None:
    e = 3e4
    t = TargetBehaviour(bands=[TargetBand(metric="effective_modulus_pa", low=fake_modulus_pa(e) / 1.2,
                                          high=fake_modulus_pa(e) * 1.2, scale="log")], priors={"youngs_modulus_pa": e})
    out = run_stage(l2, FakeL2Probes(), t)
    assert out.status == "accepted" and out.attempts_used == 1


def test_gate_failure_bounds_the_search(l2) -> None:
    """Below 2e4 Pa the fake collapses (j_min gate): the search must climb out and still find the band."""
    probes = FakeL2Probes(unstable_below_pa=2e4)
    t = l2_targets(3e4)
    out = run_stage(l2, probes, t, initial={"youngs_modulus_pa": 2e3, "poisson_ratio": 0.3, "damping_rate_per_s": 5.0})
    first = out.attempts[0]
    assert first.verdict == "revise" and first.diagnosis == "material"
    assert first.directions["youngs_modulus_pa"] == "increase"
    assert out.status == "accepted", out.message


def test_l3_ordered_enumeration_of_action_revisions() -> None:
    """Pick-and-place fake: too little squeeze drops the object, too much breaks the force budget; grasp 0 and 1 fail
    transport. Squeeze is bisected between the two failure modes, then grasps are enumerated."""
    l3 = load_contract("L3").model_copy(update={"revision_budget": 12})

    def pick_place(values: dict[str, float], action: str) -> list[ProbeResult]:
        squeeze, rank = values["squeeze_depth_m"], int(values["grasp_rank"])
        lifted = squeeze >= 0.009
        force = 1500.0 * squeeze
        ok_grasp = rank >= 2
        m = {"lifted": float(lifted), "transported": float(lifted and ok_grasp), "released_in_target": float(lifted and ok_grasp),
             "settled": 1.0, "max_finger_force_n": force, "numerically_healthy": 1.0, "max_strain": 0.2, "strain_p99": 0.1}
        return [ProbeResult(spec=ProbeSpec(kind="pick_and_place"), metrics=m)]

    out = run_stage(l3, pick_place, TargetBehaviour(), initial={
        "grasp_rank": 0, "squeeze_depth_m": 0.002, "closing_speed_m_per_s": 0.02, "lift_duration_s": 1.0,
        "transport_duration_s": 1.5, "substeps": 1})
    assert out.status == "accepted", out.message
    assert 0.009 <= out.values["squeeze_depth_m"] <= 20.0 / 1500.0
    assert out.values["grasp_rank"] == 2
    actions = [a.action for a in out.attempts]
    assert "revise_squeeze" in actions and "revise_grasp" in actions


def test_l3_strain_escalates_to_material() -> None:
    l3 = load_contract("L3")

    def too_soft(values: dict[str, float], action: str) -> list[ProbeResult]:
        m = {"lifted": 1.0, "transported": 1.0, "released_in_target": 1.0, "settled": 1.0, "max_finger_force_n": 5.0,
             "numerically_healthy": 1.0, "max_strain": 0.9, "strain_p99": 0.8}
        return [ProbeResult(spec=ProbeSpec(kind="pick_and_place"), metrics=m)]

    out = run_stage(l3, too_soft, initial={"grasp_rank": 0, "squeeze_depth_m": 0.01, "closing_speed_m_per_s": 0.02,
                                           "lift_duration_s": 1.0, "transport_duration_s": 1.5, "substeps": 1})
    assert out.status == "escalated" and out.escalation == "revise_material"
    assert out.attempts[-1].verdict == "escalated" and out.attempts_used == 2


def test_contract_parameters_can_override_the_route_table(l2) -> None:
    """A stage YAML may reorder routes declaratively: damping first."""
    c = l2.model_copy(update={"parameters": {**l2.parameters, "harness_routes": {
        "route_order": ["revise_damping", "revise_stiffness"]}}})
    out = run_stage(c, FakeL2Probes(), l2_targets(8e5, 0.3))
    assert out.status == "accepted" and out.attempts[1].action == "revise_damping"


def test_agent_schemas_are_registered() -> None:
    from contracts.registry import SCHEMAS

    for name in ("PlannerDecision", "Candidate", "Critique", "TargetBehaviour", "TargetBand", "StageOutcome"):
        assert SCHEMAS[name].model_json_schema()["title"] == name


def test_l1_mass_gate_is_steered_by_the_mass_band() -> None:
    """L1: the plausibility gate says only 'implausible'; the mass band on mass_kg tells the density which way."""
    l1 = load_contract("L1")
    volume_m3 = 2e-3

    def rigid(values: dict[str, float], action: str) -> list[ProbeResult]:
        mass = values["density_kg_per_m3"] * volume_m3
        mu = values["ground_friction"]
        m = {"mass_kg": mass, "mass_plausibility": float(0.2 <= mass <= 0.4), "place_tilt_deg": 0.5,
             "place_penetration_m": 0.0, "place_settle_time_s": 0.4, "drop_penetration_m": 0.0,
             "drop_rest_displacement_m": 0.001, "slide_below_sticks": 1.0, "slide_above_slides": 1.0,
             "slide_accel_error_rel": 0.02 if mu > 0 else 1.0}
        return [ProbeResult(spec=ProbeSpec(kind="place"), metrics=m)]

    t = TargetBehaviour(bands=[TargetBand(metric="mass_kg", unit="kg", low=0.2, high=0.4, scale="log")],
                        priors={"density_kg_per_m3": 30.0, "ground_friction": 0.5, "gripper_friction": 0.8})
    out = run_stage(l1, rigid, t)
    assert out.attempts[0].verdict == "revise" and out.attempts[0].directions["density_kg_per_m3"] == "increase"
    assert out.status == "accepted" and 0.2 <= out.metrics["mass_kg"] <= 0.4


def test_a_field_with_an_expansion_grows_its_step_instead_of_jumping_to_the_bound() -> None:
    """L3's squeeze after two slips: 5 -> 10 mm did not hold, so 10 -> 17.5 mm (1.5x the last step), not the
    contract's deepest squeeze; without the expansion the search goes straight to the bound (as L2's fields do)."""
    from contracts.agents import HistoryEntry
    from contracts.stage import EditableField
    from tasks.agents.rule import propose_field
    from tasks.agents.vocab import stage_routes

    spec = EditableField(name="squeeze_depth_m", low=0.0, high=0.04)
    history = [HistoryEntry(iteration=i, action="revise_squeeze", values={"squeeze_depth_m": v}, valid=False,
                            probed=True, directions={"squeeze_depth_m": "increase"})
               for i, v in enumerate((0.005, 0.010))]
    routes = stage_routes("L3", load_contract("L3").parameters)
    assert routes.expansion["squeeze_depth_m"] == 1.5
    nxt = propose_field(spec, "increase", 0.010, history, TargetBehaviour(), routes)
    assert nxt == pytest.approx(0.0175)
    jump = propose_field(spec, "increase", 0.010, history, TargetBehaviour(), routes.model_copy(update={"expansion": {}}))
    assert jump == pytest.approx(0.04)
    near = propose_field(spec, "increase", 0.035, history, TargetBehaviour(), routes)  # capped by the bound
    assert near == pytest.approx(0.04)
