"""The pick-and-place video: the arm and the gripper drawn at the recorded joint states above the object, a correct
depth test between robot, object and table, 1280 x 720 at 30 fps over the whole attempt (approach to settle)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tasks.manipulation.data import write_attempt
from tasks.manipulation.replay import replay
from tasks.manipulation.scene import VIDEO_FPS, AttemptRenderer, attempt_timeline
from tasks.render import mesh_raster as raster
from tasks.robot import PHASES
from tasks.robot.visual import HAND_LINKS, gripper_boxes, gripper_spec, tcp_frame
from tests.l3.render_helpers import synthetic_attempt

Attempt = tuple[dict[str, np.ndarray], dict[str, Any]]


@pytest.fixture(scope="module")
def attempt() -> Attempt:
    """A whole attempt (approach to settle) of the Franka Hand on a 3 cm cube at rest."""
    return synthetic_attempt()


def arm_coloured(rgb: np.ndarray) -> np.ndarray:
    """Pixels of the arm's colour: the Panda's white-grey, shaded (near-neutral, not dark)."""
    c = rgb.astype(int)
    return (c.min(axis=-1) >= 70) & (c.max(axis=-1) - c.min(axis=-1) <= 10)


def _frame_in(arrays: dict[str, np.ndarray], phase: str, where: float = 0.5) -> int:
    """Index of a video frame inside a phase (0: its start, 1: its end)."""
    tl = attempt_timeline(arrays)
    idx = [i for i, f in enumerate(tl) if f.control_index >= 0 and PHASES[arrays["phase"][f.control_index]] == phase]
    return idx[int(where * (len(idx) - 1))]


def test_a_frame_shows_the_arm_above_the_object(attempt: Attempt) -> None:
    arrays, attrs = attempt
    r = AttemptRenderer(arrays, attrs)
    rgb, labels = r.frame_with_labels(_frame_in(arrays, "closure"))
    assert rgb.shape == (720, 1280, 3)
    rows, cols = np.nonzero(labels == raster.OBJECT)
    assert len(rows) > 500  # the object is in view, not hidden behind the hand
    top, c0, c1 = rows.min(), cols.min(), cols.max()
    region = np.zeros(labels.shape, bool)
    region[max(0, top - 180):top, c0:c1 + 1] = True  # a quarter of the frame's height above the object
    arm = arm_coloured(rgb) & region
    assert arm.sum() > 0.3 * region.sum() and arm.sum() > 2000
    # ... and those pixels are the robot's, drawn by the rasteriser (not a grey backdrop)
    assert np.isin(labels[arm], [raster.ROBOT, raster.GRIPPER]).mean() > 0.98
    # elsewhere the backdrop never takes the arm's colour: the test cannot pass on the table, floor or wall
    bg = np.isin(r.backdrop.label, [raster.BACKGROUND, raster.TABLE])
    assert arm_coloured(r.backdrop.rgb)[bg].mean() < 0.001


def test_the_depth_test_orders_robot_object_and_table_whatever_the_drawing_order() -> None:
    """Camera at the origin looking along +z: a near triangle (z 0.5 m) hides a disc (0.6 m) that hides a far
    triangle (0.8 m); a triangle behind the backdrop (1.2 m, the table at 1.0 m) is not seen."""
    cam = (np.eye(3), np.zeros(3), 100.0)
    w, h = 64, 48
    bg_rgb, bg_depth = np.full((h, w, 3), 10, np.uint8), np.full((h, w), 1.0, np.float32)
    bg_label = np.full((h, w), raster.TABLE, np.uint8)

    def square(z: float, rgb: tuple[float, float, float], label: int, half: float = 0.15) -> raster.Mesh:
        s = half * z  # the same screen size at any depth
        v = np.array([[-s, -s, z], [s, -s, z], [s, s, z], [-s, s, z]])
        f = np.array([[0, 2, 1], [0, 3, 2]])  # counter-clockwise as seen from the camera (y down on screen)
        return raster.Mesh(v, f, np.tile(rgb, (4, 1)), label)

    near, far = square(0.5, (1, 0, 0), raster.GRIPPER, 0.1), square(0.8, (0, 0, 1), raster.ROBOT, 0.2)
    hidden = square(1.2, (0, 1, 0), raster.ROBOT, 0.45)
    # screen half widths: near 10 px, far 20 px, hidden 45 px; the disc: centre 15 px right of the middle, radius 7 px
    disc = raster.Discs(np.array([[0.09, 0.0, 0.6]]), np.array([0.04]), np.array([[0, 1, 0]]), raster.OBJECT, 12)
    a_rgb, a_lab = raster.draw(cam, w, h, bg_rgb, bg_depth, bg_label, [near, far, hidden], disc)
    b_rgb, b_lab = raster.draw(cam, w, h, bg_rgb, bg_depth, bg_label, [hidden, far, near], disc)
    assert np.array_equal(a_rgb, b_rgb) and np.array_equal(a_lab, b_lab)
    assert a_lab[24, 32] == raster.GRIPPER and tuple(a_rgb[24, 32]) == (255, 0, 0)  # the near one in the middle
    assert a_lab[24, 41] == raster.GRIPPER  # where the disc is behind the near square
    assert a_lab[24, 47] == raster.OBJECT  # the disc in front of the far square
    assert a_lab[24, 17] == raster.ROBOT and tuple(a_rgb[24, 17]) == (0, 0, 255)  # the far square
    assert a_lab[2, 2] == raster.TABLE  # the square behind the table is hidden everywhere
    assert not (a_lab == raster.ROBOT)[:, np.abs(np.arange(w) - 32) > 22].any()


def test_the_video_is_720p_at_30_fps_over_the_attempt(tmp_path: Path) -> None:
    """Replay writes an H.264 MP4 of 1280 x 720 at 30 fps whose frames span the stored attempt, from its recorded
    approach to its last simulated frame (a short attempt: 0.1 s of approach and 0.1 s simulated)."""
    import imageio.v2 as imageio

    arrays, attrs = synthetic_attempt(approach_s=0.1, end_s=None, spacing_m=0.006)
    t0 = float(arrays["frame_t_s"][0])
    keep = arrays["frame_t_s"] <= t0 + 0.1 + 1e-9
    short = dict(arrays, frame_t_s=arrays["frame_t_s"][keep], frame_control_index=arrays["frame_control_index"][keep],
                 particles_x_m=arrays["particles_x_m"][keep], particles_F=arrays["particles_F"][keep])
    write_attempt(tmp_path / "asset", short, attrs)
    out = replay(tmp_path / "asset", 0, video=tmp_path / "v.mp4")
    reader = imageio.get_reader(tmp_path / "v.mp4")
    meta = reader.get_meta_data()
    frames = [f for f in reader]
    reader.close()
    assert tuple(meta["size"]) == (1280, 720) and meta["fps"] == pytest.approx(30.0) and meta["codec"] == "h264"
    assert len(frames) == out.n_frames == len(attempt_timeline(short)) and frames[0].shape == (720, 1280, 3)
    span = float(short["frame_t_s"][-1] - short["approach_t_s"][0])
    assert span - 1e-9 <= (len(frames) - 1) / VIDEO_FPS < span + 1.0 / VIDEO_FPS
    assert out.duration_s == pytest.approx(len(frames) / 30.0)


def test_the_timeline_runs_from_the_approach_to_the_end_at_30_fps(attempt: Attempt) -> None:
    arrays, _ = attempt
    tl = attempt_timeline(arrays)
    t = np.array([f.t_s for f in tl])
    assert t[0] == 0.0 and np.allclose(np.diff(t), 1.0 / 30.0)
    assert arrays["frame_t_s"][-1] - 1e-9 <= t[-1] < arrays["frame_t_s"][-1] + 1.0 / 30.0
    seen = {"approach" if f.control_index < 0 else PHASES[arrays["phase"][f.control_index]] for f in tl}
    assert seen == set(PHASES)  # approach, closure, lift, transport, release, retreat, settle
    # the robot moves through the approach (joint states from the recorded approach, not frozen)
    approach = np.array([f.q_rad for f in tl if f.control_index < 0])
    assert len(approach) > 10 and np.ptp(approach, axis=0).max() > 0.1


def test_a_gripper_without_a_urdf_mesh_is_drawn_as_boxes_around_its_pads() -> None:
    """The 2F-85 class gripper: no Franka hand or finger meshes, its fingers' inner faces on the recorded pad faces
    and the body between the flange and the fingers; its pixels next to the object during the closure."""
    arrays, attrs = synthetic_attempt(edge_m=0.07, spacing_m=0.007, gripper="robotiq_2f85", approach_s=0.2)
    spec = gripper_spec(attrs["plan"])
    assert spec is not None and not spec.urdf_hand
    k = _frame_in(arrays, "closure", 0.9)
    fr = attempt_timeline(arrays)[k]
    half = arrays["finger_half_extents_m"]
    approach = np.array([0.0, 0.0, -1.0])
    origin, rot, opening = tcp_frame(fr.pad_position_m, half, approach)
    boxes = gripper_boxes(fr.pad_position_m, half, approach, spec)
    assert len(boxes) == 3
    for (c, _r, hb, _), sign in zip(boxes[1:], (1.0, -1.0)):
        inner = (rot.T @ (c - origin))[1] - sign * hb[1]  # TCP y of the finger's inner face
        assert inner == pytest.approx(sign * opening / 2, abs=1e-9)
    body = rot.T @ (boxes[0][0] - origin)
    assert body[2] < -0.05  # above the pads, towards the flange
    r = AttemptRenderer(arrays, attrs, 640, 360)
    rgb, labels = r.frame_with_labels(k)
    assert (labels == raster.GRIPPER).sum() > 500 and (labels == raster.ROBOT).sum() > 2000
    from tasks.robot.visual import robot_meshes

    parts = robot_meshes(r.poses[k], fr.pad_position_m, half, spec, np.array([1.0, 0.0, 0.0]))
    assert sum(p[3] for p in parts) == 3 and len(parts) == 3 + 8  # three gripper boxes and links 0-7, no hand
    franka = robot_meshes(r.poses[k], fr.pad_position_m, half, None, np.array([1.0, 0.0, 0.0]))
    assert len(franka) == 8 + len(HAND_LINKS)  # the URDF's hand and fingers when the gripper is the Franka Hand


def test_frames_are_deterministic(attempt: Attempt) -> None:
    arrays, attrs = attempt
    i = _frame_in(arrays, "lift")
    a = AttemptRenderer(arrays, attrs, 320, 180).frame(i)
    b = AttemptRenderer(arrays, attrs, 320, 180).frame(i)
    assert np.array_equal(a, b)
