"""Render the drop protocol from two views (front, side) at 30 fps into MP4 files, from recorded particle states."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tasks.geometry.gaussians import deform_gaussians
from tasks.manipulation.render import Camera, render

VIEWS: dict[str, np.ndarray] = {"front": np.array([0.0, -1.0, 0.35]), "side": np.array([1.0, 0.0, 0.35])}


def view_camera(points_m: np.ndarray, direction: np.ndarray, width: int, height: int) -> Camera:
    """A fixed camera looking at the points' centre from a direction, far enough to frame them all."""
    lo, hi = points_m.min(axis=0), points_m.max(axis=0)
    centre = 0.5 * (lo + hi)
    radius = max(0.03, 0.5 * float(np.linalg.norm(hi - lo)))
    d = direction / np.linalg.norm(direction)
    distance = 1.3 * radius / np.tan(np.radians(20.0))
    return Camera(tuple(centre + distance * d), tuple(centre), 40.0, width, height)


def render_protocol_frames(gaussians: dict[str, np.ndarray], rest_covariances_m2: np.ndarray, rest_particles_m: np.ndarray,
                           x_frames: np.ndarray, F_frames: np.ndarray, view: str, width: int = 320,
                           height: int = 240) -> list[np.ndarray]:
    """RGB frames (H, W, 3) uint8 of the deformed Gaussians from one view (the camera frames the whole motion)."""
    pts = np.concatenate([x_frames[0], x_frames[-1], rest_particles_m * [1, 1, 0]])
    cam = view_camera(np.asarray(pts, np.float64), VIEWS[view], width, height)
    frames = []
    for x, F in zip(x_frames, F_frames):
        centres, cov = deform_gaussians(gaussians["positions_m"], rest_covariances_m2, gaussians["particle_index"],
                                        gaussians["particle_weight"], rest_particles_m, x, F)
        frames.append(render(cam, centres, cov, gaussians["colors"]))
    return frames


def write_mp4(frames: list[np.ndarray], path: Path, fps: float) -> Path:
    """Encode frames as H.264 MP4 (imageio-ffmpeg) at fps."""
    import imageio.v2 as imageio

    path.parent.mkdir(parents=True, exist_ok=True)
    with imageio.get_writer(path, fps=fps, codec="libx264", macro_block_size=8, quality=7) as writer:
        for frame in frames:
            writer.append_data(frame)  # type: ignore[attr-defined]  # typed as imageio's base reader/writer
    return path
