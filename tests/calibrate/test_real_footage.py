"""What real footage does to the tracker (issue #39, the real clips under docs/calibration/real/): a hand or an arm
in the picture, a shadow or the camera's exposure changing the scene, frames repeated by a re-timed clip, the object
leaving the picture, a ball that rolls on (toward the camera) instead of coming to rest. Synthetic frames with a known
answer, each broken the way a real clip was."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from tasks.calibrate.metrics import analyse, settle_time, video_metrics
from tasks.calibrate.sim import fall_time_s, flight_time_s
from tasks.calibrate.synthetic import Camera, bouncing_centres, degrade, draw, scene
from tasks.calibrate.track import duplicate_frames, scene_background, noise_threshold, track_object

FPS, DROP, R, E = 240.0, 0.15, 0.02, 0.6
CAM = Camera(width_px=160, height_px=240, px_per_m=1000.0, floor_y_px=225.0, centre_x_px=80.3)
BALL = (40, 170, 60)  # a green ball
SKIN = (205, 150, 120)


def clean_frames(cam: Camera, centres: np.ndarray, radius_m: float) -> np.ndarray:
    """The disc drawn on the scene, float32 RGB, before noise and compression (float64 frames of a 640-frame clip are
    370 MB, and allocating them was most of these tests' time)."""
    bg = scene(cam).astype(np.float32)
    xs, ys = cam.project(centres[:, 0], centres[:, 1])
    return np.stack([draw(bg, np.array([[x, y]]), radius_m * cam.px_per_m, BALL) for x, y in zip(xs, ys)])


def rebound(frames: np.ndarray, fps: float = FPS) -> float | None:
    return analyse(track_object(frames, fps)).rebound_ratio


@pytest.fixture(scope="module")
def centres() -> np.ndarray:
    return bouncing_centres(DROP, R, E, FPS, hold_s=0.1)


@pytest.fixture(scope="module")
def drawn(centres: np.ndarray) -> np.ndarray:
    """clean_frames(CAM, centres, R), drawn once for the module (~1 s): each test breaks its own copy."""
    frames = clean_frames(CAM, centres, R)
    frames.setflags(write=False)
    return frames


def test_a_hand_that_holds_and_leaves_is_not_the_object(drawn: np.ndarray) -> None:
    """An arm (a skin-coloured bar, far bigger than the ball) holds the ball, then swings away through the picture
    while the ball falls: the largest region is the arm, the tracked one must be the ball."""
    frames = drawn.copy()
    hold = int(0.1 * FPS)
    for i in range(len(frames)):
        x0 = 80 + (0 if i < hold else 2 * (i - hold))  # the arm leaves to the right, two pixels a frame
        if x0 >= CAM.width_px:
            break
        arm = np.zeros(frames.shape[1:3], np.float32)
        cv2.rectangle(arm, (int(x0) + 12, 0), (int(x0) + 70, 60), 1.0, -1)
        frames[i] = frames[i] * (1 - arm[..., None]) + np.asarray(SKIN, np.float32) * arm[..., None]
    frames = degrade(frames, 3.0, 80)
    tr = track_object(frames, FPS)
    assert tr.reference is not None
    d = analyse(tr)
    assert d.rebound_ratio == pytest.approx(E * E, rel=0.04)
    assert float(np.median(tr.box_width)) == pytest.approx(2 * R * CAM.px_per_m, abs=2.0)


def test_a_shadow_over_the_scene_while_the_ball_falls_is_not_the_object(drawn: np.ndarray) -> None:
    """The filmer's soft shadow darkens the left half of the scene by 15 % in the first half of the clip (their
    camera brightened as they stepped away): the ball is tracked through it and its rebound is the drawn one."""
    frames = drawn.copy()
    xx = np.arange(CAM.width_px, dtype=np.float32)
    shade = 1.0 - 0.15 / (1.0 + np.exp((xx - 95.0) / 8.0))  # a soft edge across the ball's column
    for i in range(len(frames) // 2):
        frames[i] *= shade[None, :, None]
    frames = degrade(frames, 3.0, 80)
    tr = track_object(frames, FPS)
    assert tr.dropped <= 0.05 * tr.frames
    assert analyse(tr).rebound_ratio == pytest.approx(E * E, rel=0.04)


def test_a_retimed_clip_repeats_frames_and_they_are_left_out(centres: np.ndarray) -> None:
    """A 120 fps capture stored at 240 fps by showing each frame twice: the repeats are found and left out (their
    time stamps are not when they were taken), not counted as dropped, and the rebound, the restitution and the fall
    are those of the 120 fps frames at their own rate."""
    frames = degrade(clean_frames(CAM, centres[::2], R), 3.0, 80)
    doubled = np.repeat(frames, 2, axis=0)
    rep = duplicate_frames(doubled)
    # every repeat found is a second copy; the moving frames' are all found (held or at rest, a repeat and the still
    # scene look alike: those are kept, their times do not matter)
    assert rep.sum() >= 0.4 * len(frames) and not rep[0::2].any()
    assert not duplicate_frames(frames).any()
    tr = track_object(doubled, FPS)
    assert tr.duplicates == rep.sum() and tr.dropped <= 2
    d, single = analyse(tr), analyse(track_object(frames, FPS / 2))
    assert d.rebound_ratio == pytest.approx(single.rebound_ratio, rel=0.01)
    assert d.restitution == pytest.approx(single.restitution, rel=0.03)  # a slow frame's repeat may stay in
    assert d.restitution == pytest.approx(E, rel=0.04)
    assert d.rebound_ratio == pytest.approx(E * E, rel=0.06)
    assert d.fall is not None and 2.0 * d.fall.c == pytest.approx(9.81 * CAM.px_per_m, rel=0.05)


def test_frames_with_the_object_at_the_edge_are_dropped_and_counted() -> None:
    """The ball is held and released partly above the top of the picture: those frames are left out (the centre and
    extent of a cut ball are wrong) and counted apart; every frame kept shows the whole ball, and the fall's parabola
    still finds the release above the picture."""
    cam = Camera(width_px=160, height_px=150, px_per_m=1000.0, floor_y_px=120.0, centre_x_px=80.3)
    path = bouncing_centres(0.09, R, 0.9, FPS, hold_s=0.05, rest_s=0.1)
    frames = degrade(clean_frames(cam, path, R), 3.0, 80)
    _, ys = cam.project(path[:, 0], path[:, 1])
    cut = int(np.count_nonzero(ys - R * cam.px_per_m < 0.5))
    assert cut > 10
    tr = track_object(frames, FPS)
    assert cut - 3 <= tr.at_edge <= cut + 3
    assert float(np.max(tr.box_height)) <= 2 * R * cam.px_per_m + 3.0
    assert float(np.min(tr.box_height)) >= 2 * R * cam.px_per_m - 3.0
    assert analyse(tr).drop_px == pytest.approx(90.0, rel=0.03)


def test_a_ball_that_rolls_toward_the_camera_settles_when_its_bounces_end() -> None:
    """A ball that, its bounces over, rolls on toward the camera (down the picture, 10 cm a second) and is never at
    rest in view: its first impact is its first big fall's (not the lowest bottom, the end of the roll), its rebound
    the drawn one, and it has settled where its bounces end, not never."""
    g, fps = 9.81, 120.0
    tol = 1.5 / CAM.px_per_m  # the bounces end when one rises less than the contact tolerance (1.5 px here)
    t_end, v = fall_time_s(DROP, 0.0), np.sqrt(2 * g * DROP)
    while (E * v) ** 2 / (2 * g) >= tol:
        v *= E
        t_end += flight_time_s(v, 0.0)
    hold = 0.05
    path = bouncing_centres(DROP, R, E, fps, hold_s=hold, rest_s=0.4)
    t = np.arange(len(path)) / fps
    rolling = np.clip(t - hold - t_end, 0.0, None)
    path = np.stack([path[:, 0], path[:, 1] - 0.10 * rolling], 1)
    frames = degrade(clean_frames(CAM, path, R), 3.0, 80)
    d = analyse(track_object(frames, fps))
    assert not d.resting
    assert d.floor_y == pytest.approx(CAM.floor_y_px, abs=1.5)
    assert d.rebound_ratio == pytest.approx(E * E, rel=0.04)
    m = video_metrics(d, 1.0 / CAM.px_per_m)
    assert m.settle_time_s is not None
    assert m.settle_time_s == pytest.approx(t_end, abs=3.0 / fps)


def test_the_settle_rule_follows_a_rolling_line_and_refuses_a_clip_still_bouncing() -> None:
    t = np.arange(100) / 50.0
    y = 100.0 + 5.0 * t  # rolling down the picture, 5 px a second
    y[:40] -= 30.0 * np.abs(np.sin(np.pi * t[:40] / 0.4))  # bounces until 0.8 s
    assert settle_time(t, y, 0.0, 1.5, 10) == pytest.approx(0.8, abs=0.04)
    y[-10:] -= 8.0 * np.abs(np.sin(np.pi * t[-10:] / 0.1))
    assert settle_time(t, y, 0.0, 1.5, 10) is None


def test_the_background_takes_the_clear_region_at_rest_not_a_speck_of_noise(drawn: np.ndarray) -> None:
    """A few pixels that change between the first and the last frames below the ball's rest (a speck at the
    picture's bottom) are not the object at rest: the reference is the ball's, of its area and colour."""
    frames = drawn.copy()
    frames[-len(frames) // 3:, 236:239, 10:13] += 25.0
    frames = degrade(frames, 3.0, 80)
    thr = noise_threshold(frames)
    _, ref = scene_background(frames, thr)
    assert ref is not None
    assert ref.area == pytest.approx(np.pi * (R * CAM.px_per_m) ** 2, rel=0.25)
    assert np.linalg.norm(np.asarray(ref.colour) - np.asarray(BALL)) < 25.0


def test_each_bounce_restitution_from_the_timing_alone(drawn: np.ndarray) -> None:
    """The flights between impacts give each impact's restitution without a scale (a clip whose size is unsure
    still shows whether its ball's restitution changes with the speed): the drawn 0.6 at every bounce long enough."""
    frames = degrade(drawn.copy(), 3.0, 80)
    d = analyse(track_object(frames, FPS))
    assert len(d.bounces) >= 3
    for b in d.bounces:
        assert b["restitution"] == pytest.approx(E, abs=0.05)
    assert d.bounces[0]["speed_in_m_per_s"] == pytest.approx(np.sqrt(2 * 9.81 * DROP), rel=0.05)


def test_the_simulated_bounces_settle_as_the_video_rule_reads_them(monkeypatch: pytest.MonkeyPatch) -> None:
    """The settle time the fit's material gives (tasks.calibrate.sim.bounce_settle): the engine's impact replaced by
    a restitution of 0.6 at every speed, the bounces end where a rise is under the tolerance (the closed form), and
    sampled at a video's frames the video's own rule reads the same end within a frame."""
    import tasks.calibrate.sim as sim_mod
    from contracts.material import Material
    from contracts.sim import SimConfig

    calls: list[float] = []

    def fixed(*args: object, **kwargs: object) -> dict[str, float]:
        calls.append(float(args[4]))  # type: ignore[arg-type]
        return {"restitution": E, "finite": 1.0}

    monkeypatch.setattr(sim_mod, "impact", fixed)
    g, tol, fps = 9.81, 0.002, 60.0
    t_end, v = fall_time_s(DROP, 0.0), np.sqrt(2 * g * DROP)
    while (E * v) ** 2 / (2 * g) >= tol:
        v *= E
        t_end += flight_time_s(v, 0.0)
    frames = np.arange(int(2.0 * fps)) / fps
    out = sim_mod.bounce_settle(np.zeros((1, 3)), np.ones(1), None, Material(youngs_modulus_pa=1e5, poisson_ratio=0.3),  # type: ignore[arg-type]
                                DROP, SimConfig(), tol, frames, 0.1)
    assert out["settle_time_s"] == pytest.approx(t_end, rel=1e-3)
    assert out["settle_time_frames_s"] == pytest.approx(t_end, abs=1.0 / fps)
    assert calls[0] == pytest.approx(np.sqrt(2 * g * DROP)) and min(calls) == pytest.approx(np.sqrt(2 * g * tol))


def test_e_from_the_settle_time_when_the_video_shows_no_compression(monkeypatch: pytest.MonkeyPatch) -> None:
    """E's search on the settle time (tasks.calibrate.fit.fit_settle), a softer E settling later: it finds the E
    whose settle time is the video's within 5 %, refitting the viscosity at each E; out of its decade's reach it
    stops at the bound and says so."""
    from types import SimpleNamespace

    import tasks.calibrate.fit as fit_mod

    refits: list[float] = []

    def refit(p: object, young: float, d: float, target: float) -> tuple[float, float]:
        refits.append(young)
        return 3.0, d

    monkeypatch.setattr(fit_mod, "rebound_at", refit)
    reached = lambda young, eta, d: {"rebound_ratio": 0.4}  # noqa: E731  (the viscosity reaches the rebound)
    law = SimpleNamespace(settle=2.0, settle_time=lambda young, eta, d: 1.5 * (young / 1e6) ** -0.25, drop=reached)
    notes: list[str] = []
    young, eta, _ = fit_mod.fit_settle(law, 1e6, 0.0, 0.4, notes)  # type: ignore[arg-type]
    assert law.settle_time(young, eta, 0.0) == pytest.approx(2.0, rel=fit_mod.SETTLE_TOLERANCE)
    assert young < 1e6 and len(refits) <= fit_mod.SETTLE_E_SIMS and "E from the settle time" in notes[0]
    far = SimpleNamespace(settle=20.0, settle_time=law.settle_time, drop=reached)
    notes = []
    young, _, _ = fit_mod.fit_settle(far, 1e6, 0.0, 0.4, notes)  # type: ignore[arg-type]
    assert young == pytest.approx(1e6 * fit_mod.SETTLE_E_RANGE[0]) and "out of E's reach" in notes[-1]


def test_e_from_the_settle_time_rules_out_an_e_whose_rebound_the_viscosity_cannot_reach(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A hollow shell loses more at a hard impact the softer it is (it buckles): below some E even the least
    viscosity leaves less rebound than the video's, whatever that E's settle time. fit_settle rules such an E out
    and goes stiffer (the prior here is too soft, and the settle time alone would send it softer still), then finds
    the settle time among the E that reach the rebound, following the settle time's own trend with E (here a stiffer
    shell settles later), and says so."""
    from types import SimpleNamespace

    import tasks.calibrate.fit as fit_mod

    monkeypatch.setattr(fit_mod, "rebound_at", lambda p, young, d, target: (1.0, d))
    law = SimpleNamespace(settle=2.0, settle_time=lambda young, eta, d: 1.5 * (young / 1e6) ** 0.25,
                          drop=lambda young, eta, d: {"rebound_ratio": 0.4 if young >= 2e6 else 0.25})
    notes: list[str] = []
    young, _, _ = fit_mod.fit_settle(law, 1e6, 0.0, 0.4, notes)  # type: ignore[arg-type]
    assert young >= 2e6
    assert law.settle_time(young, 1.0, 0.0) == pytest.approx(2.0, rel=fit_mod.SETTLE_TOLERANCE)
    assert any("out of the viscosity's reach" in n for n in notes)
