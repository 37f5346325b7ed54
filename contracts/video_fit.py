"""`deformsmith calibrate DIR --video FILE` (issue #39): what a video of the real object (and optionally a flat-plate
press test) says about it, and the material fitted to it, written into the asset as calibration/video_fit.json.

Every quantity is SI with its unit in the field name; image quantities are in pixels (`_px`). A metric the video
could not determine is None and named in `undetermined` with the reason, never guessed.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from contracts.base import Model
from contracts.manipulation import L2Check, MaterialRevision
from contracts.material import Material

VIDEO_FIT_JSON = "calibration/video_fit.json"
SIDE_BY_SIDE_JPG = "calibration/side_by_side.jpg"  # the real clip's key frames above the simulated ones

ScaleSource = Literal["size", "drop_height", "gravity"]


class VideoScale(Model):
    """How pixels became metres."""

    metres_per_px: float = Field(gt=0)
    source: ScaleSource = Field(description="size: --size over the object's longest extent in px in its resting frames "
                                "(else its flight frames); drop_height: --drop-height over the fall in px; gravity: "
                                "9.81 m/s^2 over the free fall's fitted acceleration in px/s^2")
    detail: str = Field(description="the numbers behind it, in words")
    gravity_check: float | None = Field(default=None, description="the free fall's fitted acceleration in m/s^2 "
                                        "under this scale (9.81 when scale and frame rate agree)")


class TrackSummary(Model):
    """The tracker's account of the video (tasks.calibrate.track)."""

    frames: int = Field(ge=0, description="frames read")
    frames_tracked: int = Field(ge=0)
    frames_dropped: int = Field(ge=0, description="frames where segmentation found no object (left out of the track)")
    frames_at_edge: int = Field(default=0, ge=0, description="of those, frames where the object touched the frame's "
                                "edge (partly out of the picture)")
    frames_repeated: int = Field(default=0, ge=0, description="frames that repeat the one before (a re-timed clip), "
                                 "left out and not counted as dropped")
    fps: float = Field(gt=0)
    fps_source: Literal["file", "option"]
    frame_size_px: tuple[int, int] = Field(description="(width, height) of the frames as tracked (after any downscale)")
    downscale: float = Field(gt=0, description="tracked frame size / file frame size")
    floor_y_px: float = Field(description="the floor line: the object's bottom in its resting frames (image y, down)")
    rest_height_px: float | None = None
    flight_height_px: float | None = None
    longest_extent_px: float = Field(gt=0, description="the object's longest extent in px in the frames the scale uses")
    tracking_confidence: float = Field(ge=0.0, le=1.0, description="fraction of frames tracked times the mask-area "
                                       "consistency (1 - the coefficient of variation of the mask area over the "
                                       "flight frames, floored at 0)")
    area_consistency: float = Field(ge=0.0, le=1.0)
    threshold: float = Field(description="background-difference threshold (grey levels)")


class VideoMetrics(Model):
    """L2's drop metrics as the video shows them (tasks.calibrate.metrics)."""

    release_time_s: float | None = None
    first_impact_time_s: float | None = None
    drop_height_m: float | None = Field(default=None, description="the bottom's fall from release to the floor, "
                                        "measured in the video (metres by the scale)")
    rebound_ratio: float | None = Field(default=None, description="(COM apex after the first impact - COM at rest) / "
                                        "(COM at release - COM at rest), as L2's drop probe defines it [-]")
    restitution_from_velocities: float | None = Field(default=None, description="speed out / speed in at the first "
                                                      "impact from parabolas fitted to the flights either side [-]")
    impact_strain: float | None = Field(default=None, description="largest height compression at the first impact, "
                                        "1 - h / h_flight with h the silhouette's second-moment height [-]")
    impact_frames: int = Field(default=0, description="frames with the object on the floor in the first impact")
    settle_time_s: float | None = Field(default=None, description="from release until the bouncing is over: the "
                                        "centroid stays within the contact tolerance of a line through the last frames "
                                        "(flat at rest; sloped for a ball rolling on)")
    settle_tolerance_m: float | None = Field(default=None, description="that tolerance in metres: a bounce that rises "
                                             "less is not seen (the simulated settle time uses the same)")
    recovery_ratio: float | None = Field(default=None, description="(rest height - lowest height at impact) / "
                                         "(flight height - lowest height) [-]")
    left_floor: bool = Field(default=False, description="the object left the floor after the first impact")
    bounces: list[dict[str, float]] = Field(default_factory=list, description="each impact's restitution from the "
                                            "video's timing alone (flight after / flight before; the first: over twice "
                                            "the fall): time_s, speed_in_m_per_s, speed_out_m_per_s, restitution")


class PressTest(Model):
    """A flat-plate press test's force-displacement table (CSV) reduced to L2's compression metric."""

    path: str
    rows: int
    strain: float = Field(description="the strain the effective modulus is read at (displacement / object height)")
    force_n: float
    cross_section_m2: float
    effective_modulus_pa: float = Field(description="(F / A) / strain, as L2's compression probe defines it")


class FitStep(Model):
    """One simulation of the fit."""

    youngs_modulus_pa: float
    viscosity_pa_s: float
    damping_rate_per_s: float | None = None
    probe: Literal["drop_impact", "compress", "bounces"]
    metrics: dict[str, float]


class CalibrationChecks(Model):
    """The fitted material through L2's held-out tests and L3's revise/re-validate edge before it is published
    (flows.calibrate): it is published only when `passed`."""

    passed: bool = Field(description="every gate in `gates` held")
    gates: dict[str, bool] = Field(description="gate -> held: 'L2 hard gates' (the selection probes), 'L2 held-out "
                                   "hard gates' (the held-out tests), 'L3 robot confirmation' (when L3 ran)")
    l2: L2Check = Field(description="L2's revalidation of the fitted material at the asset's own settings: its "
                                    "selection probes and held-out tests (flows.l3_material.revalidate_in_l2)")
    word_bands: dict[str, bool] = Field(default_factory=dict, description="the target bands from the words that held "
                                        "for the L2 material -> whether the fitted material still holds them "
                                        "(information, not a gate: the video measures the real object)")
    l3: MaterialRevision | None = Field(default=None, description="the robot under the plan, physical model and force "
                                        "budget of manipulation.json with the fitted material (L3's revise/re-validate "
                                        "edge, trigger 'calibration'); None when it did not run")
    l3_status: Literal["confirmed", "failed", "skipped"]
    l3_note: str = Field(description="what happened to L3, or why it did not run (--no-l3; no L3 on this asset)")


class KeyFrame(Model):
    """One moment of the side-by-side comparison: the real frame and the simulated drop at the same time."""

    label: str = Field(description="release, first impact, top of first bounce, rest")
    t_s: float = Field(description="time in the video [s]")
    frame: int = Field(description="the video's frame index")
    sim_t_s: float = Field(description="time after the simulated release [s]")


class Comparison(Model):
    """The real clip beside the simulated one (tasks.calibrate.compare)."""

    image: str = Field(description="the side-by-side strip, relative to the asset (JPEG)")
    frames: list[KeyFrame]
    note: str = Field(default="", description="how the simulated frames were drawn")


class VideoFitRecord(Model):
    """calibration/video_fit.json: the video's evidence, the fit and its limits."""

    schema_version: int = 1
    video: str
    press: PressTest | None = None
    size_m: float = Field(gt=0, description="the object's longest extent the fit simulated it at")
    size_source: Literal["option", "video"]
    drop_height_m: float = Field(gt=0, description="the drop height the fit simulated")
    drop_height_source: Literal["option", "video"]
    scale: VideoScale
    track: TrackSummary
    metrics: VideoMetrics
    prior: Material = Field(description="the asset's material before the fit")
    fitted: Material
    youngs_modulus_source: Literal["impact_strain", "press", "settle_time", "prior"] = Field(
        description="settle_time: the video shows no compression but the bounces end; E is the one whose simulated "
                    "settle time matches the video's, the viscosity refitted to the rebound at each E")
    viscosity_source: Literal["rebound", "no_bounce_lower_bound", "prior"]
    simulated: dict[str, float] = Field(description="the fitted material's simulated metrics (same definitions)")
    residuals: dict[str, float] = Field(description="metric -> (simulated - video) / video after the fit")
    undetermined: dict[str, str] = Field(default_factory=dict, description="metric or parameter -> why the video "
                                         "(or the press test) could not determine it")
    steps: list[FitStep] = Field(default_factory=list)
    sim_calls: int = 0
    converged: bool = False
    notes: list[str] = Field(default_factory=list)
    checks: CalibrationChecks | None = Field(default=None, description="L2's held-out tests and L3's confirmation of "
                                             "the fitted material (None: a dry run, or a record written before them)")
    comparison: Comparison | None = Field(default=None, description="the real clip's key frames beside the simulated "
                                          "drop's (None: a dry run, or too few frames to pick them)")


__all__ = ["CalibrationChecks", "Comparison", "FitStep", "KeyFrame", "PressTest", "SIDE_BY_SIDE_JPG", "ScaleSource",
           "TrackSummary", "VIDEO_FIT_JSON", "VideoFitRecord", "VideoMetrics", "VideoScale"]
