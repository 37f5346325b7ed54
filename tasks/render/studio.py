"""The studio the splats stand in: a neutral backdrop, a table plane at z = 0 lit by a soft spot round the camera's
target, and a soft shadow under the object (the Gaussians' opacity splatted onto the table from above, blurred).

Colours are display RGB in 0..1. The shadow map is a darkening in 0..1 on a square grid of the table (world x, y);
the render kernel (tasks.render.splat_kernels.render_pixels) samples it bilinearly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter

FLAT_RGB = (0.93, 0.93, 0.93)  # scene="none"
TABLE_RGB = (0.87, 0.85, 0.81)  # warm light grey, in the middle of the spot
SPOT_FALLOFF = 0.2  # the table this much darker at the spot's rim, where it fades into the horizon colour
HORIZON_RGB = (0.70, 0.69, 0.67)  # the table far off and the foot of the backdrop (as dark as the spot's rim)
TOP_RGB = (0.82, 0.83, 0.85)  # the backdrop high up (a lit wall, a little cooler)
SHADOW_STRENGTH = 0.5  # darkening under a fully opaque column
SHADOW_BLUR_PER_M = 0.5  # the penumbra widens by this much per metre of clearance between object and table
SHADOW_MAX_GAUSSIANS = 65536  # a larger set casts its shadow through an even subsample (weights scaled)
SHADOW_CELLS = 96  # shadow-map cells along its longer side
SHADOW_FADE_M = 0.4  # a Gaussian this high above the table casts 1/e of the shadow it casts at rest on it


@dataclass(frozen=True)
class ShadowMap:
    """Darkening (ny, nx) in 0..1 on the table, its lower-left corner (x, y) [m] and cell size [m]."""

    darkening: np.ndarray
    origin_m: tuple[float, float]
    cell_m: float


def no_shadow() -> ShadowMap:
    """An empty 2 x 2 map (nothing darkened)."""
    return ShadowMap(np.zeros((2, 2), np.float32), (0.0, 0.0), 1.0)


def shadow_map(means_m: np.ndarray, covariances_m2: np.ndarray, opacities: np.ndarray) -> ShadowMap:
    """The object's soft shadow from a light straight above: each Gaussian's integrated alpha (o 2π sqrt(det Σ_xy)),
    fading with its height, binned on the table, blurred by a tenth of the footprint plus half the clearance (and
    the Gaussians' median spread), darkening = strength (1 - exp(-optical depth))."""
    stride = -(-len(means_m) // SHADOW_MAX_GAUSSIANS)
    means_m, covariances_m2, opacities = means_m[::stride], covariances_m2[::stride], opacities[::stride] * stride
    above = means_m[:, 2] > -0.01
    if not np.any(above):
        return no_shadow()
    xy = means_m[above, :2]
    cov = covariances_m2[above]
    sigma_xy = np.sqrt(np.clip(np.stack([cov[:, 0, 0], cov[:, 1, 1]], axis=1), 0.0, None))
    lo, hi = (xy - 3.0 * sigma_xy).min(axis=0), (xy + 3.0 * sigma_xy).max(axis=0)
    extent = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-3))
    # the penumbra (a tenth of the footprint, widening as the object rises) and the Gaussians' own spread, in one
    # blur of the binned centres
    clearance = max(0.0, float(np.min(means_m[above, 2] - 2.0 * np.sqrt(np.clip(cov[:, 2, 2], 0.0, None)))))
    blur_m = float(np.hypot(0.1 * extent + SHADOW_BLUR_PER_M * clearance, np.median(sigma_xy)))
    margin = 4.0 * blur_m
    cell = (extent + 2.0 * margin) / SHADOW_CELLS
    origin = 0.5 * (lo + hi) - 0.5 * SHADOW_CELLS * cell
    det_xy = np.clip(cov[:, 0, 0] * cov[:, 1, 1] - cov[:, 0, 1] ** 2, 0.0, None)
    height = np.clip(means_m[above, 2], 0.0, None)
    weight = opacities[above] * 2.0 * np.pi * np.sqrt(det_xy) * np.exp(-height / SHADOW_FADE_M) / cell**2
    ij = np.floor((xy - origin) / cell).astype(np.int64)
    inside = np.all((ij >= 0) & (ij < SHADOW_CELLS), axis=1)
    flat = ij[inside, 1] * SHADOW_CELLS + ij[inside, 0]
    depth = np.bincount(flat, weights=weight[inside], minlength=SHADOW_CELLS**2).reshape(SHADOW_CELLS, SHADOW_CELLS)
    depth = gaussian_filter(depth, blur_m / cell, mode="constant")
    dark = SHADOW_STRENGTH * (1.0 - np.exp(-depth))
    return ShadowMap(dark.astype(np.float32), (float(origin[0]), float(origin[1])), float(cell))
