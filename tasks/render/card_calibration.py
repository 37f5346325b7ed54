"""The card's calibration section (issue #39), when the asset was calibrated from a video (calibration/video_fit.json,
flows.calibrate): the real clip's key frames beside the simulated drop's, the fitted E and viscosity beside the prior,
the video's metrics beside the simulated ones with the fit's residuals, the checks the fitted material passed and the
record's honest limits (the scale's source, the tracking confidence, frames dropped, what the video could not
determine). Pure data: card_html and card_png draw it."""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict, ValidationError

from contracts.errors import InputError
from contracts.video_fit import VIDEO_FIT_JSON, VideoFitRecord

# metric -> (label, unit, VideoMetrics field); the simulated value and residual are the record's, under the same name
METRICS = {"rebound_ratio": ("rebound ratio", "-"), "impact_strain": ("impact strain", "-"),
           "settle_time_s": ("settle time", "s"), "recovery_ratio": ("recovery ratio", "-")}


class CalibrationRow(BaseModel):
    """One metric: the video's value, the fitted material's simulated value, the residual (sim - video) / video."""

    model_config = ConfigDict(frozen=True)

    label: str
    metric: str
    unit: str
    video: float | None
    simulated: float | None
    residual: float | None
    note: str | None = None  # no video value: why (the record's `undetermined`)


class CalibrationCard(BaseModel):
    """What the card shows of a calibration."""

    model_config = ConfigDict(frozen=True)

    record: str  # calibration/video_fit.json
    video: str  # the clip's file as given to `calibrate`
    image: str | None  # calibration/side_by_side.jpg, relative to the asset (None: not drawn)
    frames: list[str]  # 'release at 0.05 s', ... in the strip's order
    prior: tuple[float, float]  # (E [Pa], viscosity [Pa s]) before the fit
    fitted: tuple[float, float]
    youngs_modulus_source: str
    viscosity_source: str
    rows: list[CalibrationRow]
    checks: list[str]  # 'L2 held-out hard gates: passed', the L3 line
    limits: list[str]  # the scale source, tracking confidence, frames dropped, undetermined metrics
    converged: bool


def _limits(r: VideoFitRecord) -> list[str]:
    """The record's honest limits, one line each."""
    t = r.track
    out = [f"scale: {r.scale.metres_per_px * 1000:.4g} mm/px from {r.scale.source} ({r.scale.detail})",
           f"size {r.size_m:.4g} m ({r.size_source}); drop height {r.drop_height_m:.4g} m ({r.drop_height_source})",
           f"tracking confidence {t.tracking_confidence:.2f}: {t.frames_tracked} of {t.frames} frames tracked, "
           f"{t.frames_dropped} dropped ({t.frames_at_edge} at the frame's edge), {t.frames_repeated} repeated; "
           f"{t.fps:g} fps ({t.fps_source})"]
    out += [f"not determined: {k}: {why}" for k, why in r.undetermined.items()]
    out += [f"note: {n}" for n in r.notes]  # the fit's own warnings (a scale that gravity disagrees with, ...)
    return out


def _checks(r: VideoFitRecord) -> list[str]:
    """The gates the fitted material passed before it was published, and L3's line."""
    c = r.checks
    if c is None:
        return ["not checked (a record written before the checks)"]
    out = [f"{gate}: {'passed' if ok else 'FAILED'}" for gate, ok in c.gates.items()]
    out.append(f"held-out tests run: {', '.join(c.l2.held_out_probes) or 'none'}")
    out.append(f"L3 {c.l3_status}: {c.l3_note}")
    left = [m for m, ok in c.word_bands.items() if not ok]
    if left:
        out.append(f"outside the target bands from the words (not a gate: the video measures the object): "
                   f"{', '.join(left)}")
    return out


def calibration_card(asset_dir: Path) -> CalibrationCard | None:
    """The calibration section of an asset directory's card; None when it was not calibrated (InputError naming the
    record when it is there but invalid)."""
    path = Path(asset_dir) / VIDEO_FIT_JSON
    if not path.is_file():
        return None
    try:
        r = VideoFitRecord.model_validate_json(path.read_text(encoding="utf-8"))
    except (ValidationError, ValueError) as exc:
        raise InputError(f"{path}: not a valid calibration record ({type(exc).__name__})") from None
    video = r.metrics.model_dump()
    rows = [CalibrationRow(label=label, metric=m, unit=unit, video=video.get(m), simulated=r.simulated.get(m),
                           residual=r.residuals.get(m), note=r.undetermined.get(m) if video.get(m) is None else None)
            for m, (label, unit) in METRICS.items()]
    comp = r.comparison
    image = comp.image if comp is not None and (Path(asset_dir) / comp.image).is_file() else None
    return CalibrationCard(
        record=VIDEO_FIT_JSON, video=Path(r.video).name, image=image,
        frames=[f"{k.label} at {k.t_s:.2f} s" for k in comp.frames] if comp is not None else [],
        prior=(r.prior.youngs_modulus_pa, r.prior.viscosity_pa_s),
        fitted=(r.fitted.youngs_modulus_pa, r.fitted.viscosity_pa_s),
        youngs_modulus_source=r.youngs_modulus_source, viscosity_source=r.viscosity_source, rows=rows,
        checks=_checks(r), limits=_limits(r), converged=r.converged)


__all__ = ["CalibrationCard", "CalibrationRow", "calibration_card"]
