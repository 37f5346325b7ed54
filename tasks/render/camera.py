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
