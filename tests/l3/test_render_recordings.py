"""Every L3 trial is a probe with its Rerun recording: robot links, pads, particles, Gaussians and per-finger force
curves, read back with rerun's own reader; stored as recordings/L3_trial_NN.rrd (its states in interaction/attempt_NNN),
made once per trial (cached) and written atomically."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tasks.manipulation.replay import write_rrd
from tasks.record import read_recording, recording_digest
from tests.l3.render_helpers import cube_context, short_attempt, synthetic_attempt

LINKS = [f"world/robot/panda_link{i}" for i in range(8)] + ["world/robot/panda_hand", "world/robot/panda_leftfinger",
                                                            "world/robot/panda_rightfinger"]


@pytest.fixture(scope="module")
def attempt() -> tuple[dict[str, np.ndarray], dict]:
    """A short attempt: 0.3 s of approach, then closure and lift with 2 N on each finger while holding."""
    return short_attempt(approach_s=0.3, length_s=0.8)


def _scalars(path: Path, entity: str) -> np.ndarray:
    """The values logged on a metrics entity, in time order, read back from the .rrd."""
    from rerun.chunk import RrdReader

    rows = []
    for chunk in RrdReader(str(path)).stream():
        if str(chunk.entity_path).lstrip("/") != entity:
            continue
        batch = chunk.to_record_batch()
        names = batch.schema.names
        t = batch.column(next(n for n in names if n.endswith("sim_time"))).cast("int64").to_pylist()
        v = batch.column(next(n for n in names if "scalars" in n.lower())).to_pylist()
        rows += [(ti, float(np.ravel(vi)[0])) for ti, vi in zip(t, v)]
    return np.array([v for _, v in sorted(rows)])


def test_a_trial_recording_holds_robot_pads_object_and_force_curves(attempt: tuple, tmp_path: Path) -> None:
    arrays, attrs = attempt
    path = write_rrd(arrays, attrs, tmp_path / "L3_attempt_000.rrd")
    s = read_recording(path)
    want = {*LINKS, "world/colliders/finger_0", "world/colliders/finger_1", "world/object/particles",
            "world/object/gaussians", "metrics/finger_0_force_n", "metrics/finger_1_force_n", "harness/log"}
    assert want <= s.entity_paths and {"frame", "sim_time"} <= s.timelines
    n_approach, n_frames = len(arrays["approach_t_s"]), len(arrays["frame_t_s"])
    # a link: its mesh (static) and one pose per robot state shown (the approach's and each recorded frame's)
    assert s.rows_per_entity["world/robot/panda_link7"] == 1 + n_approach + n_frames
    assert s.rows_per_entity["world/colliders/finger_0"] == n_approach + n_frames
    # the per-finger force curves at the control rate are the recorded forces
    for f in range(2):
        got = _scalars(path, f"metrics/finger_{f}_force_n")
        np.testing.assert_allclose(got, np.linalg.norm(arrays["finger_force_n"][:, f], axis=1), rtol=1e-6)
    assert _scalars(path, "metrics/finger_0_force_n").max() == pytest.approx(2.0)


def test_a_box_gripper_is_recorded_as_boxes(tmp_path: Path) -> None:
    arrays, attrs = synthetic_attempt(edge_m=0.07, spacing_m=0.01, gripper="robotiq_2f85", approach_s=0.1,
                                      end_s=None)
    keep = arrays["frame_t_s"] < arrays["frame_t_s"][0] + 0.2
    short = dict(arrays, **{k: arrays[k][keep] for k in ("frame_t_s", "frame_control_index", "particles_x_m",
                                                         "particles_F")})
    s = read_recording(write_rrd(short, attrs, tmp_path / "box.rrd"))
    assert "world/robot/gripper" in s.entity_paths and "world/robot/panda_link7" in s.entity_paths
    assert not {"world/robot/panda_hand", "world/robot/panda_leftfinger"} & s.entity_paths


def test_every_stored_trial_gets_its_recording_made_once(attempt: tuple, tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """L3's _store: interaction/attempt_NNN and recordings/L3_trial_NN.rrd for each trial, failed ones included, the
    recording named by the trial's one number (from 1, as the console and manipulation.json count); the same trial
    stored again reuses the cached recording (nothing is re-recorded)."""
    from contracts.probes import ProbeResult, ProbeSpec
    from contracts.robot import ActionPlan
    from tasks.manipulation import replay as replay_module

    arrays, attrs = attempt
    ctx = cube_context(tmp_path / "asset")
    plan = ActionPlan.model_validate(attrs["plan"])
    failed = {"lifted": 0.0, "transported": 0.0, "released_in_target": 0.0, "settled": 1.0}
    out = {"probe": ProbeResult(spec=ProbeSpec(kind="pick_and_place"), metrics=failed), "arrays": arrays, "info": {}}
    inputs = {"plan": plan, "settings": {"substeps": 1}}
    ctx._store(out, plan, inputs, {"squeeze_depth_m": 0.003}, "selection", "", None, 0.0)
    rrd0 = tmp_path / "asset" / "recordings" / "L3_trial_01.rrd"
    assert ctx.attempts[0].recording == "recordings/L3_trial_01.rrd" and rrd0.is_file()
    assert (tmp_path / "asset" / "interaction" / "attempt_000").is_dir()
    assert set(LINKS) <= read_recording(rrd0).entity_paths
    assert not list((tmp_path / "asset" / "recordings").glob("*.tmp"))  # nothing half-written left

    def no_rerecording(*args: object, **kwargs: object) -> None:
        raise AssertionError("a cached trial's recording was written again")

    monkeypatch.setattr(replay_module, "write_rrd", no_rerecording)
    ctx._store(out, plan, inputs, {"squeeze_depth_m": 0.003}, "held_out", "", None, 0.0)
    rrd1 = tmp_path / "asset" / "recordings" / "L3_trial_02.rrd"
    assert ctx.attempts[1].recording == "recordings/L3_trial_02.rrd"
    assert recording_digest(rrd1) == recording_digest(rrd0)
    ctx.recordings = False  # run_l3(recordings=False): no recordings
    ctx._store(out, plan, inputs, {"squeeze_depth_m": 0.003}, "held_out", "", None, 0.0)
    assert ctx.attempts[2].recording is None
