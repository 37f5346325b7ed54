"""The one camera model: a pinhole Camera unchanged by the up hint and the orthographic mode, a camera that looks straight
down, and L0's front / side / top views drawn through it with the axes (and the pixels) they had before they moved
into tasks.render (#37 item 5)."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest
import trimesh

from tasks.render.camera import Camera, project
from tasks.render.views import VIEWS, render_view, view_axes, view_camera, write_renders

SPONGE = Path(__file__).parents[1] / "export" / "fixtures" / "sponge" / "mesh.glb"
# the views' (screen-right, screen-up, towards-viewer) axes of tasks/geometry/render.py before the move
OLD_AXES = {"front": ((0, 1, 0), (0, 0, 1), (1, 0, 0)), "side": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
            "top": ((1, 0, 0), (0, 1, 0), (0, 0, 1))}
# sha256 of render_view(sponge, view, 96) by tasks/geometry/render.py before the move
OLD_SPONGE_96 = {"front": "2b315cbb53c5d26262f4d30ffdc45b953c1e7afa3a4868dd269ecbc7aa24f27a",
                 "side": "d4116f58d8a6a04d85b8581744a369aff2fcecf2567f94f9d974447268062923",
                 "top": "7419512cc57fa14dbb519197130e9595fb06185813646c1dfd6150a282394d54"}


def test_the_default_up_and_no_ortho_keep_the_pinhole_arithmetic() -> None:
    """The pinhole frame and projection are those written out before the up hint and the orthographic mode."""
    cam = Camera((0.4, -0.9, 0.3), (0.02, 0.01, 0.05), 30.0, 160, 90)
    eye, tgt = np.asarray(cam.eye, float), np.asarray(cam.target, float)
    fwd = (tgt - eye) / np.linalg.norm(tgt - eye)
    right = np.cross(fwd, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    rot = np.stack([right, np.cross(fwd, right), fwd])
    f = 0.5 * cam.height / np.tan(np.radians(cam.fov_deg) / 2.0)
    got_rot, got_eye, got_f = cam.frame()
    assert np.array_equal(got_rot, rot) and np.array_equal(got_eye, eye) and got_f == f
    pts = np.random.default_rng(0).normal(0.0, 0.1, (50, 3))
    c = (pts - eye) @ rot.T
    u, v, z = project(cam, pts)
    assert np.array_equal(u, f * c[:, 0] / c[:, 2] + 80.0) and np.array_equal(v, f * c[:, 1] / c[:, 2] + 45.0)
    assert np.array_equal(z, c[:, 2])


def test_an_orthographic_camera_looking_straight_down_maps_offsets_linearly() -> None:
    """Looking down with +y up the image: +x goes right, +y goes up, 1 m is height / ortho_height_m pixels at any
    depth; the depth is along the view."""
    cam = Camera((0.0, 0.0, 2.0), (0.0, 0.0, 0.0), width=200, height=100, up=(0.0, 1.0, 0.0), ortho_height_m=0.5)
    u, v, z = project(cam, np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.1, 0.1, -3.0]]))
    assert u == pytest.approx([100.0, 120.0, 100.0, 120.0]) and v == pytest.approx([50.0, 50.0, 30.0, 30.0])
    assert z == pytest.approx([2.0, 2.0, 2.0, 5.0])


@pytest.mark.parametrize("view", list(OLD_AXES))
def test_each_view_has_the_axes_it_had(view: str) -> None:
    """Screen-right, screen-up and towards-viewer of each view's camera are the old table's (no mirrored image)."""
    for got, want in zip(view_axes(view), OLD_AXES[view]):
        assert np.array_equal(got, np.asarray(want, float))
    cam = view_camera(view, np.array([0.1, 0.2, 0.3]), 0.5, 64)
    assert cam.ortho_height_m == 0.5 and cam.width == cam.height == 64


def test_the_iso_view_shows_front_side_and_top_with_the_vertical_up() -> None:
    """The three-quarter view looks at the +x front, the -y side and the top at once, keeps the vertical on screen-up
    (no roll), and an x-long bar is drawn long: a pool noodle is not read end-on as a washer."""
    right, up, toward = view_axes("iso")
    assert toward[0] > 0.5 and toward[1] < -0.3 and 0.3 < toward[2] < 0.6  # front, side, ~26 deg above
    assert abs(right[2]) < 1e-12 and up[2] > 0.85  # the vertical is screen-up, the horizon level
    bar = trimesh.creation.box((1.0, 0.05, 0.05))
    img = render_view(bar, "iso", 96)
    pix = np.argwhere(img.min(axis=2) < 250).astype(float)
    spread = np.sqrt(np.linalg.eigvalsh(np.cov(pix.T)))
    assert spread[1] > 5 * spread[0] and spread[1] > 15  # drawn long (pixels along its axis), not a square end


def test_the_views_of_a_mesh_are_the_pixels_they_were(tmp_path: Path) -> None:
    """The sponge fixture's three views are byte for byte those of the renderer before the move; write_renders
    writes them as PNGs."""
    mesh = trimesh.load(SPONGE, force="mesh")
    for view, digest in OLD_SPONGE_96.items():
        img = render_view(mesh, view, 96)
        assert img.shape == (96, 96, 3) and img.dtype == np.uint8
        assert hashlib.sha256(np.ascontiguousarray(img).tobytes()).hexdigest() == digest, view
    assert write_renders(mesh, tmp_path, 32) == {v: f"{v}.png" for v in VIEWS}
    assert all((tmp_path / f"{v}.png").is_file() for v in VIEWS)
