"""`deformsmith calibrate DIR --video FILE`: the asset's material fitted to a video of the real object dropped on a
table (and to a flat-plate press test): read and track the video, reduce the track to L2's drop metrics, fit E and
the Kelvin-Voigt viscosity with the engine's drop impact at the video's drop height and size (tasks.calibrate), then
check the fitted material as L3's material revisions are checked (L2's selection probes and held-out tests at the
asset's own settings, every hard gate; then, when the asset has L3, the robot under manipulation.json's plan, physical
model and force budget: L3's revise/re-validate edge, flows.l3_manipulation.confirm_material; `l3=False` skips it),
draw the real clip's key frames beside the simulated drop's (calibration/side_by_side.jpg), and only when every gate
held write the record (calibration/video_fit.json) and the fitted material as the asset's (material.json, asset.json
and the card when the asset is published) in one staged update: all of it, or nothing. The checks run in that
update's working copy: when the robot confirmed the material, its trials are stored there and L3's confirmed result
is written as L3's material revisions are (manipulation.json: the confirmation as the reported trial, the held-out
conditions with the fitted material; flows.l3_manipulation.write_l3_record), and asset.json, the PhysGaussian
config, the card and the pick-and-place video follow it (flows.generate.refresh_after_l3, as after `deformsmith
manipulate`). A failed gate is a StageFailure (exit 6) naming it, and writes nothing.

Everything that can be checked without simulating (the asset, the press table, the video, the object, the scale, the
drop height) is checked before the first simulation; a failure is one InputError line and writes nothing.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import zarr

from contracts.asset_dir import PARTICLES_ZARR, MaterialRecord
from contracts.errors import InputError, StageFailure
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from contracts.video_fit import (SIDE_BY_SIDE_JPG, VIDEO_FIT_JSON, CalibrationChecks, Comparison, PressTest,
                                 VideoFitRecord, VideoMetrics)
from flows.generate import refresh_after_l3
from flows.l3_manipulation import confirm_material
from flows.l3_material import revalidate_in_l2
from tasks.asset_dir import AssetDir, document_json
from tasks.calibrate.compare import background, key_frames, sim_frames, simulate_key_frames, strip, write_jpeg
from tasks.calibrate.fit import SETTLE_TOLERANCE, FitProblem, fit
from tasks.calibrate.metrics import REST_FRAMES, DropAnalysis, analyse, contact_tol_px, video_metrics
from tasks.calibrate.press import press_test, read_press
from tasks.calibrate.scale import track_summary, video_scale
from tasks.calibrate.sim import scaled_body
from tasks.export.calibrate import rel
from tasks.calibrate.track import Track, track_object
from tasks.calibrate.video import Video, read_video
from tasks.manipulation.l3_record import CALIBRATION_TRIGGER
from tasks.manipulation.material_revision import MaterialLimits
from tasks.publish import staged_update, write_json_atomic
from tasks.render.card import CARD_HTML, build_card

Progress = Callable[[str], None]


@dataclass
class AssetBody:
    """What the fit needs of the asset: its particles, L1's model and its adopted material."""

    positions_m: np.ndarray
    volumes_m3: np.ndarray
    physical: PhysicalModel
    material: Material
    material_source: str


def load_asset(asset_dir: Path) -> AssetBody:
    """The asset's particles, physical model and adopted material (InputError naming what is missing)."""
    adir = AssetDir(asset_dir)
    if not Path(asset_dir).is_dir():
        raise InputError(f"{asset_dir} is not an asset directory")
    physical = adir.physical_model()
    adopted = adir.adopted_material()
    path = Path(asset_dir) / PARTICLES_ZARR
    try:
        g = zarr.open_group(str(path), mode="r")
        pos, vol = np.asarray(g["positions_m"][...], np.float64), np.asarray(g["volumes_m3"][...], np.float64)
    except (OSError, KeyError, ValueError) as exc:
        raise InputError(f"{path}: no particles to simulate ({type(exc).__name__})") from None
    return AssetBody(pos, vol, physical, adopted.material, adopted.source)


def calibrate_asset(asset_dir: Path, video_path: Path, drop_height_m: float | None = None,
                    size_m: float | None = None, fps: float | None = None, press_csv: Path | None = None,
                    sim: SimConfig | None = None, write: bool = True, l3: bool = True,
                    progress: Progress | None = None) -> VideoFitRecord:
    """Fit the asset's material to the video, check it and publish it (see the module docstring); returns the record
    (checked and written when `write`; a dry run neither checks nor writes). l3: False skips the robot's confirmation
    (--no-l3; the record says so). progress: a sink for one line per step."""
    sim = sim or SimConfig()
    say = progress or (lambda _: None)
    asset = load_asset(Path(asset_dir))
    table = read_press(press_csv) if press_csv is not None else None
    video = read_video(video_path, fps)
    tr = track_object(video.frames, video.fps)
    d = analyse(tr)
    scale = video_scale(d, size_m, drop_height_m)
    mpp = scale.metres_per_px
    metrics = video_metrics(d, mpp)
    undetermined = dict(d.why)
    h = drop_height_m if drop_height_m is not None else metrics.drop_height_m
    if h is None or not h > 0:
        raise InputError("the drop height is not in the video (no release seen): give --drop-height")
    size = size_m if size_m is not None else d.longest_extent * mpp
    pos, vol, phys = scaled_body(asset.positions_m, asset.volumes_m3, asset.physical, size)
    press: PressTest | None = None
    if table is not None and press_csv is not None:
        press = press_test(press_csv, table, pos, vol, phys.particle_spacing_m)
    limit = None
    if metrics.rebound_ratio == 0.0 and d.drop_px:
        limit = contact_tol_px(d.flight_height or d.longest_extent) / d.drop_px  # a rise the tracker would see
    problem = FitProblem(pos, vol, phys, asset.material, h, sim, strain=metrics.impact_strain,
                         rebound=metrics.rebound_ratio if metrics.rebound_ratio else None, rebound_limit=limit,
                         press=press, settle=metrics.settle_time_s, settle_tolerance_m=metrics.settle_tolerance_m,
                         frame_times_s=tr.t_s, release_t_s=d.release_t or 0.0,
                         settle_tail=max(5, int(REST_FRAMES * len(tr.t_s))))
    say("fitting E and the viscosity with the engine's drop")
    result = fit(problem)
    simulated, residuals = dict(result.simulated), dict(result.residuals)
    settle_notes = simulate_settle(problem, result.material, metrics, simulated, residuals)
    converged = result.converged and (result.young_source != "settle_time"
                                      or abs(residuals.get("settle_time_s", 0.0)) <= 2 * SETTLE_TOLERANCE)
    if result.young_source == "prior":
        undetermined["youngs_modulus_pa"] = ("kept at the prior: " + undetermined.get("impact_strain", "no impact "
                                             "strain") + "; give a press test (--press) to fix it")
    elif result.young_source == "press" and metrics.impact_strain is None:
        undetermined.setdefault("impact_strain", "not seen")
    if result.viscosity_source == "prior":
        undetermined["viscosity_pa_s"] = "kept at the prior: " + undetermined.get("rebound_ratio", "no rebound")
    notes = list(result.notes) + settle_notes
    if asset.material_source != "L2":
        notes.append(f"the prior was the asset's adopted material ({asset.material_source})")
    if scale.gravity_check is not None and abs(scale.gravity_check / 9.81 - 1.0) > 0.15:
        notes.append(f"the free fall shows {scale.gravity_check:.2f} m/s^2 under this scale: check --fps (a slow-motion "
                     "clip stores its playback rate) and --size")
    if not write:
        notes.append("a dry run: L2's held-out tests and L3 were not run on the fitted material, and nothing written")
    record = VideoFitRecord(
        video=str(video_path), press=press, size_m=size, size_source="option" if size_m is not None else "video",
        drop_height_m=h, drop_height_source="option" if drop_height_m is not None else "video", scale=scale,
        track=track_summary(tr, d, video), metrics=metrics, prior=asset.material, fitted=result.material,
        youngs_modulus_source=result.young_source, viscosity_source=result.viscosity_source,
        simulated=simulated, residuals=residuals, undetermined=undetermined, steps=problem.steps,
        sim_calls=len(problem.steps), converged=converged, notes=notes)
    if not write:
        return record
    with staged_update(Path(asset_dir)) as work:  # the checks' robot trials and every record: all, or nothing
        checks = check_material(work, record.fitted, sim, l3, say, publish=True)
        record = record.model_copy(update={"checks": checks})
        if not checks.passed:
            raise StageFailure("calibrate", failure_message(checks) + "; nothing written")
        say("drawing the real clip beside the simulated drop")
        comparison = write_comparison(work, video, tr, d, mpp, (pos, vol, phys), record.fitted, h, sim)
        record = record.model_copy(update={"comparison": comparison})
        write_records(work, record)
        published = AssetDir(work).manipulation() if checks.l3_status == "confirmed" else None
        if published is not None and refresh_after_l3(work, published, sim.device) is not None:
            say("asset.json, card and video refreshed from manipulation.json")  # as `deformsmith manipulate` does
        elif (work / CARD_HTML).is_file():  # a published asset: its card shows the calibration
            say("rebuilding the card")
            build_card(work)
    return record


def check_material(asset_dir: Path, material: Material, sim: SimConfig, l3: bool, say: Progress,
                   publish: bool = False) -> CalibrationChecks:
    """The fitted material as L3's material revisions are checked (flows.l3_material.revalidate_in_l2 with L2's
    held-out tests: every hard gate on both), then, when L2 passed it and the asset has a passed L3, the robot under
    manipulation.json's plan (flows.l3_manipulation.confirm_material). Not `publish`: the trials' data go to a
    scratch folder and nothing in the asset is written. `publish`: asset_dir is the working copy of the asset being
    published (calibrate_asset's staged update); the trials are stored in it, and a material the robot confirmed is
    written there as L3's result (manipulation.json, as L3's own material revisions are)."""
    adir = AssetDir(asset_dir)
    say("L2: the fitted material's selection probes and held-out tests")
    check = revalidate_in_l2(asset_dir, material, adir.physical_model(), sim=sim, held_out=True)
    limits = MaterialLimits.from_asset(asset_dir)
    words = {b.metric: bool(b.contains(check.metrics.get(b.metric))) for b in limits.held_bands()}
    gates = {"L2 hard gates": all(check.gates.values()), "L2 held-out hard gates": all(check.held_out_gates.values())}
    revision = None
    if not check.passed:
        status, note = "skipped", "not run: L2 did not pass the fitted material"
    elif not l3:
        status, note = "skipped", "not run: --no-l3"
    elif not adir.has("manipulation"):
        status, note = "skipped", "not run: the asset has no L3 (manipulation.json)"
    else:
        say("L3: the robot under manipulation.json's plan with the fitted material")
        with tempfile.TemporaryDirectory(prefix="deformsmith-calibrate-l3-") as scratch:
            out = confirm_material(asset_dir, check, CALIBRATION_TRIGGER, "calibrated from video",
                                   None if publish else Path(scratch), device=sim.device,
                                   cpu_threads=sim.cpu_threads, progress=say, publish=publish)
        if isinstance(out, str):
            status, note = "skipped", out
        else:
            revision = out
            gates["L3 robot confirmation"] = out.accepted
            status = "confirmed" if out.accepted else "failed"
            missed = [k for k in L3_OUTCOMES if not (out.confirmation or {}).get(k)]
            note = ("the robot picked, carried and placed it under the same plan"
                    + ("; published as L3's result (manipulation.json)" if publish else "") if out.accepted else
                    "the robot failed under the same plan: " + (", ".join(f"not {k}" for k in missed)
                                                                 or "a gate of L3's contract (see l3.confirmation)"))
    return CalibrationChecks(passed=all(gates.values()), gates=gates, l2=check, word_bands=words, l3=revision,
                             l3_status=status, l3_note=note)


L3_OUTCOMES = ("lifted", "transported", "released_in_target", "settled")


def failure_message(checks: CalibrationChecks) -> str:
    """One line: which gates the fitted material failed, and the failing L2 gates by name."""
    failed = [g for g, ok in checks.gates.items() if not ok]
    l2 = [g for g, ok in checks.l2.gates.items() if not ok]
    held = [g for g, ok in checks.l2.held_out_gates.items() if not ok]
    detail = ([f"selection probes: {', '.join(l2)}"] if l2 else []) + (
        [f"held-out tests ({', '.join(checks.l2.held_out_probes)}): {', '.join(held)}"] if held else []) + (
        [f"L3: {checks.l3_note}"] if checks.l3_status == "failed" else [])
    m = checks.l2.material
    what = (f"E {m.youngs_modulus_pa:.4g} Pa, viscosity {m.viscosity_pa_s:.4g} Pa s" if m is not None
            else "the fitted material")
    return f"the fitted material ({what}) failed {', '.join(failed)} ({'; '.join(detail)})"


def write_comparison(work: Path, video: Video, tr: Track, d: DropAnalysis, metres_per_px: float,
                     body: tuple[np.ndarray, np.ndarray, PhysicalModel], material: Material, drop_height_m: float,
                     sim: SimConfig) -> Comparison | None:
    """calibration/side_by_side.jpg: the clip's key frames above the fitted material's simulated drop at the same
    times after the release, drawn in the clip's camera (tasks.calibrate.compare); None without key frames."""
    frames = key_frames(tr, d)
    if not frames:
        return None
    pos, vol, phys = body
    drawing = simulate_key_frames(pos, vol, phys, material, drop_height_m, video.fps, frames, sim)
    release = int(np.argmin(np.abs(tr.t_s - frames[0].t_s)))
    sims = sim_frames(drawing, background(video.frames, tr), metres_per_px, d.floor_y, float(tr.cx[release]))
    write_jpeg(work / SIDE_BY_SIDE_JPG, strip([video.frames[k.frame] for k in frames], sims, frames))
    return Comparison(image=SIDE_BY_SIDE_JPG, frames=frames,
                      note="the fitted material's drop simulated from the same height, its particles drawn as discs "
                           "in the clip's scale on the clip's empty background (the median of its frames without the object), the floor "
                           "the drop height below its bottom at release on the clip's floor line")


def simulate_settle(problem: FitProblem, material: Material, metrics: VideoMetrics, simulated: dict[str, float],
                    residuals: dict[str, float]) -> list[str]:
    """The fitted material's bounces after the video's drop until they are under the video's settle tolerance
    (FitProblem.bounces: tasks.calibrate.sim.bounce_settle), sampled at the video's frames: simulated settle_time_s
    (and its continuous value), the bounces seen, the engine's restitution at each probed speed; the residual against
    the video's settle time (fitted only when E came from it). Returns notes."""
    if problem.settle_tolerance_m is None or not problem.settle_tolerance_m > 0:
        return ["no settle time simulated: the video gave no settle tolerance"]
    out = problem.bounces(material.youngs_modulus_pa, material.viscosity_pa_s, material.damping_rate_per_s)
    sampled = out.get("settle_time_frames_s")
    simulated["settle_time_s"] = sampled if sampled is not None else out["settle_time_s"]
    simulated["settle_time_continuous_s"] = out["settle_time_s"]
    simulated["settle_bounces"] = out["bounces"]
    simulated.update({k: v for k, v in out.items() if k.startswith("restitution_at_")})
    notes = []
    if metrics.settle_time_s is not None and metrics.settle_time_s > 0:
        residuals["settle_time_s"] = rel(simulated["settle_time_s"], metrics.settle_time_s)
        if abs(residuals["settle_time_s"]) > 0.10:
            notes.append(f"the settle time is {100 * residuals['settle_time_s']:+.0f} % off the video's (the bounces "
                         "after the first follow the engine's restitution at their slower speeds)")
    if sampled is None:
        notes.append("the simulated bounces outlast the video's frames: its settle time is the continuous one")
    return notes


def write_records(work: Path, record: VideoFitRecord) -> None:
    """The record and the fitted material as the asset's (material.json; asset.json's material when published) in a
    working copy of the asset (staged_update: swapped in whole)."""
    write_json_atomic_mkdir(work / VIDEO_FIT_JSON, document_json(record))
    adir = AssetDir(work)
    mat: MaterialRecord = adir.material()
    adir.write_material(mat.model_copy(update={
        "material": record.fitted,
        "message": f"{mat.message}; calibrated from video ({VIDEO_FIT_JSON}: E from "
                   f"{record.youngs_modulus_source}, viscosity from {record.viscosity_source})"}))
    if adir.has("manifest"):
        adir.write_manifest(adir.manifest().model_copy(update={"material": record.fitted}))

def write_json_atomic_mkdir(path: Path, data: dict) -> None:
    """write_json_atomic into a folder made first."""
    path.parent.mkdir(parents=True, exist_ok=True)
    write_json_atomic(path, data)


__all__ = ["AssetBody", "calibrate_asset", "check_material", "failure_message", "load_asset", "simulate_settle",
           "write_comparison", "write_records"]
