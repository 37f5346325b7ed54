"""`deformsmith calibrate DIR --video FILE`: the asset's E and viscosity fitted to a video of the real object dropped
on a table (and to a flat-plate press test); flows.calibrate."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from contracts.errors import DeformSmithError
from contracts.sim import SimConfig
from contracts.video_fit import VIDEO_FIT_JSON, VideoFitRecord
from flows.cli.apps import app, console, emit_json, fail, results


def _positive(name: str, v: float | None) -> None:
    if v is not None and not (math.isfinite(v) and v > 0):
        fail(f"{name} must be a positive finite number, got {v}")


def summary_lines(r: VideoFitRecord, asset_dir: Path) -> list[str]:
    """The fit in a few lines."""
    m, t = r.metrics, r.track

    def f(v: float | None, fmt: str = ".3g") -> str:
        return "n/a" if v is None else format(v, fmt)

    lines = [
        f"E {r.prior.youngs_modulus_pa:.4g} -> {r.fitted.youngs_modulus_pa:.4g} Pa (from {r.youngs_modulus_source}); "
        f"viscosity {r.prior.viscosity_pa_s:.4g} -> {r.fitted.viscosity_pa_s:.4g} Pa s (from {r.viscosity_source})",
        f"rebound ratio video {f(m.rebound_ratio)} sim {f(r.simulated.get('rebound_ratio'))}; impact strain video "
        f"{f(m.impact_strain)} sim {f(r.simulated.get('impact_strain'))}; settle time {f(m.settle_time_s)} s; "
        f"recovery {f(m.recovery_ratio)}",
        "residuals: " + (", ".join(f"{k} {v:+.1%}" for k, v in r.residuals.items()) or "none")
        + f"; converged {r.converged}; {r.sim_calls} simulations",
        f"scale {r.scale.metres_per_px * 1000:.4g} mm/px from {r.scale.source} ({r.scale.detail}); drop "
        f"{r.drop_height_m:.4g} m ({r.drop_height_source}), size {r.size_m:.4g} m ({r.size_source})",
        f"tracked {t.frames_tracked}/{t.frames} frames ({t.frames_dropped} dropped) at {t.fps:g} fps ({t.fps_source}); "
        f"tracking confidence {t.tracking_confidence:.2f}",
    ]
    if r.checks is not None:
        c = r.checks
        lines.append("checks: " + ", ".join(f"{g} {'passed' if ok else 'FAILED'}" for g, ok in c.gates.items())
                     + f" (held-out tests: {', '.join(c.l2.held_out_probes) or 'none'}); L3 {c.l3_status}: "
                     f"{c.l3_note}")
        left = [m for m, ok in c.word_bands.items() if not ok]
        if left:
            lines.append(f"outside the words' bands (not a gate: the video measures the object): {', '.join(left)}")
    if r.comparison is not None:
        lines.append(f"real beside simulated: {asset_dir / r.comparison.image} "
                     f"({', '.join(k.label for k in r.comparison.frames)})")
    lines += [f"undetermined: {k}: {why}" for k, why in r.undetermined.items()]
    lines += [f"note: {n}" for n in r.notes]
    lines.append(f"record: {asset_dir / VIDEO_FIT_JSON}")
    return lines


@app.command("calibrate")
def calibrate(
    asset_dir: Path = typer.Argument(..., help="an asset directory that L2 has run on (material.json)"),
    video: Path = typer.Option(..., "--video", help="a static-camera video of the real object dropped on a table"),
    drop_height: float = typer.Option(None, "--drop-height", help="the fall of the object's bottom to the table, in m "
                                      "(default: measured in the video)"),
    size: float = typer.Option(None, "--size", help="the object's longest extent, in m: the video's scale "
                               "(default: the drop height's, else gravity's)"),
    fps: float = typer.Option(None, "--fps", help="frames per second, when the file lacks it (or stores a slow-motion "
                              "clip's playback rate)"),
    press: Path = typer.Option(None, "--press", help="a flat-plate press test: CSV with columns displacement_m, force_n"),
    cpu_threads: int = typer.Option(2, "--cpu-threads", help="threads sharing each MPM rollout's particles"),
    no_l3: bool = typer.Option(False, "--no-l3", help="skip the robot's confirmation of the fitted material under "
                               "manipulation.json's plan (L3 trials are the slow part; the record says it was skipped)"),
    dry_run: bool = typer.Option(False, "--dry-run", help="fit and report; no held-out tests, no L3, nothing written"),
    as_json: bool = typer.Option(False, "--json", help="print the record as JSON"),
) -> None:
    """Fit the asset's Young's modulus and Kelvin-Voigt viscosity to a video of the real object (rebound, impact
    strain; E from a press test when given) with the engine's drop at the video's height and size; check it with
    L2's held-out tests and (when the asset has L3) the robot under its plan; only when every gate holds, write
    calibration/video_fit.json, calibration/side_by_side.jpg and the fitted material as the asset's (exit 6 and
    nothing written when a gate fails)."""
    for name, v in (("--drop-height", drop_height), ("--size", size), ("--fps", fps)):
        _positive(name, v)
    if not 1 <= cpu_threads <= 64:
        fail(f"--cpu-threads must be 1 to 64, got {cpu_threads}")
    # lazy: pulls warp, OpenCV, zarr (--help imports every command module)
    from flows.calibrate import calibrate_asset

    try:
        with console.status("tracking the video and fitting the material ...") as status:
            record = calibrate_asset(asset_dir, video, drop_height, size, fps, press,
                                     SimConfig(cpu_threads=cpu_threads), write=not dry_run, l3=not no_l3,
                                     progress=status.update)
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    if as_json:
        emit_json(record.model_dump(mode="json"))
        return
    for line in summary_lines(record, asset_dir):
        results.print(line, markup=False, highlight=False)
