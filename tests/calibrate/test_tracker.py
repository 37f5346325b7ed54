"""The tracker on synthetic frames (tasks.calibrate): a drawn disc on a known parabola with bounces, with camera
noise and JPEG compression; what it measures equals what was drawn."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from contracts.errors import InputError
from tasks.calibrate.metrics import analyse, impact_amplitude, video_metrics
from tasks.calibrate.scale import video_scale
from tasks.calibrate.synthetic import Camera, bouncing_centres, disc_video, scene
from tasks.calibrate.track import Track, track_object
from tasks.calibrate.video import read_video, write_video

FPS, DROP, R = 240.0, 0.15, 0.02
CAM = Camera(width_px=100, height_px=240, px_per_m=1000.0, floor_y_px=225.0, centre_x_px=50.3)


@pytest.fixture(scope="module")
def bounce() -> tuple[np.ndarray, np.ndarray]:
    """A disc dropped from 0.15 m bouncing with restitution 0.6, its video and its drawn centres."""
    centres = bouncing_centres(DROP, R, 0.6, FPS)
    return disc_video(CAM, centres, R, noise_grey=4.0, jpeg_quality=75), centres


@pytest.fixture(scope="module")
def bounce_track(bounce: tuple[np.ndarray, np.ndarray]) -> Track:
    """track_object of the bounce's video, once for the tests that read the same track."""
    return track_object(bounce[0], FPS)


def test_the_tracked_rebound_equals_the_drawn_one(bounce_track: Track) -> None:
    tr = bounce_track
    d = analyse(tr)
    assert tr.dropped == 0
    assert d.left_floor and d.resting
    assert d.rebound_ratio == pytest.approx(0.36, rel=0.03)  # the centre's rise over its fall: e^2
    assert d.restitution == pytest.approx(0.6, rel=0.03)
    assert d.floor_y == pytest.approx(CAM.floor_y_px, abs=1.0)
    assert d.release_t == pytest.approx(0.05, abs=1.5 / FPS)
    assert d.drop_px == pytest.approx(DROP * CAM.px_per_m, rel=0.02)


def test_the_scale_from_the_size_and_from_gravity(bounce_track: Track) -> None:
    d = analyse(bounce_track)
    by_size = video_scale(d, 2 * R, None)
    assert by_size.source == "size" and by_size.metres_per_px == pytest.approx(1e-3, rel=0.04)
    by_gravity = video_scale(d, None, None)
    assert by_gravity.source == "gravity" and by_gravity.metres_per_px == pytest.approx(1e-3, rel=0.03)
    by_drop = video_scale(d, None, DROP)
    assert by_drop.source == "drop_height" and by_drop.metres_per_px == pytest.approx(1e-3, rel=0.02)
    m = video_metrics(d, by_size.metres_per_px)
    assert m.drop_height_m == pytest.approx(DROP, rel=0.05)
    assert m.settle_time_s is not None and m.settle_time_s > 0.3


def test_frames_without_the_object_are_dropped_and_counted(bounce: tuple[np.ndarray, np.ndarray]) -> None:
    frames, _ = bounce
    blank = frames.copy()
    bg = np.clip(scene(CAM), 0, 255).astype(np.uint8)
    gone = [20, 21, 60, 100]
    for i in gone:
        blank[i] = bg
    tr = track_object(blank, FPS)
    assert tr.dropped == len(gone)
    assert analyse(tr).rebound_ratio == pytest.approx(0.36, rel=0.03)


def test_an_object_that_does_not_bounce_has_no_rebound() -> None:
    centres = bouncing_centres(DROP, R, 0.0, FPS)
    d = analyse(track_object(disc_video(CAM, centres, R), FPS))
    assert not d.left_floor and d.rebound_ratio == 0.0


def test_the_half_sine_fit_is_not_biased_by_noise() -> None:
    rng = np.random.default_rng(3)
    t = np.arange(40) / 1000.0
    clean = np.where((t >= 0.012) & (t <= 0.025), 0.05 * np.sin(np.pi * (t - 0.012) / 0.013), 0.0)
    fits = [impact_amplitude(t, clean + rng.normal(0, 0.005, t.shape)) for _ in range(40)]
    assert impact_amplitude(t, clean) == pytest.approx(0.05, rel=0.03)
    assert float(np.mean(fits)) == pytest.approx(0.05, rel=0.05)
    assert float(np.mean([np.max(clean + rng.normal(0, 0.005, t.shape)) for _ in range(40)])) > 0.052  # the largest sample is biased up


def test_a_video_without_the_object_is_refused() -> None:
    still = np.repeat(np.clip(scene(CAM), 0, 255).astype(np.uint8)[None], 30, axis=0)
    with pytest.raises(InputError, match="never found"):
        track_object(still, FPS)


def test_an_h264_video_tracks_as_the_frames_do(bounce: tuple[np.ndarray, np.ndarray], tmp_path: Path) -> None:
    """The frames written as H.264 (imageio-ffmpeg) and read back by OpenCV: the rate from the file, the rebound
    within 3 % of the drawn one."""
    frames, _ = bounce
    video = read_video(write_video(tmp_path / "bounce.mp4", frames, FPS))
    assert video.fps == pytest.approx(FPS) and video.fps_source == "file" and len(video.frames) == len(frames)
    assert analyse(track_object(video.frames, video.fps)).rebound_ratio == pytest.approx(0.36, rel=0.03)


def test_an_impact_between_two_frames_is_found_by_its_reversal() -> None:
    """A 0.3 m drop at 240 fps: 10 px a frame at the floor, so no frame shows the ball on the floor line; the first
    impact is where the fall turns, the rebound and the restitution are still the drawn ones, the strain is not
    measured (and says why)."""
    cam = Camera(width_px=160, height_px=380, px_per_m=1000.0, floor_y_px=360.0, centre_x_px=80.3)
    frames = disc_video(cam, bouncing_centres(0.3, 0.025, 0.5, FPS, rest_s=0.2), 0.025)
    d = analyse(track_object(frames, FPS))
    assert d.impact_frames == 0 and d.contact is not None
    assert d.drop_px == pytest.approx(300.0, rel=0.02)
    assert d.rebound_ratio == pytest.approx(0.25, rel=0.04)
    assert d.restitution == pytest.approx(0.5, rel=0.03)
    assert d.strain is None and "frame rate is too low" in d.why["impact_strain"]
