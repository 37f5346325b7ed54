"""A squeeze grasp of a soft object wider than the Franka Hand: the Planner's wide gripper, a force-controlled closure
centimetres deep, a pick-and-place that holds by the two-jaw friction law within the force budget."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan
from tasks.manipulation.body import box_body
from tasks.manipulation.outcome import TrialTolerances
from tasks.manipulation.trial import TrialResult, TrialSettings, run_trial
from tasks.robot.choice import choose_gripper
from tasks.robot.grasp import GraspSettings, select_grasps
from tasks.robot.gripper import gripper

EDGE_M = 0.10
SPACING_M = 0.008
PLUSH = Material(youngs_modulus_pa=1e4, poisson_ratio=0.3, damping_rate_per_s=16.0)
RHO = 100.0  # a plush toy's whole-object density [kg/m^3]: 0.1 kg
MU = 0.7
BUDGET_N = 20.0


@pytest.fixture(scope="module")
def plush_pick() -> tuple[TrialResult, dict[str, float], str, str]:
    """The Planner's gripper for a 10 cm plush cube, its force target and squeeze range, and one draft trial."""
    body = box_body(EDGE_M, SPACING_M)
    phys = PhysicalModel(density_kg_per_m3=RHO, volume_m3=body.volume_m3, mass_kg=RHO * body.volume_m3,
                         particle_count=len(body.particles_m), particle_spacing_m=SPACING_M, ground_friction=0.5,
                         gripper_friction=MU, center_of_mass_m=(0.0, 0.0, EDGE_M / 2), extents_m=(EDGE_M,) * 3,
                         category="plush_animal")
    com = np.asarray(phys.center_of_mass_m)
    choice = choose_gripper(body.surface_points_m, body.surface_normals, com, MU, PLUSH.youngs_modulus_pa,
                            PLUSH.poisson_ratio, phys.mass_kg, budget_n=BUDGET_N)
    assert choice.name is not None, choice.reason
    option = choice.option(choice.name)
    sq = option.squeeze
    assert sq is not None
    grasp = select_grasps(body.surface_points_m, body.surface_normals, com, MU, settings=GraspSettings(
        gripper=choice.name, soft_indent_m=sq.soft_indent_m)).best()
    plan = ActionPlan(grasp=grasp, gripper=choice.name, gripper_reason=choice.reason, squeeze_depth_m=sq.high_m,
                      grip_force_limit_n=sq.force_target_n, closing_speed_m_per_s=0.04, target_xy_m=(0.08, 0.06),
                      closure_duration_s=0.3, lift_duration_s=0.5, transport_duration_s=0.6, release_duration_s=0.2,
                      retreat_duration_s=0.2, settle_duration_s=0.2)
    result = run_trial(body, phys, PLUSH, plan, TrialSettings(), TrialTolerances(force_budget_n=BUDGET_N))
    return result, sq.as_dict(), choice.name, choice.reason


def test_a_plush_wider_than_the_franka_hand_goes_to_the_wide_gripper(plush_pick) -> None:  # type: ignore
    _, _, name, reason = plush_pick
    assert gripper(name).stroke_m > EDGE_M > gripper("franka_hand").stroke_m
    assert name == "robotiq_2f140" and "franka_hand" in reason  # the smaller ones were weighed and why they lost


def test_a_force_controlled_squeeze_picks_and_places_the_plush(plush_pick) -> None:  # type: ignore[no-untyped-def]
    r, sq, _, _ = plush_pick
    m = r.metrics
    assert m["lifted"] == 1 and m["transported"] == 1 and m["released_in_target"] == 1 and m["settled"] == 1
    assert m["numerically_healthy"] == 1 and m["strain_p99"] <= 0.6
    # the closure stopped at the force target, centimetres into the plush, as the linear estimate said within 2x
    assert m["grip_guard_stopped"] == 1 and m["grip_force_target_n"] == pytest.approx(sq["force_target_n"])
    assert m["squeeze_per_finger_m"] > 0.005
    assert 0.5 < m["squeeze_per_finger_m"] / sq["depth_m"] < 2.0
    assert r.info["grip_guard"]["closure_skipped_s"] > 0.0  # the lift started once the target was reached


def test_the_hold_obeys_the_two_jaw_law_within_the_force_budget(plush_pick) -> None:  # type: ignore[no-untyped-def]
    """Held in the air the fingers carry the weight (vertical force ~ m g) and 2 mu N >= m g with the planned margin
    nearly kept (the target is 3 m g / (2 mu)); no finger's force exceeds the budget, nor much the target."""
    r, sq, _, _ = plush_pick
    m = r.metrics
    assert m["held_airborne_s"] > 0.5
    assert abs(m["hold_vertical_ratio"] - 1.0) < 0.2
    assert 2.0 * MU * m["hold_normal_force_n"] >= 1.5 * m["weight_n"]
    assert m["hold_friction_ratio"] >= 1.5 and m["hold_min_capacity_ratio"] >= 1.0
    assert m["force_budget_violated"] == 0 and m["max_finger_force_n"] <= BUDGET_N
    assert m["max_finger_force_n"] <= 1.5 * sq["force_target_n"]
