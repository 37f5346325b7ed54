"""`deformsmith calibrate DIR --video FILE`: bad input is one `error:` line, a non-zero exit and nothing written."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from benchmarks.calibrate_roundtrip import write_sphere_asset
from flows.cli.main import app
from tasks.calibrate.synthetic import Camera, disc_video, scene
from tasks.calibrate.video import write_video

CAM = Camera(width_px=100, height_px=160, px_per_m=1000.0, floor_y_px=150.0, centre_x_px=50.0)


def digest(root: Path) -> str:
    """The asset tree's content, for 'nothing written'."""
    h = hashlib.sha256()
    for p in sorted(root.rglob("*")):
        h.update(str(p.relative_to(root)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


@pytest.fixture()
def asset(tmp_path: Path) -> Path:
    return write_sphere_asset(tmp_path / "asset", 0.008)


def run(*args: str) -> tuple[int, str]:
    res = CliRunner().invoke(app, ["calibrate", *args])
    return res.exit_code, res.output


def refused(asset: Path, *args: str, match: str) -> None:
    before = digest(asset)
    code, out = run(str(asset), *args)
    assert code == 2, out
    errors = [line for line in out.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and match in errors[0], out
    assert digest(asset) == before and not (asset / "calibration").exists()


def test_an_unreadable_video_is_refused(asset: Path, tmp_path: Path) -> None:
    bad = tmp_path / "clip.mp4"
    bad.write_text("not a video")
    refused(asset, "--video", str(bad), "--size", "0.04", match="not a readable video")
    refused(asset, "--video", str(tmp_path / "missing.mp4"), match="video not found")


def test_a_video_that_never_shows_the_object_is_refused(asset: Path, tmp_path: Path) -> None:
    still = np.repeat(np.clip(scene(CAM), 0, 255).astype(np.uint8)[None], 20, axis=0)
    video = write_video(tmp_path / "still.avi", still, 30.0)
    refused(asset, "--video", str(video), "--size", "0.04", match="never found")


def test_no_size_and_no_way_to_scale_is_refused(asset: Path, tmp_path: Path) -> None:
    """A disc that only slides along the floor: no fall, so neither the drop nor gravity can scale it."""
    n = 30
    centres = np.stack([np.linspace(-0.02, 0.02, n), np.full(n, 0.01)], axis=1)
    video = write_video(tmp_path / "slide.avi", disc_video(CAM, centres, 0.01), 30.0)
    refused(asset, "--video", str(video), match="no way to scale")


def test_bad_options_and_a_bad_asset_or_press_table_are_refused(asset: Path, tmp_path: Path) -> None:
    video = tmp_path / "v.avi"
    refused(asset, "--video", str(video), "--fps", "-3", match="--fps must be a positive")
    refused(asset, "--video", str(video), "--size", "nan", match="--size must be a positive")
    empty = tmp_path / "empty"
    empty.mkdir()
    code, out = run(str(empty), "--video", str(video))
    assert code == 2 and "physical.json" in out and not (empty / "calibration").exists(), out
    csv = tmp_path / "press.csv"
    csv.write_text("mm,newtons\n1,2\n")
    refused(asset, "--video", str(video), "--press", str(csv), match="displacement_m and force_n")
