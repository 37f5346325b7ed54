"""The pick-and-place video (#36): the whole robot in the frame, the object drawn by the Gaussian splatting renderer
(the same one as the drop videos), the 2F-85 / 2F-140 drawn link by link with their pads on the recorded pads, and a
close-up inset of the fingers."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import tasks.render.attempt_video as attempt_video
from contracts.robot import load_gripper
from tasks.manipulation.scene import attempt_timeline
from tasks.manipulation.video import PickPlaceVideo
from tasks.render.attempt_video import inset_rect, inset_size, points_in_frame
from tasks.render.camera import project
from tasks.render.gripper_model import SILICONE, gripper_parts_local, knuckle_angle, robotiq_links
from tasks.render.splats import render_gaussians
from tasks.robot import PHASES
from tests.l3.render_helpers import synthetic_attempt

W, H = 640, 360


@pytest.fixture(scope="module", params=["robotiq_2f140", None])
def video(request: pytest.FixtureRequest) -> PickPlaceVideo:
    """A whole attempt (approach to settle) on a 6 cm cube: the 2F-140, and the Franka Hand (no gripper named)."""
    arrays, attrs = synthetic_attempt(edge_m=0.06, spacing_m=0.006, gripper=request.param, approach_s=0.4)
    return PickPlaceVideo(arrays, attrs, W, H)


def _frame_in(arrays: dict[str, np.ndarray], phase: str, where: float = 0.5) -> int:
    tl = attempt_timeline(arrays)
    idx = [i for i, f in enumerate(tl) if f.control_index >= 0 and PHASES[arrays["phase"][f.control_index]] == phase]
    return idx[int(where * (len(idx) - 1))]


def test_the_whole_robot_is_in_the_frame_at_every_moment(video: PickPlaceVideo) -> None:
    """Every 4th video frame (and the last): each projected point of every link and of the gripper lies inside the
    wide frame, with the base and the top of the arm among them."""
    n = len(video)
    for i in sorted({*range(0, n, 4), n - 1}):
        pts = video.robot_points(i)
        assert len(pts) > 1000
        assert points_in_frame(video.cam, pts).all(), i
    base = video.robot_points(0)
    assert base[:, 2].min() < 0.1 and base[:, 2].max() > 0.5  # the base at the table and the arm high above it


def test_the_object_is_drawn_by_the_splatting_renderer(video: PickPlaceVideo, monkeypatch: pytest.MonkeyPatch
                                                       ) -> None:
    """A frame during the lift: the object's Gaussians go through tasks.render.splats.render_gaussians twice (the
    wide view and the close-up), over the robot's picture and its depth buffer, and change the pixels where they
    project."""
    calls: list[dict[str, Any]] = []

    def spy(cam: Any, means: np.ndarray, covs: np.ndarray, colours: np.ndarray, opac: np.ndarray,
            **kw: Any) -> np.ndarray:
        image = render_gaussians(cam, means, covs, colours, opac, **kw)
        calls.append({"cam": cam, "n": len(means), "background": kw.get("background"), "image": image})
        return image

    monkeypatch.setattr(attempt_video, "render_gaussians", spy)
    k = _frame_in(video.arrays, "lift")
    frame = video.frame(k)
    assert frame.shape == (H, W, 3)
    n = len(video.arrays["gaussian_positions_m"])
    assert [c["n"] for c in calls] == [n, n]
    assert calls[0]["cam"] == video.cam and calls[1]["cam"] == video.inset_camera(k)
    for c in calls:
        rgb, depth = c["background"]
        assert rgb.shape == (c["cam"].height, c["cam"].width, 3) and depth.shape == rgb.shape[:2]
        changed = np.abs(c["image"].astype(int) - rgb.astype(int)).max(axis=-1) > 20
        assert changed.sum() > (40 if c is calls[0] else 2000)  # the cube: small in the wide view, large close up
    iw, ih = inset_size(W, H)
    y0, x0, y1, x1 = inset_rect(H, W, (ih, iw), video.corner)
    assert np.array_equal(frame[y0:y1, x0:x1], calls[1]["image"])  # the close-up, pasted into its corner
    # ... where it hides none of the object's and the pads' path in the wide view
    u, v, _ = project(video.cam, np.asarray([f.pad_position_m for f in video.timeline]).reshape(-1, 3))
    assert not ((u >= x0) & (u <= x1) & (v >= y0) & (v <= y1)).any()


@pytest.mark.parametrize("name", ["robotiq_2f85", "robotiq_2f140"])
def test_the_robotiq_links_open_to_the_stroke_and_put_the_pads_where_the_trial_had_them(name: str) -> None:
    """Fully open, the four-bar linkage puts the pad faces the gripper's stroke apart; at any opening the silicone
    pads' inner faces are at +- half the opening and centred at the pads' depth; the knuckles close as the pads do."""
    links = robotiq_links(name)
    assert links is not None
    stroke = load_gripper(name).stroke_m
    open_alpha = np.radians(links.knuckle_open_deg)
    half_open = links.inner_pivot_m[0] + links.knuckle_m * np.sin(open_alpha) - links.finger_inset_m
    assert 2 * half_open == pytest.approx(stroke, abs=0.002)
    for half in (0.4 * stroke / 2, stroke / 2):
        parts = gripper_parts_local(links, half, 0.2)
        pads = [p for p in parts if np.array_equal(p.rgb, SILICONE)]
        assert len(pads) == 2
        inner = sorted(float(np.abs(p.vertices_m[:, 1]).min()) for p in pads)
        assert inner == pytest.approx([half, half], abs=1e-9)
        assert all(p.vertices_m[:, 2].mean() == pytest.approx(0.2, abs=1e-9) for p in pads)
    assert knuckle_angle(links, 0.2 * stroke / 2) < knuckle_angle(links, 0.8 * stroke / 2)


def test_the_2f140_is_drawn_from_its_links_not_boxes() -> None:
    """The 2F-140's parts: coupling, housing, and per finger knuckles, fingers, pad and pivot pins (many parts, not
    three boxes)."""
    arrays, attrs = synthetic_attempt(edge_m=0.06, spacing_m=0.006, gripper="robotiq_2f140", approach_s=0.2)
    v = PickPlaceVideo(arrays, attrs, W, H)
    assert v.links is not None and v.links.name == "robotiq_2f140"
    k = _frame_in(arrays, "closure", 0.9)
    n_links = len(v._robot_parts(k))
    assert n_links >= 8 + 4 + 2 * 10  # Panda links 0-7, coupling and housing, 2 x (3 links, finger, pad, 4 pins...)


def test_the_runs_device_reaches_both_renderers(monkeypatch: pytest.MonkeyPatch) -> None:
    """PickPlaceVideo(device="cuda") draws the robot's triangles (mesh_raster.draw) and the object's splats
    (render_gaussians) on that device, in the wide view and the close-up; here on the CPU, each spy drawing what it was
    asked on the CPU."""
    import tasks.render.mesh_raster as raster

    devices: list[tuple[str, str]] = []
    real_draw = raster.draw

    def draw(*args: Any, device: str = "cpu", **kw: Any) -> Any:
        devices.append(("triangles", device))
        return real_draw(*args, **kw)

    def splats(*args: Any, device: str = "cpu", **kw: Any) -> np.ndarray:
        devices.append(("splats", device))
        return render_gaussians(*args, **kw)

    monkeypatch.setattr(raster, "draw", draw)
    monkeypatch.setattr(attempt_video, "render_gaussians", splats)
    arrays, attrs = synthetic_attempt(edge_m=0.06, spacing_m=0.006, gripper="robotiq_2f85", approach_s=0.2)
    video = PickPlaceVideo(arrays, attrs, W, H, device="cuda")
    assert video.frame(_frame_in(arrays, "lift")).shape == (H, W, 3)
    assert devices == [("triangles", "cuda"), ("splats", "cuda")] * 2
    devices.clear()
    PickPlaceVideo(arrays, attrs, W, H).frame(0)
    assert {d for _, d in devices} == {"cpu"}
