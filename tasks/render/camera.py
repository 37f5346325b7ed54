"""The pinhole Camera shared by the renderers: eye and target [m], vertical field of view, image size."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Camera:
    """Pinhole camera: eye and target [m], vertical field of view [deg], image size [px]."""

    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_deg: float = 40.0
    width: int = 320
    height: int = 240

    def frame(self) -> tuple[np.ndarray, np.ndarray, float]:
        """World -> camera rotation (rows: right, down, forward), eye [m], focal length [px]."""
        eye, tgt = np.asarray(self.eye, float), np.asarray(self.target, float)
        fwd = (tgt - eye) / np.linalg.norm(tgt - eye)
        right = np.cross(fwd, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        down = np.cross(fwd, right)
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
    """Pixel coordinates (u, v) (pixel centres at i + 0.5) and camera depth [m] of world points."""
    rot, eye, f = cam.frame()
    c = (np.asarray(points_m, np.float64).reshape(-1, 3) - eye) @ rot.T
    z = np.where(c[:, 2] > 1e-9, c[:, 2], 1e-9)
    return f * c[:, 0] / z + 0.5 * cam.width, f * c[:, 1] / z + 0.5 * cam.height, c[:, 2]
