"""A quiet console: no Warp CUDA-driver notice and no pybullet banner on a CPU machine (other native output still
shows), progress lines without a source-file suffix."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tasks.native_output import native_output_filtered

REPO = Path(__file__).resolve().parents[2]


def test_native_lines_are_filtered_and_everything_else_passes(capfd: pytest.CaptureFixture[str]) -> None:
    with native_output_filtered(("banner",)) as dropped:
        os.write(1, b"pybullet banner line\nkept on stdout\n")
        os.write(2, b"an error from C\n")
        print("python print", flush=True)
    out, err = capfd.readouterr()
    assert dropped == ["pybullet banner line\n"]
    assert sorted(out.splitlines()) == ["kept on stdout", "python print"] and err == "an error from C\n"


def test_importing_warp_and_pybullet_prints_nothing() -> None:
    code = ("from tasks.native_output import init_warp_quietly; import tasks.quiet_pybullet, warp; "
            "notes = init_warp_quietly(); "  # what tasks.mpm runs at import
            "print('cuda' if warp.is_cuda_available() else notes and 'dropped' or 'no-driver-line')")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120,
                         env=dict(os.environ, PYTHONPATH=str(REPO)))
    assert res.returncode == 0, res.stderr
    assert res.stderr == "" and res.stdout.strip() in ("cuda", "dropped", "no-driver-line")


def test_progress_lines_carry_no_source_file() -> None:
    from flows.cli.apps import console

    with console.capture() as cap:
        console.log("L0 geometry")
    assert "L0 geometry" in cap.get() and ".py:" not in cap.get()
