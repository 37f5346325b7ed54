"""Drop protocol videos: views named as the stills, 30 fps x 5 s = 150 frames, the fall visible, deterministic."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from tasks.render.protocol_video import (
    CARD_TIMES_S,
    HOLD_AFTER_S,
    HOLD_BEFORE_S,
    SLOW_MOTION,
    VIEW_NAMES,
    _disc_renderer,
    card_still_name,
    clip_states,
    drop_files,
    protocol_camera,
    render_protocol_frames,
    view_axes,
)
from tasks.render.views import render_view

RED = np.array([0.9, 0.1, 0.1])


def _bar(extents_m: tuple[float, float, float], spacing_m: float = 0.005) -> tuple[np.ndarray, trimesh.Trimesh]:
    """Particles filling a box resting on z = 0 (centred in x, y) and the box's mesh."""
    axes = [np.arange(spacing_m / 2, e, spacing_m) - e / 2 for e in extents_m]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    pts[:, 2] += extents_m[2] / 2
    mesh = trimesh.creation.box(extents=extents_m)
    mesh.apply_translation([0, 0, extents_m[2] / 2])
    return pts, mesh


def _gaussians(particles_m: np.ndarray, sigma_m: float = 0.003) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """One red Gaussian on each particle, bound to it alone."""
    n = len(particles_m)
    g = {"positions_m": particles_m.copy(), "colors": np.tile(RED, (n, 1)), "opacities": np.full(n, 0.95),
         "particle_index": np.arange(n)[:, None], "particle_weight": np.ones((n, 1))}
    return g, np.tile(np.eye(3) * sigma_m**2, (n, 1, 1))


def _falling(particles_m: np.ndarray, clearance_m: float, n_states: int = 151, fps: float = 30.0
             ) -> tuple[np.ndarray, np.ndarray]:
    """States of a rigid body released clearance_m above the table: free fall, then at rest on it."""
    t = np.arange(n_states) / fps
    lift = np.maximum(clearance_m - 0.5 * 9.81 * t**2, 0.0)
    x = particles_m[None] + lift[:, None, None] * np.array([0.0, 0.0, 1.0])
    return x.astype(np.float32), np.tile(np.eye(3, dtype=np.float32), (n_states, len(particles_m), 1, 1))


def _red_mask(img: np.ndarray) -> np.ndarray:
    r, g, b = (img[..., i].astype(int) for i in range(3))
    return (r > 120) & (r > g + 50) & (r > b + 50)


def _aspect(mask: np.ndarray) -> float:
    ys, xs = np.nonzero(mask)
    return float(np.ptp(xs) + 1) / float(np.ptp(ys) + 1)


def test_video_views_show_the_side_of_the_still_with_the_same_name() -> None:
    """A 12 x 3 x 3 cm bar: the front still (camera on +x) shows its 3 cm end, the side still its 12 cm length; the
    first video frame of each view has the silhouette of the still of its name, and the same screen-right axis."""
    particles, mesh = _bar((0.12, 0.03, 0.03))
    g, cov = _gaussians(particles)
    x, F = _falling(particles, 0.0075, n_states=1)
    aspects = {}
    for view in VIEW_NAMES:
        still = render_view(mesh, view, 96)
        video = render_protocol_frames(g, cov, particles, x, F, view, 160, 96, renderer=_disc_renderer)[0]
        aspects[view] = (_aspect(still.min(axis=2) < 250), _aspect(_red_mask(video)))
        rot, _, _ = protocol_camera(x, view, 160, 96).frame()
        assert np.allclose(rot[0], view_axes(view)[0], atol=1e-9)  # screen-right is the still's
    (front_still, front_video), (side_still, side_video) = aspects["front"], aspects["side"]
    assert side_still > 3 * front_still  # the fixture tells the views apart
    for own, shown, other in ((front_still, front_video, side_still), (side_still, side_video, front_still)):
        assert abs(np.log(shown / own)) < abs(np.log(shown / other))  # closer to its own still than to the other
        assert abs(np.log(shown / own)) < np.log(1.6)


def test_drop_video_is_the_motion_in_slow_motion_and_the_object_visibly_falls(tmp_path: Path) -> None:
    """151 recorded states at 30 fps of a body that falls for 0.045 s and then rests: the clip holds the start for
    HOLD_BEFORE_S, shows the fall SLOW_MOTION x slower and HOLD_AFTER_S of the rest (not 4.9 s of a still body); the
    card's drop frames at 0 / 0.3 / 1 / 5 s are written; the body released a quarter of its height up is lower on
    screen at 0.3 s by over 2 % of the frame; the same states give the same bytes."""
    imageio = pytest.importorskip("imageio.v2")
    particles, _ = _bar((0.08, 0.06, 0.04), spacing_m=0.01)
    g, cov = _gaussians(particles, 0.005)
    x, F = _falling(particles, 0.25 * 0.04)
    files = drop_files(g, cov, particles, x, F, tmp_path / "a", 30.0, 5.0, 128, 72, renderer=_disc_renderer)
    assert set(files) == {f"drop_{v}.mp4" for v in VIEW_NAMES} | {card_still_name(v, t) for v in VIEW_NAMES
                                                                   for t in CARD_TIMES_S}
    reader = imageio.get_reader(files["drop_front.mp4"])
    try:
        assert reader.get_meta_data()["fps"] == 30.0
        times, slowed = clip_states(x, 30.0)
        assert reader.count_frames() == len(times) < 80
        assert reader.get_data(0).shape == (72, 128, 3)
    finally:
        reader.close()
    start, landed = (imageio.imread(files[card_still_name("side", t)]) for t in (0.0, 0.3))
    low = [np.nonzero(_red_mask(img))[0].max() for img in (start, landed)]  # lowest red row
    assert low[1] - low[0] > 0.02 * 72
    settled = 2  # the fall: 10 mm in 0.045 s, between states 1 and 2
    assert np.array_equal(times, np.concatenate([np.zeros(round(HOLD_BEFORE_S * 30)),
                                                 np.arange(settled * SLOW_MOTION + 1) / SLOW_MOTION,
                                                 np.arange(settled + 1, settled + 1 + round(HOLD_AFTER_S * 30))]))
    assert slowed.sum() == settled * SLOW_MOTION + 1
    again = drop_files(g, cov, particles, x, F, tmp_path / "b", 30.0, 5.0, 128, 72, renderer=_disc_renderer)
    assert all(files[k].read_bytes() == again[k].read_bytes() for k in files)


def test_a_state_with_exploded_particles_still_renders_the_rest() -> None:
    """An unhealthy rollout's last state (some particles NaN): the camera frames the finite ones, the frame shows
    what is left instead of failing the render."""
    particles, _ = _bar((0.06, 0.04, 0.03), spacing_m=0.01)
    g, cov = _gaussians(particles, 0.005)
    x, F = _falling(particles, 0.0075, n_states=2)
    x[1, :3] = np.nan
    frames = render_protocol_frames(g, cov, particles, x, F, "side", 96, 56, renderer=_disc_renderer)
    assert len(frames) == 2 and _red_mask(frames[1]).sum() > 0.5 * _red_mask(frames[0]).sum()


@pytest.mark.slow  # ~10 s on 2 busy cores: 1280 x 720 frames through the splatting renderer and H.264
def test_full_size_drop_videos_are_1280x720_at_30_fps(tmp_path: Path) -> None:
    imageio = pytest.importorskip("imageio.v2")
    particles, _ = _bar((0.12, 0.08, 0.05), spacing_m=0.01)
    g, cov = _gaussians(particles, 0.006)
    x, F = _falling(particles, 0.25 * 0.05)
    files = drop_files(g, cov, particles, x, F, tmp_path, 30.0, 5.0)
    for view in VIEW_NAMES:
        reader = imageio.get_reader(files[f"drop_{view}.mp4"])
        try:
            assert reader.get_meta_data()["fps"] == 30.0 and reader.count_frames() == len(clip_states(x, 30.0)[0])
            assert reader.get_data(0).shape == (720, 1280, 3)
        finally:
            reader.close()
        assert files[f"drop_{view}.mp4"].stat().st_size < 3e6


def test_the_video_reuses_the_card_frames_pictures_and_writes_the_same_files(tmp_path: Path,
                                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    """drop_files draws the card's drop frames first and the video's frames of the same recorded states hand their
    pictures back instead of drawing them again: fewer pictures drawn, the same bytes in every file."""
    import tasks.render.protocol_video as pv

    particles, _ = _bar((0.08, 0.06, 0.04), spacing_m=0.01)
    g, cov = _gaussians(particles, 0.005)
    x, F = _falling(particles, 0.25 * 0.04)
    calls: list[int] = []

    def counting(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls.append(1)
        return _disc_renderer(*args, **kwargs)

    files = drop_files(g, cov, particles, x, F, tmp_path / "a", 30.0, 5.0, 128, 72, renderer=counting)
    reusing = len(calls)

    class Drawing(pv.KeptPictures):  # keeps nothing: every picture drawn
        def __call__(self, cam, *args, **kwargs):  # type: ignore[no-untyped-def]
            self.kept.clear()
            return super().__call__(cam, *args, **kwargs)

    monkeypatch.setattr(pv, "KeptPictures", Drawing)
    calls.clear()
    again = drop_files(g, cov, particles, x, F, tmp_path / "b", 30.0, 5.0, 128, 72, renderer=counting)
    assert reusing < len(calls)
    assert all(files[k].read_bytes() == again[k].read_bytes() for k in files)
