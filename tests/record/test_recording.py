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


class _OneRowAtATime(ProbeRecording):
    """The scalars logged one row at a time, as before they were kept and sent as columns."""

    def scalar(self, name: str, value: float) -> None:
        import rerun as rr

        self.rec.log(f"metrics/{name}", rr.Scalars(float(value)))

    def set_sim_time(self, sim_time_s: float) -> None:
        self.rec.set_time("sim_time", duration=float(sim_time_s))


def test_scalars_kept_and_sent_as_columns_are_the_rows_logging_them_one_by_one_wrote(tmp_path: Path) -> None:
    """ProbeRecording keeps its scalars and sends one column per metric as it closes (one native call per scalar was
    ~10 s of a cold generate): what the recording shows is the same, curves between frames (set_sim_time) too."""
    from tasks.record.rerun_recording import recording_digest

    rng = np.random.default_rng(0)
    x = rng.random((5, 20, 3))

    def write(cls: type[ProbeRecording], path: Path, first: float = 1.0) -> Path:
        with cls(path, recording_id="same") as rec:
            rec.scalar("at_start_j", first)
            for frame in range(1, 5):
                rec.set_time(frame, 0.01 * frame)
                rec.particles(x[frame])
                rec.scalar("kinetic_energy_j", float(x[frame].sum()))
                rec.scalar("com_z_m", float(x[frame, :, 2].mean()))
                for k in range(3):  # a curve at a finer rate than the frames
                    rec.set_sim_time(0.01 * frame + 0.003 * k)
                    rec.scalar("finger_0_force_n", float(k + frame))
            rec.log("done")
        return path

    kept = write(ProbeRecording, tmp_path / "kept.rrd")
    assert recording_digest(kept) == recording_digest(write(_OneRowAtATime, tmp_path / "rows.rrd"))
    assert recording_digest(kept) != recording_digest(write(ProbeRecording, tmp_path / "other.rrd", first=2.0))
    summary = read_recording(kept)
    assert {"metrics/kinetic_energy_j", "metrics/finger_0_force_n", "metrics/at_start_j"} <= summary.entity_paths
    assert summary.rows_per_entity["metrics/finger_0_force_n"] == 12
