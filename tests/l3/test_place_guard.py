"""The force-guarded place's control in run_trial, on a stand-in simulator: an object that hangs 2 cm lower in the
hand than where it was gripped meets the table 1 cm above the planned place height; the hand stops there."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import tasks.manipulation.trial as trial_module
from tasks.manipulation.trial import TrialSettings, run_trial
from tests.l3.conftest import FIRM, TOL, Cube

HANG_M = 0.02


class HangingObject:
    """Rigid particles carried by the pads' midpoint from the lift on, HANG_M lower than where they were gripped; never
    below the table (particle centres at z >= 0), which then carries the whole weight (the stand-in for the MPM: this tests the control, not the physics)."""

    def __init__(self, x0: np.ndarray, weight_n: float, lift_start_s: float, t_start_s: float) -> None:
        self.x0, self.x, self.weight, self.time_s = x0, x0.copy(), weight_n, 0.0
        self.lift_start, self.t_start = lift_start_s, t_start_s
        self.mid0: np.ndarray | None = None
        self.mid = np.zeros(3)
        self.pads: dict[int, np.ndarray] = {}
        self.control = self

    def set_grid_velocity(self, scene: int, v: Any) -> None:
        pass

    def set_collider(self, scene: int, f: int, position_m: Any, linear_velocity_m_per_s: Any, **_: Any) -> None:
        self.pads[f] = (np.asarray(position_m, float), np.asarray(linear_velocity_m_per_s, float))

    def particles(self, scene: int) -> dict[str, np.ndarray]:
        return {"x": self.x, "v": np.zeros_like(self.x), "F": np.broadcast_to(np.eye(3), (len(self.x), 3, 3)).copy()}

    def advance(self, dt: float) -> Any:
        mid = 0.5 * sum(p + v * dt for p, v in self.pads.values())
        self.time_s += dt
        if self.time_s + self.t_start < self.lift_start:  # the hand grips at its lowest point: carried from there
            self.mid0 = mid
            return self._report(on_table=True)
        assert self.mid0 is not None
        x = self.x0 + (mid - self.mid0) - np.array([0.0, 0.0, HANG_M])
        on_table = float(x[:, 2].min()) <= 0.0
        x[:, 2] -= min(0.0, float(x[:, 2].min()))
        self.x = x
        return self._report(on_table)

    def _report(self, on_table: bool) -> Any:
        ground = np.array([[0.0, 0.0, -self.weight if on_table else 0.0]])  # the object's force on the table
        health = SimpleNamespace(ok=True, first=lambda: None)
        return SimpleNamespace(steps=1, ground_force_n=ground, health=health,
                               collider_force=lambda model, scene, f: np.zeros(3))


def _run(monkeypatch: pytest.MonkeyPatch, cube: Cube, settings: TrialSettings) -> Any:
    plan = cube.plan(0.004)
    traj = trial_module.trial_trajectory(plan, cube.body, settings)
    t_start = traj.phases["closure"][0] - settings.settle_before_closure_s
    weight = cube.physical.mass_kg * 9.81
    made: list[HangingObject] = []

    def simulator(model: Any) -> HangingObject:
        made.append(HangingObject(model.x0, weight, traj.phases["lift"][0], t_start))
        return made[-1]

    def build(scenes: list[Any], cfg: Any) -> Any:
        return SimpleNamespace(dx=cfg.dx_m, x0=np.asarray(scenes[0].positions_m, float))

    monkeypatch.setattr(trial_module, "Simulator", simulator)
    monkeypatch.setattr(trial_module, "build_model", build)
    # the stand-in hangs HANG_M low: its rise is short of the failed-lift threshold, which does not matter here
    settings_ = TrialSettings(**{**settings.__dict__, "settle_until_rest_max_s": 0.0, "stop_when_lift_fails": False})
    return run_trial(cube.body, cube.physical, FIRM, plan, settings_, TOL), traj


def test_the_hand_stops_lowering_where_the_table_takes_the_object(monkeypatch: pytest.MonkeyPatch,
                                                                   cube: Cube) -> None:
    r, planned = _run(monkeypatch, cube, TrialSettings())
    guard = r.info["place_guard"]
    assert r.metrics["place_guard_stopped"] == 1.0
    assert guard["support_n"] >= 0.5 * guard["weight_n"]
    # met the table HANG_M - place_height - the lowest particle centre's height above the table (1 cm - 1.25 mm) above
    # the planned place; stopped within one control interval at 0.1 m/s (0.4 mm) and the 20 ms brake (1 mm) below
    touch = HANG_M - 0.01 - 0.5 * cube.body.spacing_m
    assert touch - 0.002 < guard["stopped_above_plan_m"] < touch
    pads_z = r.arrays["finger_position_m"][:, :, 2].mean(axis=1)
    phase = r.arrays["phase"]
    release = pads_z[phase == trial_module.PHASES.index("release")]
    assert np.ptp(release) < 1e-4  # the hand waits while the fingers open
    planned_z = float(planned.pads_at(np.array([planned.phases["release"][0]])).position_m[0, :, 2].mean())
    assert release.mean() - planned_z == pytest.approx(guard["stopped_above_plan_m"], abs=1e-4)
    assert r.info["phases"]["settle"][1] < planned.duration_s


def test_without_the_guard_the_hand_lowers_to_the_planned_height(monkeypatch: pytest.MonkeyPatch, cube: Cube) -> None:
    r, planned = _run(monkeypatch, cube, TrialSettings(place_support_fraction=None))
    assert r.info["place_guard"] == {} and r.metrics["place_guard_stopped"] == 0.0
    assert r.info["phases"]["transport"][1] == pytest.approx(planned.phases["transport"][1])
