"""Image measures of the rendered videos: how sharp the object is (variance of the Laplacian over its pixels).

    from tasks.render.quality import object_mask, sharpness

    mask = coverage_mask(cam, means_m, covariances_m2, opacities)  # pixels the Gaussians cover (not their shadow)
    s = sharpness(frame, mask)               # variance of the 3 x 3 Laplacian of the grey image over the mask

The Laplacian is the 4-neighbour one (0 1 0 / 1 -4 1 / 0 1 0) of the grey level (ITU-R 601 weights, 0..255); a
blurred picture has a small variance of it, a picture with edges and texture a large one (Pech-Pacheco et al.
2000). Numpy only.
"""

from __future__ import annotations

import numpy as np

from tasks.render.camera import Camera
from tasks.render.splats import FLAT_RGB, render_gaussians

GREY = np.array([0.299, 0.587, 0.114])
MASK_LEVELS = 6.0  # a pixel belongs to the object where it differs from the background by more than this (0..255)


def grey(image: np.ndarray) -> np.ndarray:
    """Grey levels (H, W) float64 of an RGB uint8 image."""
    return np.asarray(image, np.float64)[..., :3] @ GREY


def laplacian(image: np.ndarray) -> np.ndarray:
    """4-neighbour Laplacian (H, W) of the grey image, edges replicated."""
    g = np.pad(grey(image), 1, mode="edge")
    return g[:-2, 1:-1] + g[2:, 1:-1] + g[1:-1, :-2] + g[1:-1, 2:] - 4.0 * g[1:-1, 1:-1]


def object_mask(image: np.ndarray, background: np.ndarray, levels: float = MASK_LEVELS) -> np.ndarray:
    """Pixels (H, W) bool where the image differs from the background (the same view without the object)."""
    diff = np.abs(np.asarray(image, np.float64) - np.asarray(background, np.float64)).max(axis=-1)
    return diff > levels


def coverage_mask(cam: Camera, means_m: np.ndarray, covariances_m2: np.ndarray, opacities: np.ndarray,
                  min_alpha: float = 0.5) -> np.ndarray:
    """Pixels (H, W) bool that the Gaussians cover with at least min_alpha (black splats over the flat scene: the
    object without its shadow or the table)."""
    n = len(means_m)
    img = render_gaussians(cam, means_m, covariances_m2, np.zeros((n, 3)), opacities, scene="none")
    return grey(img) < (1.0 - min_alpha) * 255.0 * float(np.mean(FLAT_RGB))


def sharpness(image: np.ndarray, mask: np.ndarray) -> float:
    """Variance of the Laplacian of the grey image over the masked pixels (0 for an empty mask)."""
    values = laplacian(image)[np.asarray(mask, bool)]
    return float(values.var()) if len(values) else 0.0
