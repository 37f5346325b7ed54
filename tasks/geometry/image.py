"""Single image -> object mask (alpha, or GrabCut seeded from the border) -> inflated watertight mesh with image colours."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import trimesh
from scipy import ndimage

from contracts.errors import InputError
from tasks.geometry.meshing import mesh_from_field

SEG_MAX_SIDE = 400  # segmentation works on an image at most this large [px]
MIN_AREA_FRAC = 0.004
MAX_AREA_FRAC = 0.95


def load_image(path: Path) -> np.ndarray:
    """RGB or RGBA uint8 array of a PNG/JPEG (clear error when missing or unreadable)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"image file not found: {path}")
    raw = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if raw is None or raw.size == 0:
        raise InputError(f"cannot read image {path.name}: not a valid PNG/JPEG")
    if raw.dtype == np.uint16:
        raw = (raw / 257).astype(np.uint8)
    if raw.ndim == 2:
        raw = cv2.cvtColor(raw, cv2.COLOR_GRAY2BGR)
    if raw.shape[2] == 4:
        return cv2.cvtColor(raw, cv2.COLOR_BGRA2RGBA)
    return cv2.cvtColor(raw[:, :, :3], cv2.COLOR_BGR2RGB)


def segment(image: np.ndarray, seed: int = 0) -> tuple[np.ndarray, str]:
    """Foreground mask (H, W) bool and the method used ('alpha' or 'grabcut')."""
    h, w = image.shape[:2]
    if image.shape[2] == 4:
        alpha = image[:, :, 3]
        if alpha.min() < 250:
            mask = alpha >= 128
            return _clean(mask, "alpha"), "alpha"
    rgb = np.ascontiguousarray(image[:, :, :3])
    if float(rgb.astype(np.float32).std(axis=(0, 1)).max()) < 3.0:
        raise InputError("no object found: the image is blank (one uniform colour)")
    scale = min(1.0, SEG_MAX_SIDE / max(h, w))
    small = cv2.resize(rgb, (max(8, int(w * scale)), max(8, int(h * scale))), interpolation=cv2.INTER_AREA)
    sh, sw = small.shape[:2]
    gc = np.full((sh, sw), cv2.GC_PR_FGD, np.uint8)
    band = max(2, int(0.03 * max(sh, sw)))
    gc[:band, :] = gc[-band:, :] = gc[:, :band] = gc[:, -band:] = cv2.GC_BGD
    bgd, fgd = np.zeros((1, 65), np.float64), np.zeros((1, 65), np.float64)
    cv2.setRNGSeed(seed)
    cv2.grabCut(cv2.cvtColor(small, cv2.COLOR_RGB2BGR), gc, None, bgd, fgd, 6, cv2.GC_INIT_WITH_MASK)
    fg = (gc == cv2.GC_FGD) | (gc == cv2.GC_PR_FGD)
    first = _clean(fg, "grabcut")
    # second pass: away from the chosen region is background, its core is certain foreground and the rest of it is
    # probably background, so the foreground model learns the object's colours only and touching clutter peels off
    gc2 = np.full((sh, sw), cv2.GC_BGD, np.uint8)
    k = max(3, int(0.02 * max(sh, sw)) | 1)
    near = cv2.dilate(first.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))).astype(bool)
    gc2[near] = cv2.GC_PR_BGD
    core = ndimage.distance_transform_edt(first)
    gc2[core > 0.35 * core.max()] = cv2.GC_FGD
    bgd, fgd = np.zeros((1, 65), np.float64), np.zeros((1, 65), np.float64)
    cv2.grabCut(cv2.cvtColor(small, cv2.COLOR_RGB2BGR), gc2, None, bgd, fgd, 6, cv2.GC_INIT_WITH_MASK)
    fg = (gc2 == cv2.GC_FGD) | (gc2 == cv2.GC_PR_FGD)
    fg = cv2.resize(fg.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST).astype(bool)
    return _clean(fg, "grabcut"), "grabcut"


def _clean(mask: np.ndarray, method: str) -> np.ndarray:
    """Open/close, keep the most central large component, fill holes; error when nothing plausible remains."""
    h, w = mask.shape
    k = max(3, int(0.01 * max(h, w)) | 1)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
    m = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, kernel)
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, kernel)
    n, labels, stats, cents = cv2.connectedComponentsWithStats(m, connectivity=8)
    if n <= 1:
        raise InputError(f"no object found in the image ({method} segmentation is empty)")
    area = stats[1:, cv2.CC_STAT_AREA].astype(np.float64)
    diag = np.hypot(h, w)
    dist = np.hypot(cents[1:, 0] - w / 2.0, cents[1:, 1] - h / 2.0) / diag
    score = area * np.exp(-((dist / 0.25) ** 2))
    best = 1 + int(np.argmax(score))
    out = ndimage.binary_fill_holes(labels == best)
    frac = float(out.mean())
    if frac < MIN_AREA_FRAC:
        raise InputError(f"no object found in the image (largest region covers only {100 * frac:.2f}% of it)")
    if frac > MAX_AREA_FRAC:
        raise InputError("no object found: the foreground fills the whole image; crop less tightly or use a PNG with alpha")
    return out


def inflate(
    mask: np.ndarray, image: np.ndarray, longest_m: float, thickness_m: float, resolution: int
) -> trimesh.Trimesh:
    """Watertight mesh of the silhouette inflated to `thickness_m`; image right -> +x, image up -> +z, depth -> y."""
    ys, xs = np.nonzero(mask)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    crop = mask[y0:y1, x0:x1].astype(np.float32)
    long_px = max(crop.shape)
    n = resolution / long_px
    small = cv2.resize(crop, (max(2, round(crop.shape[1] * n)), max(2, round(crop.shape[0] * n))), interpolation=cv2.INTER_AREA)
    small = cv2.GaussianBlur(np.pad(small, 3), (0, 0), 0.7) >= 0.5
    spacing = longest_m / max(small.shape)
    d_in = ndimage.distance_transform_edt(small) * spacing
    d_out = ndimage.distance_transform_edt(~small) * spacing
    half = thickness_m / 2.0
    reach = max(float(d_in.max()), spacing)
    prof = np.sqrt(np.clip(1.0 - (1.0 - np.minimum(d_in / reach, 1.0)) ** 2, 0.0, 1.0))
    height = np.where(small, half * prof + 0.5 * spacing, -d_out)
    nz = int(np.ceil(half / spacing)) + 3
    z = (np.arange(2 * nz + 1) - nz) * spacing
    field = np.abs(z)[None, None, :] - height[:, :, None]  # axes: row, col, depth
    mesh = mesh_from_field(field, np.array([0.0, 0.0, -nz * spacing]), spacing)
    v = mesh.vertices
    row, col, depth = v[:, 0], v[:, 1], v[:, 2]
    src_r = y0 + (row / spacing - 3.0 + 0.5) / n - 0.5
    src_c = x0 + (col / spacing - 3.0 + 0.5) / n - 0.5
    mesh.vertices = np.stack([col, depth, -row], axis=1)
    mesh.invert()  # the axis swap mirrors the mesh
    colors = _sample_colors(image, mask, src_r, src_c)
    mesh.visual = trimesh.visual.ColorVisuals(mesh, vertex_colors=colors)
    return mesh


def _sample_colors(image: np.ndarray, mask: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """RGBA uint8 from the object's pixels (background replaced by the nearest object pixel before sampling)."""
    rgb = image[:, :, :3]
    _, (ir, ic) = ndimage.distance_transform_edt(~mask, return_indices=True)
    filled = rgb[ir, ic]
    filled = cv2.GaussianBlur(filled, (0, 0), 1.0)
    r = np.clip(np.round(rows).astype(int), 0, mask.shape[0] - 1)
    c = np.clip(np.round(cols).astype(int), 0, mask.shape[1] - 1)
    out = np.full((len(rows), 4), 255, np.uint8)
    out[:, :3] = filled[r, c]
    return out


def silhouette_aspect(mask: np.ndarray) -> float:
    """Short / long side of the mask's bounding box."""
    ys, xs = np.nonzero(mask)
    a, b = ys.max() - ys.min() + 1, xs.max() - xs.min() + 1
    return float(min(a, b) / max(a, b))
