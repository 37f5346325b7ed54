"""The pick-and-place video's picture: a wide view that holds the whole robot, the object drawn by the Gaussian
splatting renderer (tasks.render.splats) over the robot and the room, and a close-up inset of the fingers.

    frame = compose(cam, room_rgb, room_depth, gaussians)            # splats over a picture with its depth buffer
    frame = paste_inset(frame, compose(inset_cam, ...), "fingers")   # the close-up in the lower right corner

The robot and the room are triangles and ray-cast planes drawn by the caller (tasks.render.mesh_raster); what lies in
front of a Gaussian (a finger, the table) hides it, per pixel, through the depth buffer. Deterministic on the CPU.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tasks.render.camera import Camera, fit_camera, project
from tasks.render.captions import caption
from tasks.render.shading import lit_colors
from tasks.render.splats import render_gaussians

WIDE_FOV_DEG = 40.0
WIDE_FILL = 0.88  # the robot's and the object's points within this fraction of the half-frame
INSET_FRACTION = 0.36  # the inset's width, of the frame's
INSET_MARGIN_PX = 16  # from the frame's lower right corner (720 lines)
INSET_BORDER_PX = 3
INSET_FOV_DEG = 30.0
INSET_RADIUS = 1.3  # the inset frames a sphere this many times the grasp's half-size round the pads' midpoint
SPLAT_TILE_PX = 8  # the object's Gaussians crowd a few tiles of the wide view: 8-pixel tiles (the same picture) cut
# each pixel's list and the time of both views by a fifth against the default 16 (the drop videos keep 16)
BORDER_RGB = (40, 40, 46)


@dataclass(frozen=True)
class SplatSet:
    """Gaussians to draw: centres [m] (G, 3), covariances [m^2] (G, 3, 3), albedo (G, 3) in 0..1, opacities (G,)
    and unit normals (G, 3) for the light."""

    means_m: np.ndarray
    covariances_m2: np.ndarray
    albedo: np.ndarray
    opacities: np.ndarray
    normals: np.ndarray


def wide_camera(points_m: np.ndarray, toward_eye: np.ndarray, width: int, height: int) -> Camera:
    """The fixed wide camera: every given point (the robot's links over the whole attempt, the object, the place
    target) inside the frame."""
    return fit_camera(points_m, toward_eye, WIDE_FOV_DEG, width, height, WIDE_FILL)


def inset_size(width: int, height: int) -> tuple[int, int]:
    """The inset's size [px] (16:9 like the frame, even)."""
    w = int(round(INSET_FRACTION * width / 2.0)) * 2
    return w, int(round(w * height / width / 2.0)) * 2


def inset_camera(centre_m: np.ndarray, radius_m: float, toward_eye: np.ndarray, width: int, height: int) -> Camera:
    """A camera looking at centre_m from along toward_eye that frames a sphere of INSET_RADIUS x radius_m."""
    back = np.asarray(toward_eye, np.float64) / np.linalg.norm(toward_eye)
    distance = INSET_RADIUS * radius_m / np.sin(np.radians(0.5 * INSET_FOV_DEG))
    c = np.asarray(centre_m, np.float64)
    return Camera(tuple(c + distance * back), tuple(c), INSET_FOV_DEG, width, height)


def compose(cam: Camera, rgb: np.ndarray, depth: np.ndarray, splats: SplatSet | None, device: str = "cpu"
            ) -> np.ndarray:
    """The Gaussians, lit, splatted (on `device`) over a picture (H, W, 3) uint8 with its camera depth (H, W) [m]."""
    if splats is None or not len(splats.means_m):
        return np.ascontiguousarray(rgb)
    colours = lit_colors(splats.albedo, splats.normals, cam)
    return render_gaussians(cam, splats.means_m, splats.covariances_m2, colours, splats.opacities,
                            background=(rgb, depth), device=device, tile_px=SPLAT_TILE_PX)


CORNERS = ("bottom_right", "top_right", "bottom_left")  # the caption holds the top left


def inset_rect(height: int, width: int, inset_hw: tuple[int, int], corner: str) -> tuple[int, int, int, int]:
    """The inset's pixel rectangle (y0, x0, y1, x1) in a frame of height x width, in a corner, INSET_MARGIN_PX in
    (scaled with the height) and below its title strip when at the top."""
    scale = height / 720.0
    margin = int(round(INSET_MARGIN_PX * scale))
    ih, iw = inset_hw
    title = int(30 * scale) + max(1, int(round(INSET_BORDER_PX * scale)))
    y0 = margin + title if corner.startswith("top") else height - margin - ih
    x0 = width - margin - iw if corner.endswith("right") else margin
    return y0, x0, y0 + ih, x0 + iw


def choose_corner(cam: Camera, inset_hw: tuple[int, int], points_m: np.ndarray, weights: np.ndarray) -> str:
    """The corner whose inset hides the least of the given points (weighted: the object and the fingers count
    more than the arm); the first of CORNERS on a tie."""
    u, v, z = project(cam, points_m)
    w = np.where(z > 0, np.asarray(weights, np.float64), 0.0)
    hidden = []
    for corner in CORNERS:
        y0, x0, y1, x1 = inset_rect(cam.height, cam.width, inset_hw, corner)
        pad = 30.0 * cam.height / 720.0  # the title strip and a little room round the inset
        inside = (u >= x0 - pad) & (u <= x1 + pad) & (v >= y0 - pad) & (v <= y1 + pad)
        hidden.append(float(w[inside].sum()))
    return CORNERS[int(np.argmin(hidden))]


def paste_inset(frame: np.ndarray, inset: np.ndarray, title: str = "", corner: str = "bottom_right") -> np.ndarray:
    """The inset in a corner of the frame (inset_rect) with a dark border and a title strip over it; a copy."""
    out = np.ascontiguousarray(frame).copy()
    h = frame.shape[0]
    scale = h / 720.0
    border = max(1, int(round(INSET_BORDER_PX * scale)))
    y0, x0, y1, x1 = inset_rect(h, frame.shape[1], inset.shape[:2], corner)
    out[y0 - border:y1 + border, x0 - border:x1 + border] = BORDER_RGB
    out[y0:y1, x0:x1] = inset
    if title:
        tag = caption(np.full((int(30 * scale), x1 - x0, 3), 245, np.uint8), [title], (8, 21), scale)
        out[y0 - border - tag.shape[0]:y0 - border, x0:x1] = tag
    return out


def points_in_frame(cam: Camera, points_m: np.ndarray, margin_px: float = 0.0) -> np.ndarray:
    """Whether each world point projects inside the frame (and in front of the camera)."""
    u, v, z = project(cam, points_m)
    return (z > 0) & (u >= margin_px) & (u <= cam.width - margin_px) & (v >= margin_px) & \
        (v <= cam.height - margin_px)
