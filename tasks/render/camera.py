"""The one camera model of the renderers: eye and target [m], an up hint, vertical field of view (pinhole) or frame
height (orthographic), image size. Every image and video the project makes is drawn through a Camera: the videos'
perspective views and L0's orthographic reference views (tasks.render.views) alike."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Camera:
    """A camera at eye looking at target [m], image size [px]; right = forward x up (up: a hint, not necessarily
    orthogonal to the view; the default +z keeps the horizon level, a camera looking straight down needs another).
    Pinhole (vertical field of view fov_deg) unless ortho_height_m is given: then orthographic, the frame's height in
    metres (fov_deg unused). The perspective renderers (splats, discs, the mesh rasteriser) draw pinhole cameras;
    project() maps points through either."""

    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_deg: float = 40.0
    width: int = 320
    height: int = 240
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    ortho_height_m: float | None = None

    def frame(self) -> tuple[np.ndarray, np.ndarray, float]:
        """World -> camera rotation (rows: right, down, forward), eye [m], focal length [px] (orthographic: pixels per
        metre)."""
        eye, tgt = np.asarray(self.eye, float), np.asarray(self.target, float)
        fwd = (tgt - eye) / np.linalg.norm(tgt - eye)
        right = np.cross(fwd, np.asarray(self.up, float))
        right /= np.linalg.norm(right)
        down = np.cross(fwd, right)
        if self.ortho_height_m is not None:
            return np.stack([right, down, fwd]), eye, float(self.height / self.ortho_height_m)
        f = 0.5 * self.height / np.tan(np.radians(self.fov_deg) / 2.0)
        return np.stack([right, down, fwd]), eye, float(f)


def fit_camera(points_m: np.ndarray, toward_eye: np.ndarray, fov_deg: float, width: int, height: int,
               fill: float = 0.9) -> Camera:
    """A camera looking along -toward_eye at the centre of the points' bounding box, as close as lets every point
    (every corner of the box) lie within fill of the frame's half-width and half-height under perspective."""
    pts = np.asarray(points_m, np.float64).reshape(-1, 3)
    pts = pts[np.isfinite(pts).all(axis=1)]
    pts = pts if len(pts) else np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = 0.5 * (lo + hi)
    back = np.asarray(toward_eye, np.float64) / np.linalg.norm(toward_eye)
    rot, _, _ = Camera(tuple(centre + back), tuple(centre), fov_deg, width, height).frame()
    tan_v = np.tan(np.radians(fov_deg) / 2.0) * fill
    tan_h = tan_v * width / height
    c = (pts - centre) @ rot.T  # (right, down, forward) offsets from the target
    # a point at depth D + c_f is inside when |c_r| <= tan_h (D + c_f) and |c_d| <= tan_v (D + c_f)
    distance = float(max(np.max(np.abs(c[:, 0]) / tan_h - c[:, 2]), np.max(np.abs(c[:, 1]) / tan_v - c[:, 2])))
    distance = max(distance, 1e-3 + float(np.max(-c[:, 2])))
    return Camera(tuple(centre + distance * back), tuple(centre), fov_deg, width, height)


def project(cam: Camera, points_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixel coordinates (u, v) (pixel centres at i + 0.5) and camera depth [m] of world points (orthographic: u, v
    linear in the camera-space right and down offsets; depth along the view, negative behind the eye)."""
    rot, eye, f = cam.frame()
    c = (np.asarray(points_m, np.float64).reshape(-1, 3) - eye) @ rot.T
    if cam.ortho_height_m is not None:
        return f * c[:, 0] + 0.5 * cam.width, f * c[:, 1] + 0.5 * cam.height, c[:, 2]
    z = np.where(c[:, 2] > 1e-9, c[:, 2], 1e-9)
    return f * c[:, 0] / z + 0.5 * cam.width, f * c[:, 1] / z + 0.5 * cam.height, c[:, 2]
