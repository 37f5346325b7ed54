"""The trial's simulation frame: a turn about the vertical that puts the closing axis at a fixed angle to the grid."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tasks.manipulation.frame import SimFrame
from tasks.manipulation.trial import TrialSettings, run_trial
from tasks.robot import PHASES
from tests.l3.conftest import FIRM, TOL


def _rotate_by_quat(q_xyzw: np.ndarray, v: np.ndarray) -> np.ndarray:
    x, y, z, w = q_xyzw
    u = np.array([x, y, z])
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def test_the_frame_turns_points_vectors_tensors_and_orientations_consistently() -> None:
    rng = np.random.default_rng(3)
    f = SimFrame(math.radians(37.0))
    r = f.rotation
    pts = rng.normal(size=(5, 3))
    assert np.allclose(f.to_world(f.to_sim(pts)), pts, atol=1e-12)
    assert np.allclose(f.to_sim(pts)[:, 2], pts[:, 2])  # the vertical is kept: ground and gravity do not move
    m = rng.normal(size=(4, 3, 3))
    m_sim = np.einsum("ij,njk,lk->nil", r, m, r)  # a tensor field turned into the simulation frame
    assert np.allclose(f.tensor_to_world(m_sim), m, atol=1e-12)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    v = rng.normal(size=3)
    assert np.allclose(_rotate_by_quat(f.quat_to_sim(q), v), r @ _rotate_by_quat(q, v), atol=1e-12)


@pytest.mark.parametrize("angle_deg", [0.0, 45.0])
def test_the_aligned_frame_puts_the_closing_axis_at_the_chosen_angle_to_the_grid(angle_deg: float) -> None:
    axis = np.array([-0.245, 0.969, 0.013])
    c = SimFrame.aligned(axis, angle_deg).to_sim(axis)
    assert math.degrees(math.atan2(c[1], c[0])) == pytest.approx(angle_deg, abs=1e-9)
    assert SimFrame.aligned(axis, None).is_identity
    assert SimFrame.aligned(np.array([0.0, 0.0, 1.0]), 45.0).is_identity  # no horizontal part: nothing to align


@pytest.mark.slow  # tens of seconds on 2 cores (CI time, 2026-11-29)
def test_a_grasp_lifts_the_same_at_every_yaw_and_reports_in_the_world_frame(cube) -> None:  # type: ignore[no-untyped-def]
    """The same grasp on the object turned by 0 and 37 degrees: in the aligned frame the grid sees the same
    contact, so the lift, the grip force and the slip agree; the recording is in the world frame."""
    s = replace(TrialSettings(), closing_axis_to_grid_deg=45.0, stop_when_lift_fails=True)
    runs = {yaw: run_trial(cube.body, cube.physical, FIRM, cube.plan(0.004, initial_yaw_deg=yaw), s, TOL)
            for yaw in (0.0, 37.0)}
    a, b = runs[0.0].metrics, runs[37.0].metrics
    assert a["lifted"] == b["lifted"] == 1.0
    assert b["lift_rise_m"] == pytest.approx(a["lift_rise_m"], abs=2e-4)
    assert b["hold_normal_force_n"] == pytest.approx(a["hold_normal_force_n"], rel=0.02)
    assert b["slip_distance_m"] == pytest.approx(a["slip_distance_m"], abs=5e-4)
    for r in runs.values():
        arr = r.arrays
        # the first recorded frame is the object at rest where the world put it (turned back from the sim frame)
        assert np.allclose(arr["particles_x_m"][0], arr["rest_particles_m"], atol=2e-4)
        # the fingers' mean normal force points along the world closing axis (squeezing: finger 0 pushed to -axis)
        axis = arr["closing_axis_world"]
        hold = np.nanmean(arr["finger_force_n"][arr["phase"] == PHASES.index("lift")], axis=0)
        assert hold[0] @ axis < 0.0 < hold[1] @ axis
    # the object turned by 37 degrees is simulated turned back by 37 degrees more
    turn = runs[37.0].info["sim_frame_yaw_deg"] - runs[0.0].info["sim_frame_yaw_deg"]
    assert (turn + 37.0 + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=1e-6)
