"""A trial plan's reach check (tasks.manipulation.context.plan_executable, #37): planning a trajectory to see that the
arm executes it takes ~1 s on the CPU and ran for every trial on every fully cached rerun; the answer is the same as
plan_or_error's, and a second check of the same plan on the same body is read from the cache without planning."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import tasks.manipulation.context as context
from contracts.stage import load_contract
from tasks.manipulation.context import L3Context, L3Options, initial_values, plan_executable
from tasks.manipulation.trial import plan_or_error, reachable_plan
from tasks.robot import select_grasps
from tests.l3.conftest import FIRM, Cube


@pytest.fixture
def planned(monkeypatch: pytest.MonkeyPatch) -> list[object]:
    """The plans context.plan_or_error is asked to plan (it still plans them)."""
    seen: list[object] = []

    def counting(plan, body, settings=None):  # noqa: ANN001, ANN202
        seen.append(plan)
        return plan_or_error(plan, body, settings)

    monkeypatch.setattr(context, "plan_or_error", counting)
    return seen


def test_the_check_answers_as_planning_does_and_plans_once(cube: Cube, planned: list[object]) -> None:
    near, far = cube.plan(0.004), cube.plan(0.004, target_xy_m=(1.2, 0.0))  # 1.2 m: out of the Panda's reach
    assert [plan_executable(p, cube.body) for p in (near, far)] == [True, False]  # planned (plan_or_error's answers)
    assert len(planned) == 2
    assert [plan_executable(p, cube.body) for p in (near, far)] == [True, False]  # from the cache
    assert len(planned) == 2
    taller = replace(cube.body, height_m=cube.body.height_m + 0.01)
    assert plan_executable(near, taller)  # another body height is another question
    assert len(planned) == 3


def test_the_context_plans_as_reachable_plan_does(cube: Cube, planned: list[object]) -> None:
    grasps = select_grasps(cube.body.surface_points_m, cube.body.surface_normals,
                           np.asarray(cube.physical.center_of_mass_m), cube.physical.gripper_friction).candidates[:3]
    ctx = L3Context(asset_dir=Path("/nonexistent"), body=cube.body, physical=cube.physical, material=FIRM,
                    material_source="given", grasps=grasps, options=L3Options(), contract=load_contract("L3"))
    values = initial_values(ctx)
    for target, yaw in ((None, 0.0), ((0.12, 0.15), 45.0)):  # nominal, and a turned object placed elsewhere
        plan = ctx.plan(values, target, yaw)
        checked = len(planned)
        assert checked > 0
        assert ctx.plan(values, target, yaw) == plan and len(planned) == checked  # a rerun's check: from the cache
        assert reachable_plan(plan, grasps, cube.body) == plan  # what reachable_plan, planning uncached, keeps
        planned.clear()


def test_a_trajectory_is_planned_once_per_process_for_the_same_plan_body_height_and_settings(
        cube: Cube, monkeypatch: pytest.MonkeyPatch) -> None:
    """plan_executable's check and the trial itself plan the same trajectory: the second is the first's (a trajectory
    is not changed once planned); another plan, body height, pad or place setting is planned anew."""
    import tasks.manipulation.trial as trial
    from tasks.manipulation.trial import TrialSettings, trial_trajectory

    calls: list[object] = []
    real = trial.plan_trajectory

    def counting(plan, **kw):  # noqa: ANN001, ANN003, ANN202
        calls.append(plan)
        return real(plan, **kw)

    monkeypatch.setattr(trial, "plan_trajectory", counting)
    monkeypatch.setattr(trial, "_PLANNED", type(trial._PLANNED)())
    plan, s = cube.plan(0.004), TrialSettings()
    first = trial_trajectory(plan, cube.body, s)
    assert trial_trajectory(plan, cube.body, s) is first and plan_or_error(plan, cube.body)[0] is first
    assert len(calls) == 1
    others = [trial_trajectory(cube.plan(0.005), cube.body, s),
              trial_trajectory(plan, replace(cube.body, height_m=cube.body.height_m + 0.01), s),
              trial_trajectory(plan, cube.body, replace(s, pad_half_thickness_m=0.005)),
              trial_trajectory(plan, cube.body, replace(s, place_support_fraction=None)),
              trial_trajectory(plan, cube.body, s, place_stop_s=first.lower_window_s[0] + 0.01)]
    assert len(calls) == 6 and all(o is not first for o in others)
    fresh = real(plan, object_pose=trial.object_pose(plan), object_height_m=cube.body.height_m,
                 pad_half_thickness_m=s.pad_half_thickness_m,
                 place=trial.PlaceApproach(height_m=s.place_guard_height_m, speed_m_per_s=s.place_guard_speed_m_per_s,
                                           brake_s=s.place_brake_s))
    t = np.linspace(0.0, first.duration_s, 50)
    np.testing.assert_array_equal(fresh.pads_at(t).position_m, first.pads_at(t).position_m)  # what it would plan
