"""A written .rrd reads back (rerun's RrdReader) with the logged entities and timelines."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from tasks.record import COLLIDERS, GAUSSIANS, HARNESS_LOG, PARTICLES, ProbeRecording, read_recording


def test_recording_reads_back_with_entities_and_timelines(tmp_path: Path) -> None:
    path = tmp_path / "recordings" / "drop.rrd"
    rng = np.random.default_rng(0)
    with ProbeRecording(path, recording_id="drop-abc") as rec:
        for i in range(5):
            rec.set_time(i, i * 1e-3)
            rec.particles(rng.random((50, 3)))
            rec.gaussians(rng.random((20, 3)), np.full((20, 3), 0.01), np.tile([0, 0, 0, 1.0], (20, 1)), rng.random((20, 3)))
            rec.box_collider("finger_left", np.zeros(3), np.full(3, 0.01))
            rec.scalar("kinetic_energy_j", float(i))
        rec.log("candidate accepted")
    summary = read_recording(path)
    assert summary.recording_ids == ["drop-abc"]
    assert {PARTICLES, GAUSSIANS, f"{COLLIDERS}/finger_left", "metrics/kinetic_energy_j", HARNESS_LOG} <= summary.entity_paths
    assert {"frame", "sim_time"} <= summary.timelines
    assert summary.rows_per_entity[PARTICLES] == 5
    assert not list(tmp_path.rglob("*.tmp"))


def test_failed_probe_leaves_no_recording(tmp_path: Path) -> None:
    path = tmp_path / "bad.rrd"
    with pytest.raises(RuntimeError):
        with ProbeRecording(path, recording_id="bad") as rec:
            rec.particles(np.zeros((3, 3)))
            raise RuntimeError("simulation failed")
    assert not path.exists() and not list(tmp_path.iterdir())


@pytest.mark.skipif(shutil.which("rerun") is None, reason="rerun CLI not on PATH")
def test_rerun_cli_verifies_the_file(tmp_path: Path) -> None:
    path = tmp_path / "x.rrd"
    with ProbeRecording(path, recording_id="x") as rec:
        rec.particles(np.zeros((3, 3)))
    out = subprocess.run(["rerun", "rrd", "verify", str(path)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
