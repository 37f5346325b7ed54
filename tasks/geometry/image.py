"""Single image -> object mask: alpha, or GrabCut seeded by a saliency (boundary connectivity on superpixels x colour
contrast against the border and a centre prior), with thin strips reaching the image border (door frames, table edges)
cut off, cast shadows removed and touching clutter peeled off; both checked against the saliency, so a highlight, a
dark side panel or a cap as white as the table stays on the object."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from scipy import ndimage

from contracts.errors import InputError
from tasks.geometry.image_guard import check_image_size

SEG_MAX_SIDE = 400  # segmentation works on an image at most this large [px]
PHOTO_MAX_SIDE = 1024  # a photo is reduced to at most this many pixels along a side as it is read [px]
MIN_AREA_FRAC = 0.004
MAX_AREA_FRAC = 0.95
STRIP_OPEN_FRAC = 0.3  # opening radius / the mask's largest inscribed radius: cuts strips thinner than this [-]
SHADOW_CHROMA = 10.0  # Lab a-b distance under which a darker pixel counts as the background in shade [-]
# a shadow is less salient than the object: a shadow-coloured region is removed only when its mean boundary saliency
# is under this x the rest of the mask's (cast shadows of the drawn scenes 0.57-0.63, the basketball's rim 0.58-0.77;
# object parts taken for shadows in the photos: a bottle's dark bottom, an apple's shaded side 0.88-0.99) [-]
SHADOW_SALIENCY = 0.8
# the peel takes off what is unlike the object's core; a piece it took is given back when it is large and as salient
# as the object (touching clutter of the drawn turtle: at most 5 % of the object; a backpack's side panel, an apple's
# highlighted side, the second cherry: 9-111 %, saliency 0.87-0.91 x the object's; the basketball's rim 0.68-0.80) [-]
PEEL_KEEP_AREA = 0.07
PEEL_KEEP_SALIENCY = 0.85
SALIENCY_SEGMENTS = 350  # SLIC superpixels of the saliency at the segmentation size [-]
SALIENCY_SIGMA_CLR = 10.0  # CIE Lab distance scale of "similar colours" in the saliency's graph [-]


def load_image(path: Path, max_side: int | None = PHOTO_MAX_SIDE) -> np.ndarray:
    """RGB or RGBA uint8 array of a PNG/JPEG (clear error when missing or unreadable), turned upright by its EXIF
    orientation and reduced to at most `max_side` pixels along a side as it is read (a 12-megapixel phone photo is
    decoded at a quarter of its size by the JPEG decoder itself, so nothing after this pays for its pixels)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"image file not found: {path}")
    width, height = check_image_size(path)  # refuse a decompression bomb from its header, before decoding
    flag = cv2.IMREAD_UNCHANGED
    if not _has_alpha(path):
        flag = cv2.IMREAD_COLOR  # applies the EXIF orientation (IMREAD_UNCHANGED ignores it)
        reduced = {2: cv2.IMREAD_REDUCED_COLOR_2, 4: cv2.IMREAD_REDUCED_COLOR_4, 8: cv2.IMREAD_REDUCED_COLOR_8}
        for k in (8, 4, 2):
            if max_side is not None and max(width, height) >= k * max_side:
                flag = reduced[k]
                break
    raw = cv2.imread(str(path), flag)
    if raw is None or raw.size == 0:
        raise InputError(f"cannot read image {path.name}: not a valid PNG/JPEG")
    if raw.dtype == np.uint16:
        raw = (raw / 257).astype(np.uint8)
    if raw.ndim == 2:
        raw = cv2.cvtColor(raw, cv2.COLOR_GRAY2BGR)
    if max_side is not None and max(raw.shape[:2]) > max_side:
        k = max_side / max(raw.shape[:2])
        size = (max(8, round(raw.shape[1] * k)), max(8, round(raw.shape[0] * k)))
        raw = cv2.resize(raw, size, interpolation=cv2.INTER_AREA)
    if raw.shape[2] == 4:
        return cv2.cvtColor(raw, cv2.COLOR_BGRA2RGBA)
    return cv2.cvtColor(raw[:, :, :3], cv2.COLOR_BGR2RGB)


def _has_alpha(path: Path) -> bool:
    """True when the image's header declares transparency (an alpha channel or a transparent palette entry)."""
    from PIL import Image

    try:
        with Image.open(path) as im:
            return im.mode in ("RGBA", "LA", "PA", "La", "RGBa") or "transparency" in im.info
    except (OSError, SyntaxError, ValueError):
        return True  # let OpenCV read it unchanged and say what it finds


def segment(image: np.ndarray, seed: int = 0) -> tuple[np.ndarray, str]:
    """Foreground mask (H, W) bool and the method used ('alpha' or 'grabcut+saliency[+shadow]')."""
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
    bgr = cv2.cvtColor(small, cv2.COLOR_RGB2BGR)
    lab = cv2.cvtColor(small, cv2.COLOR_RGB2LAB).astype(np.float32)
    sh, sw = small.shape[:2]
    band = max(2, int(0.03 * max(sh, sw)))
    border = np.zeros((sh, sw), bool)
    border[:band, :] = border[-band:, :] = border[:, :band] = border[:, -band:] = True
    cv2.setRNGSeed(seed)
    # boundary connectivity finds the whole object (a highlight is salient), but also background enclosed by the
    # object, its shadow and a door frame; the colour contrast to the border is low there: GrabCut is seeded by both
    rbd = boundary_saliency(small)
    sal = np.sqrt(rbd * contrast_saliency(lab, border))
    # pass 1: the border is background; salient pixels are probably the object, the rest probably background
    gc = np.where(sal >= _otsu(sal), cv2.GC_PR_FGD, cv2.GC_PR_BGD).astype(np.uint8)
    if (gc == cv2.GC_PR_FGD).mean() < MIN_AREA_FRAC:
        gc[:] = cv2.GC_PR_FGD
    gc[border] = cv2.GC_BGD
    first = _clean(_grabcut(bgr, gc), "grabcut", sal)
    shadow = shadow_pixels(lab, first, rbd)
    if shadow.any() and (first & ~shadow).sum() > 0.5 * first.sum():
        first = _clean(first & ~shadow, "grabcut", sal)
    # pass 2: away from the chosen region is background, its core is certain foreground and the rest of it is
    # probably background, so the foreground model learns the object's colours only and touching clutter peels off;
    # large pieces as salient as the object are given back (parts of colours its core lacks)
    gc2 = np.full((sh, sw), cv2.GC_BGD, np.uint8)
    k = max(3, int(0.02 * max(sh, sw)) | 1)
    near = cv2.dilate(first.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))).astype(bool)
    gc2[near] = cv2.GC_PR_BGD
    core = ndimage.distance_transform_edt(first)
    gc2[core > 0.35 * core.max()] = cv2.GC_FGD
    peeled = _clean(_grabcut(bgr, gc2), "grabcut", sal)
    fg = peeled | _salient_pieces(first & ~peeled, peeled, rbd)
    if fg.sum() > peeled.sum():
        fg = _clean(fg, "grabcut", sal)
    method = "grabcut+saliency"
    shadow = shadow_pixels(lab, fg, rbd)
    if shadow.any():
        fg = _clean(fg & ~shadow, "grabcut", sal)
        method += "+shadow"
    fg = cv2.resize(fg.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST).astype(bool)
    return _clean(fg, "grabcut"), method


def _salient_pieces(lost: np.ndarray, kept: np.ndarray, sal: np.ndarray) -> np.ndarray:
    """The pieces of `lost` (what the peel took off `kept`) that are part of the object: large (at least
    PEEL_KEEP_AREA of the kept mask) and about as salient as it (mean saliency at least PEEL_KEEP_SALIENCY x its)."""
    lost = cv2.morphologyEx(lost.astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    n, labels = cv2.connectedComponents(lost, connectivity=8)
    if n <= 1:
        return np.zeros_like(kept)
    idx = np.arange(1, n)
    area = np.bincount(labels.ravel(), minlength=n)[1:]
    mean = np.asarray(ndimage.mean(sal, labels, idx))
    ok = (area >= PEEL_KEEP_AREA * kept.sum()) & (mean >= PEEL_KEEP_SALIENCY * float(sal[kept].mean()))
    return np.isin(labels, idx[ok])


def _grabcut(bgr: np.ndarray, gc: np.ndarray, iterations: int = 6) -> np.ndarray:
    bgd, fgd = np.zeros((1, 65), np.float64), np.zeros((1, 65), np.float64)
    cv2.grabCut(bgr, gc, None, bgd, fgd, iterations, cv2.GC_INIT_WITH_MASK)
    return (gc == cv2.GC_FGD) | (gc == cv2.GC_PR_FGD)


def _otsu(values: np.ndarray) -> float:
    v = np.clip(values * 255.0, 0, 255).astype(np.uint8)
    t, _ = cv2.threshold(v, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    return float(t) / 255.0


def _colour_centres(lab: np.ndarray, where: np.ndarray, k: int) -> np.ndarray:
    """k-means Lab colour centres of the pixels `where` (deterministic for a fixed cv2 RNG seed)."""
    px = lab[where].reshape(-1, 3).astype(np.float32)
    if len(px) > 20_000:
        px = px[:: len(px) // 20_000 + 1]
    k = max(1, min(k, len(px)))
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 30, 0.5)
    _, _, centres = cv2.kmeans(px, k, None, crit, 2, cv2.KMEANS_PP_CENTERS)
    return centres


def _nearest_distance(lab: np.ndarray, centres: np.ndarray) -> np.ndarray:
    d = np.linalg.norm(lab[:, :, None, :] - centres[None, None, :, :], axis=-1)
    return d.min(axis=2)


def boundary_saliency(rgb: np.ndarray, segments: int = SALIENCY_SEGMENTS) -> np.ndarray:
    """Per-pixel object likelihood in [0, 1] by robust background detection (Zhu et al., CVPR 2014) on SLIC
    superpixels: a region is background as far as it is connected to the image border through similar colours
    (its boundary connectivity), so a highlight on the object, a cap as white as the table or a dark side panel is
    still salient when the object's outline separates it from the border; the contrast against the background-weighted
    regions and a smoothness term over neighbouring superpixels are then combined by least squares."""
    from scipy import sparse
    from scipy.sparse.csgraph import dijkstra
    from scipy.sparse.linalg import spsolve
    from skimage.segmentation import slic

    h, w = rgb.shape[:2]
    sp = slic(rgb, n_segments=segments, compactness=10, start_label=0, enforce_connectivity=True)
    n = int(sp.max()) + 1
    flat = sp.ravel()
    count = np.maximum(np.bincount(flat, minlength=n), 1).astype(np.float64)
    lab = cv2.cvtColor(rgb, cv2.COLOR_RGB2LAB).astype(np.float64)
    lab[..., 0] *= 100.0 / 255.0  # CIE Lab units: a colour difference of 10 is a clearly visible one
    lab[..., 1:] -= 128.0
    colour = np.stack([np.bincount(flat, lab[..., c].ravel(), n) for c in range(3)], axis=1) / count[:, None]
    yy, xx = np.mgrid[:h, :w] / float(max(h, w))
    pos = np.stack([np.bincount(flat, yy.ravel(), n), np.bincount(flat, xx.ravel(), n)], axis=1) / count[:, None]
    a = np.concatenate([sp[:, :-1].ravel(), sp[:-1, :].ravel()])
    b = np.concatenate([sp[:, 1:].ravel(), sp[1:, :].ravel()])
    touching = np.unique(np.sort(np.stack([a[a != b], b[a != b]], axis=1), axis=1), axis=0)
    edge = np.unique(np.concatenate([sp[0], sp[-1], sp[:, 0], sp[:, -1]]))
    ii, jj = np.triu_indices(len(edge), 1)
    links = np.unique(np.concatenate([touching, np.stack([edge[ii], edge[jj]], axis=1)]), axis=0)
    d_link = np.linalg.norm(colour[links[:, 0]] - colour[links[:, 1]], axis=1) + 1e-3
    graph = sparse.coo_matrix((d_link, (links[:, 0], links[:, 1])), shape=(n, n)).tocsr()
    geo = dijkstra(graph, directed=False)
    near = np.exp(-(geo**2) / (2.0 * SALIENCY_SIGMA_CLR**2))
    connectivity = near[:, edge].sum(axis=1) / np.sqrt(near.sum(axis=1))
    w_bg = 1.0 - np.exp(-(connectivity**2) / 2.0)
    d_app = np.linalg.norm(colour[:, None] - colour[None], axis=2)
    d_spa = np.linalg.norm(pos[:, None] - pos[None], axis=2)
    contrast = (d_app * np.exp(-(d_spa**2) / (2.0 * 0.25**2)) * w_bg[None]).sum(axis=1)
    w_fg = contrast / max(float(contrast.max()), 1e-9)
    w_ij = np.exp(-(d_app[touching[:, 0], touching[:, 1]] ** 2) / (2.0 * SALIENCY_SIGMA_CLR**2)) + 0.1
    rows = np.concatenate([touching[:, 0], touching[:, 1]])
    cols = np.concatenate([touching[:, 1], touching[:, 0]])
    smooth = sparse.coo_matrix((np.concatenate([w_ij, w_ij]), (rows, cols)), shape=(n, n)).tocsr()
    lap = sparse.diags(np.asarray(smooth.sum(axis=1)).ravel()) - smooth
    s = spsolve((sparse.diags(w_bg + w_fg) + lap).tocsc(), w_fg)
    s = (s - s.min()) / max(float(np.ptp(s)), 1e-9)
    return s[sp].astype(np.float32)


def contrast_saliency(lab: np.ndarray, border: np.ndarray) -> np.ndarray:
    """Per-pixel object likelihood in [0, 1]: Lab distance to the nearest border colour x a centre prior."""
    sh, sw = border.shape
    contrast = _nearest_distance(lab, _colour_centres(lab, border, 8))
    contrast = cv2.GaussianBlur(contrast, (0, 0), 0.01 * max(sh, sw) + 0.5)
    contrast = contrast / max(float(np.percentile(contrast, 99)), 1e-6)
    yy, xx = np.mgrid[:sh, :sw]
    centre = np.exp(-0.5 * (((xx - sw / 2.0) / (0.35 * sw)) ** 2 + ((yy - sh / 2.0) / (0.35 * sh)) ** 2))
    return np.clip(contrast, 0.0, 1.0) * centre


def shadow_pixels(lab: np.ndarray, mask: np.ndarray, sal: np.ndarray | None = None) -> np.ndarray:
    """Mask pixels that look like the surrounding background in shade: the ring's chroma, darker, unlike the core;
    with a saliency map, only regions less salient than the rest of the mask (SHADOW_SALIENCY)."""
    size = max(mask.shape)
    k = max(5, int(0.06 * size) | 1)
    ring = cv2.dilate(mask.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))).astype(bool) & ~mask
    core_d = ndimage.distance_transform_edt(mask)
    core = core_d > 0.5 * core_d.max()
    if ring.sum() < 20 or core.sum() < 20:
        return np.zeros_like(mask)
    bg = _colour_centres(lab, ring, 6)
    obj = _colour_centres(lab, core, 6)
    ab, L = lab[:, :, 1:], lab[:, :, 0]
    chroma_d = np.linalg.norm(ab[:, :, None, :] - bg[None, None, :, 1:], axis=-1)
    darker = L[:, :, None] < 0.85 * bg[None, None, :, 0]
    lighter_than_black = L[:, :, None] > 0.2 * bg[None, None, :, 0]
    shade_d = np.where(darker & lighter_than_black, chroma_d, np.inf).min(axis=2)
    obj_d = _nearest_distance(lab, obj)
    cand = mask & (shade_d < SHADOW_CHROMA) & (shade_d < 0.5 * obj_d) & ~core
    # a shadow is a sizeable region reaching the outline, not scattered dark texture inside the object
    cand = cv2.morphologyEx(cand.astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8)).astype(bool)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(cand.astype(np.uint8), connectivity=8)
    edge = mask & ~cv2.erode(mask.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    keep = np.zeros(n, bool)
    on_edge = np.unique(labels[edge & cand])
    keep[on_edge] = True
    keep[0] = False
    keep &= stats[:, cv2.CC_STAT_AREA] >= 0.01 * mask.sum()
    if sal is not None and keep.any():
        rest = mask & ~keep[labels]
        if rest.any():
            mean = np.asarray(ndimage.mean(sal, labels, np.arange(n)))
            keep &= mean < SHADOW_SALIENCY * float(sal[rest].mean())
    return keep[labels]


def _clean(mask: np.ndarray, method: str, saliency_map: np.ndarray | None = None) -> np.ndarray:
    """Cut thin strips, reject border-hugging regions, keep the most central / salient large component, fill holes;
    error when nothing plausible remains."""
    h, w = mask.shape
    m = mask.astype(np.uint8)
    k = max(3, int(0.01 * max(h, w)) | 1)
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
    # strips (door frames, table edges) are thin: an opening wider than them but narrower than the object cuts them
    thick = ndimage.distance_transform_edt(m)
    r = max(1, int(STRIP_OPEN_FRAC * float(thick.max())))
    opened = cv2.morphologyEx(m, cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1)))
    if opened.sum() < 0.3 * m.sum():
        opened = m
    n, labels, stats, cents = cv2.connectedComponentsWithStats(opened, connectivity=8)
    if n <= 1:
        raise InputError(f"no object found in the image ({method} segmentation is empty)")
    area = stats[1:, cv2.CC_STAT_AREA].astype(np.float64)
    diag = np.hypot(h, w)
    dist = np.hypot(cents[1:, 0] - w / 2.0, cents[1:, 1] - h / 2.0) / diag
    score = area * np.exp(-((dist / 0.25) ** 2))
    if saliency_map is not None:
        sal = ndimage.mean(saliency_map, labels, np.arange(1, n))
        score *= 0.25 + np.asarray(sal)
    # a region running along the image border (a door frame, the table edge) is background
    x0, y0 = stats[1:, cv2.CC_STAT_LEFT], stats[1:, cv2.CC_STAT_TOP]
    x1, y1 = x0 + stats[1:, cv2.CC_STAT_WIDTH], y0 + stats[1:, cv2.CC_STAT_HEIGHT]
    spans = ((y0 == 0) & (y1 == h)) | ((x0 == 0) & (x1 == w))
    score = np.where(spans & (area < 0.5 * h * w), score * 1e-3, score)
    best = 1 + int(np.argmax(score))
    # give back what the opening shaved off (legs, ears, tails, and what hangs on them), except pieces reaching the
    # image border and regions spanning it: those are strips of the background (door frames, table edges)
    n2, lab2 = cv2.connectedComponents((m.astype(bool) & ~opened.astype(bool)).astype(np.uint8), connectivity=8)
    edge_ids = np.unique(np.concatenate([lab2[0], lab2[-1], lab2[:, 0], lab2[:, -1]]))
    strips = 1 + np.flatnonzero(spans & (np.arange(n - 1) != best - 1))
    bad = np.isin(lab2, edge_ids[edge_ids > 0]) | np.isin(labels, strips)
    n3, lab3 = cv2.connectedComponents((m.astype(bool) & ~bad).astype(np.uint8), connectivity=8)
    keep = np.bincount(lab3[labels == best], minlength=n3)
    keep[0] = 0
    out = lab3 == int(np.argmax(keep))
    out = ndimage.binary_fill_holes(out)
    frac = float(out.mean())
    if frac < MIN_AREA_FRAC:
        raise InputError(f"no object found in the image (largest region covers only {100 * frac:.2f}% of it)")
    if frac > MAX_AREA_FRAC:
        raise InputError("no object found: the foreground fills the whole image; crop less tightly or use a PNG with alpha")
    return out
