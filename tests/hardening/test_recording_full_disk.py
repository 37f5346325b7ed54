"""A full disk inside Rerun's `.rrd` writer (#27): one OSError naming the recording and the cause (the CLI's one
`error:` line, exit 2), no `.rrd` and no `*.rrd.<pid>.tmp` left, nothing of the writer's own on stderr.

The full disk is a real one where a tmpfs can be mounted (root); the monkeypatched writer failures run everywhere.
"""

from __future__ import annotations

import errno
import gc
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from tasks.record import ProbeRecording
from tasks.record import rerun_recording


@pytest.fixture
def tiny_disk(tmp_path: Path) -> Iterator[Path]:
    """A 256 KiB tmpfs (skipped where it cannot be mounted)."""
    where = tmp_path / "tiny"
    where.mkdir()
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(where)], capture_output=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.decode(errors='replace').strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)


def _record(path: Path, frames: int = 60) -> None:
    with ProbeRecording(path, recording_id="full-disk") as rec:
        for i in range(frames):
            rec.set_time(i, i * 0.01)
            rec.particles(np.random.default_rng(i).random((4000, 3), dtype=np.float32))


@pytest.mark.parametrize("when", ["fills_while_recording", "full_before_it_starts"])
def test_a_full_disk_while_recording_is_one_oserror_and_leaves_no_file(when: str, tiny_disk: Path) -> None:
    if when == "full_before_it_starts":
        with open(tiny_disk / "filler", "wb") as fh, pytest.raises(OSError):
            fh.write(bytes(1 << 20))
    path = tiny_disk / "recordings" / "L1_drop-0123456789abcdef.rrd"
    with pytest.raises(OSError) as info:
        _record(path)
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(path)
    assert sorted(p.name for p in path.parent.iterdir()) == []  # no .rrd, no .rrd.<pid>.tmp


def test_a_write_that_fails_half_way_names_the_recording(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def half(fh: object, data: bytes) -> None:
        fh.write(data[: len(data) // 2])  # type: ignore[attr-defined]
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(rerun_recording, "_write_bytes", half)
    path = tmp_path / "rec" / "a.rrd"
    with pytest.raises(OSError) as info:
        _record(path, frames=2)
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(path)
    assert list(path.parent.iterdir()) == []


def test_an_unwritable_folder_fails_before_anything_is_recorded(tmp_path: Path) -> None:
    (tmp_path / "plain").write_text("a file")
    with pytest.raises(OSError) as info:
        ProbeRecording(tmp_path / "plain" / "a.rrd", recording_id="x").__enter__()
    assert info.value.filename == str(tmp_path / "plain" / "a.rrd")


def test_a_recording_holds_what_rerun_s_own_writer_would_write(tmp_path: Path) -> None:
    """The in-memory stream written by ProbeRecording reads back as the same recording as Rerun's file sink."""
    from tasks.record import read_recording, recording_digest

    ours = tmp_path / "ours.rrd"
    _record(ours, frames=5)
    theirs = rerun_recording.rr.RecordingStream(rerun_recording.APP_ID, recording_id="full-disk")
    theirs.save(str(tmp_path / "theirs.rrd"))
    theirs.set_time("frame", sequence=0)
    theirs.set_time("sim_time", duration=0.0)
    for i in range(5):
        theirs.set_time("frame", sequence=i)
        theirs.set_time("sim_time", duration=i * 0.01)
        theirs.log(rerun_recording.PARTICLES, rerun_recording.rr.Points3D(
            np.random.default_rng(i).random((4000, 3), dtype=np.float32)))
    theirs.flush()
    theirs.disconnect()
    assert recording_digest(ours) == recording_digest(tmp_path / "theirs.rrd")
    assert read_recording(ours).recording_ids == ["full-disk"]


def test_a_recording_never_closed_leaves_no_temporary(tmp_path: Path) -> None:
    """A rollout that raises never closes its recordings: their temporaries go when they are collected."""
    rec = ProbeRecording(tmp_path / "a.rrd", recording_id="open").__enter__()
    rec.particles(np.zeros((10, 3), np.float32))
    assert [p.name.endswith(".tmp") for p in tmp_path.iterdir()] == [True]
    del rec
    gc.collect()
    assert list(tmp_path.iterdir()) == []


_CLI_ON_A_FULL_DISK = """
import sys
import numpy as np
from flows.cli import main as cli_main
from tasks.record import ProbeRecording

path = sys.argv[1]

def app():
    with ProbeRecording(path, recording_id="x") as rec:
        for i in range(60):
            rec.set_time(i, 0.0)
            rec.particles(np.random.default_rng(i).random((4000, 3), dtype=np.float32))

cli_main.app = app
sys.argv = ["deformsmith", "schema"]
cli_main.main()
"""


@pytest.mark.slow  # ~3 s (a CLI process); the OSError is tested above, its one line in test_locations
def test_the_cli_says_a_full_disk_in_one_line(tiny_disk: Path) -> None:
    path = tiny_disk / "recordings" / "L2_drop-0123456789abcdef.rrd"
    proc = subprocess.run([sys.executable, "-c", _CLI_ON_A_FULL_DISK, str(path)], capture_output=True, text=True,
                          timeout=120, cwd=Path(__file__).resolve().parents[2])
    assert proc.returncode == 2, proc.stderr[-3000:]
    assert proc.stderr == f"error: cannot use {path}: no space left on the device\n"
    assert list(path.parent.iterdir()) == []
