"""`deformsmith calibrate` publishes a fitted material only after L2's held-out tests (and L3, when the asset has it)
passed it: the record lists the held-out results and the side-by-side frames; a failed gate exits non-zero and leaves
the asset untouched; the card shows the calibration when there is one and nothing of it otherwise. A small sphere (81
particles at 8 mm) dropped in an MPM video (benchmarks.calibrate_roundtrip)."""

from __future__ import annotations

import json
import os
import shutil
from html import escape as html_escape
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from benchmarks.calibrate_roundtrip import CASES, RADIUS_M, write_case_video, write_sphere_asset
from contracts.sim import SimConfig
from contracts.stage import StageContract, load_contract
from contracts.video_fit import SIDE_BY_SIDE_JPG, VIDEO_FIT_JSON, VideoFitRecord
from flows.cli.main import app
from tasks.asset_dir import AssetDir
from tasks.calibrate.compare import CAPTION_PX, TILE_HEIGHT_PX
from tasks.probes.registry import stage_probes
from tasks.render.card import CARD_HTML, CARD_PNG, build_card
from tasks.render.card_data import card_data
from tasks.render.card_text import si
from tests.calibrate.test_calibrate_cli import digest
from tests.render.test_card import _asset as card_asset

SPACING = 0.008
CASE = CASES["medium"]


@pytest.fixture(scope="module")
def drop(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The sphere's asset (L0, L1, the prior as L2's material) and an MPM drop video of it (E 200 kPa, 30 Pa s)."""
    root = tmp_path_factory.mktemp("calibrate")
    video = root / "drop.avi"
    write_case_video(CASE, SPACING, video, SimConfig(cpu_threads=1))
    return write_sphere_asset(root / "asset", SPACING), video


def calibrate(asset: Path, video: Path, *extra: str) -> tuple[int, str, str]:
    """The command on the asset: (exit code, stdout, all output)."""
    res = CliRunner().invoke(app, ["calibrate", str(asset), "--video", str(video), "--drop-height",
                                   str(CASE.drop_height_m), "--size", str(2 * RADIUS_M), "--cpu-threads", "1", *extra])
    return res.exit_code, res.stdout, res.output


@pytest.fixture(scope="module")
def calibrated(drop: tuple[Path, Path], tmp_path_factory: pytest.TempPathFactory, prefect_api: str) -> Path:
    """A copy of the asset calibrated through the command (--no-l3)."""
    asset = tmp_path_factory.mktemp("calibrated") / "asset"
    shutil.copytree(drop[0], asset)
    code, _, out = calibrate(asset, drop[1], "--no-l3")
    assert code == 0, out
    assert "L2 held-out hard gates passed" in out and "L3 skipped: not run: --no-l3" in out, out
    return asset


@pytest.fixture(scope="module")
def calibrated_cache(calibrated: Path) -> str:
    """The cache root `calibrated` ran against (the session's: module fixtures are set up before a test's own
    `_isolated_cache`)."""
    return os.environ["DEFORMSMITH_CACHE"]


def test_the_record_lists_the_held_out_results_and_the_side_by_side_frames(calibrated: Path) -> None:
    rec = VideoFitRecord.model_validate_json((calibrated / VIDEO_FIT_JSON).read_text())
    checks = rec.checks
    assert checks is not None and checks.passed
    assert checks.gates == {"L2 hard gates": True, "L2 held-out hard gates": True}
    l2 = load_contract("L2")
    assert checks.l2.material == rec.fitted and checks.l2.passed
    assert checks.l2.held_out_probes == [p.kind for p in stage_probes(l2, held_out=True)]
    assert set(checks.l2.gates) == {g.name for g in l2.hard_gates}
    # the held-out tests' own gates, judged on their metrics (the long rollout is the stability probe's: not among)
    assert set(checks.l2.held_out_gates) == {g.name for g in l2.hard_gates if g.metric != "stable_long_rollout"}
    assert all(checks.l2.held_out_gates.values())
    held, sel = checks.l2.held_out_metrics, checks.l2.metrics
    assert held["compression_strain"] == pytest.approx(l2.parameters["compression_strain_held_out"], rel=0.05)
    assert sel["compression_strain"] == pytest.approx(l2.parameters["compression_strain"], rel=0.05)
    assert checks.l3 is None and checks.l3_status == "skipped" and "--no-l3" in checks.l3_note
    assert AssetDir(calibrated).material_model() == rec.fitted  # published after the checks
    comp = rec.comparison
    assert comp is not None and comp.image == SIDE_BY_SIDE_JPG
    labels = [k.label for k in comp.frames]
    assert labels[:2] == ["release", "first impact"] and "top of first bounce" in labels  # the sphere bounces
    assert comp.frames[0].sim_t_s == 0.0
    assert all(b.t_s > a.t_s for a, b in zip(comp.frames, comp.frames[1:]))
    assert comp.frames[1].t_s == pytest.approx(rec.metrics.first_impact_time_s)
    jpg = calibrated / SIDE_BY_SIDE_JPG
    data = jpg.read_bytes()
    assert data[:2] == b"\xff\xd8" and len(data) < 300_000
    import cv2

    img = cv2.imread(str(jpg))
    assert img.shape[0] == 2 * (TILE_HEIGHT_PX + CAPTION_PX)  # the real frames above the simulated ones
    top, bottom = img[CAPTION_PX:TILE_HEIGHT_PX + CAPTION_PX], img[-TILE_HEIGHT_PX:]
    blue = (bottom[..., 0].astype(int) - bottom[..., 2]) > 80  # BGR: the simulated particles are drawn blue
    red = (top[..., 2].astype(int) - top[..., 0]) > 80  # the video's sphere is red
    assert blue.sum() > 200 and red.sum() > 200 and ((top[..., 0].astype(int) - top[..., 2]) > 80).sum() < 20


def test_a_failed_gate_exits_non_zero_and_leaves_the_asset_untouched(drop: tuple[Path, Path], tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch,
                                                                     prefect_api: str, calibrated_cache: str) -> None:
    """An L2 contract whose 'no explosion' gate allows no swelling at all (J <= 1): the sphere's impact swells it a
    few per cent, so the fitted material fails there; one error line names the gate, exit 6, nothing written. (Against
    the cache `calibrated` filled: its L2 probe runs are reused, only the verdict differs.)"""
    import flows.l3_material as l3_material

    def strict(stage: str) -> StageContract:
        c = load_contract(stage)  # type: ignore[arg-type]
        gates = [g.model_copy(update={"threshold": 1.0}) if g.name == "no explosion" else g for g in c.hard_gates]
        return c.model_copy(update={"hard_gates": gates})

    monkeypatch.setattr(l3_material, "load_contract", strict)
    assert calibrated_cache != os.environ["DEFORMSMITH_CACHE"]
    monkeypatch.setenv("DEFORMSMITH_CACHE", calibrated_cache)
    asset = tmp_path / "asset"
    shutil.copytree(drop[0], asset)
    before = digest(asset)
    code, _, out = calibrate(asset, drop[1], "--no-l3")
    assert code == 6, out
    errors = [line for line in out.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "no explosion" in errors[0] and "nothing written" in errors[0], out
    assert digest(asset) == before and not (asset / "calibration").exists()


def test_the_card_shows_the_real_clip_beside_the_simulated_one(calibrated: Path, tmp_path: Path) -> None:
    root = card_asset(tmp_path, "sponge")
    shutil.copytree(calibrated / "calibration", root / "calibration")
    rec = VideoFitRecord.model_validate_json((root / VIDEO_FIT_JSON).read_text())
    png, page = build_card(root)
    html = page.read_text(encoding="utf-8")
    assert "Calibrated from a video of the real object" in html
    assert 'src="../calibration/side_by_side.jpg"' in html
    assert rec.comparison is not None
    for k in rec.comparison.frames:
        assert f"{k.label} at {k.t_s:.2f} s" in html
    assert si(rec.fitted.youngs_modulus_pa, "Pa") in html and si(rec.prior.youngs_modulus_pa, "Pa") in html
    assert si(rec.fitted.viscosity_pa_s, "Pa s") in html
    assert si(rec.metrics.rebound_ratio, "-") in html and si(rec.simulated["rebound_ratio"], "-") in html
    assert f"{100 * rec.residuals['rebound_ratio']:+.1f} %" in html
    assert f"tracking confidence {rec.track.tracking_confidence:.2f}" in html and "from size" in html
    assert "L2 held-out hard gates: passed" in html and "held-out tests run: compress, drop" in html
    for key in rec.undetermined:
        assert f"not determined: {key}" in html
    for note in rec.notes:
        assert html_escape(f"note: {note}") in html
    card = card_data(root)
    assert card.calibration is not None and card.calibration.image == SIDE_BY_SIDE_JPG
    from PIL import Image

    assert Image.open(png).size == (1800, 1300)


def test_a_card_without_a_calibration_has_no_calibration_section(tmp_path: Path) -> None:
    root = card_asset(tmp_path, "sponge")
    _, page = build_card(root)
    assert "Calibrated from a video" not in page.read_text(encoding="utf-8")
    assert card_data(root).calibration is None
    (root / "calibration").mkdir()
    (root / VIDEO_FIT_JSON).write_text(json.dumps({"video": "x"}))
    from contracts.errors import InputError

    with pytest.raises(InputError, match="not a valid calibration record"):
        build_card(root)
    assert (root / CARD_HTML).is_file() and (root / CARD_PNG).is_file()


def test_key_frames_follow_the_track() -> None:
    """The key moments of a bouncing disc's track: release, first impact, the top of the first bounce, rest."""
    from tasks.calibrate.compare import key_frames
    from tasks.calibrate.metrics import analyse
    from tasks.calibrate.synthetic import Camera, bouncing_centres, disc_video
    from tasks.calibrate.track import track_object

    cam = Camera(width_px=100, height_px=200, px_per_m=1000.0, floor_y_px=190.0, centre_x_px=50.0)
    fps = 200.0
    centres = bouncing_centres(0.12, 0.01, 0.5, fps, rest_s=0.4)
    tr = track_object(disc_video(cam, centres, 0.01), fps)
    frames = key_frames(tr, analyse(tr))
    assert [k.label for k in frames] == ["release", "first impact", "top of first bounce", "rest"]
    dz = np.diff(centres[:, 1])
    first_floor = int(np.argmax(dz > 0))  # the lowest frame of the fall: the impact is in the frame after it
    top = first_floor + int(np.argmax(dz[first_floor:] < 0))  # the highest frame of the first bounce
    assert abs(frames[1].frame - first_floor) <= 1
    assert abs(frames[2].frame - top) <= 1


@pytest.mark.slow  # ~2 min on one core: the fit, L2's probes and held-out tests, and the robot's trials, all real
def test_the_command_publishes_the_robots_confirmation_as_l3s_result(drop: tuple[Path, Path], tmp_path: Path,
                                                                     prefect_api: str) -> None:
    """The sphere with a real L3 (5 mm trial lattice, one held-out condition): the command's real checks (L2, then
    the robot under manipulation.json's plan) confirm the fitted material, and manipulation.json is L3's result with
    it, published with material.json and the record."""
    from flows.l3_manipulation import L3Options, run_l3

    asset = tmp_path / "asset"
    shutil.copytree(drop[0], asset)
    before, _ = run_l3(asset, L3Options(particle_spacing_m=0.005, robustness=(), held_out=((0.06, -0.08, 30.0),),
                                        cpu_threads=1))
    assert before.passed
    code, _, out = calibrate(asset, drop[1])
    assert code == 0, out
    assert "L3 robot confirmation passed" in out and "published as L3's result" in out, out
    rec = VideoFitRecord.model_validate_json((asset / VIDEO_FIT_JSON).read_text())
    assert rec.checks is not None and rec.checks.l3_status == "confirmed" and rec.checks.l3 is not None
    l3 = AssetDir(asset).manipulation()
    assert l3.passed and l3.material == rec.fitted and l3.material_revision == rec.checks.l3
    assert AssetDir(asset).material_model() == rec.fitted == AssetDir(asset).adopted_material().material
    assert [a.role for a in l3.attempts[len(before.attempts):]] == ["confirmation", "held_out"]
