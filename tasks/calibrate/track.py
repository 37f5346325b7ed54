"""Segment the object in every frame by background difference and track its centre, bottom and height (pixels).

The background: a static camera sees the object held (or entering) at the start and resting at the end, so a median
over all frames holds the resting object. Instead the medians of the first and of the last frames are taken; where
they agree they are the background; where they differ, the lower region (image y down: the object at rest) takes
the first frames' median and the upper (the object before its release) the last frames'. The object in a frame is
the largest connected region whose colour differs from the background by more than a threshold set from the image
noise; a frame with no such region (or one far smaller or larger than the object) is dropped and counted.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from contracts.errors import InputError

END_FRACTION = 0.15  # the first and last 15 % of the frames (at least END_FRAMES) give the two background medians
END_FRAMES = 5
MIN_AREA_PX = 12  # a region smaller than this is not the object
AREA_OUTLIER = 3.0  # a frame's mask area beyond 3x (or under 1/3 of) the median area is a failed segmentation
MIN_THRESHOLD = 18.0  # grey levels


@dataclass
class Track:
    """Per tracked frame: time [s], centroid (x, y) and second-moment height (4 sigma_y, the height of an ellipse or
    a disc of that sigma) of the coverage (object_mask), bottom and top y of the mask (image y down), width and height (_extent), mask area [px]; with the frame
    count, the indices of the frames kept, the threshold and the frame rate."""

    frames: int
    index: np.ndarray
    t_s: np.ndarray
    cx: np.ndarray
    cy: np.ndarray
    bottom: np.ndarray
    top: np.ndarray
    moment_height: np.ndarray
    box_width: np.ndarray
    box_height: np.ndarray
    area: np.ndarray
    threshold: float
    fps: float

    @property
    def dropped(self) -> int:
        """Frames without the object."""
        return self.frames - len(self.index)


def _diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest per-channel absolute difference of two RGB images (float32)."""
    return np.abs(a.astype(np.float32) - b.astype(np.float32)).max(axis=-1)


def noise_threshold(frames: np.ndarray) -> float:
    """Background-difference threshold: 6 robust sigmas of the frame-to-frame difference of still pixels, at least
    MIN_THRESHOLD grey levels."""
    n = len(frames)
    pairs = [(i, i + 1) for i in np.linspace(0, n - 2, min(8, n - 1)).astype(int)]
    d = np.concatenate([(frames[i].astype(np.float32) - frames[j].astype(np.float32)).ravel() for i, j in pairs])
    mad = float(np.median(np.abs(d - np.median(d))))
    return max(MIN_THRESHOLD, 6.0 * 1.4826 * mad / np.sqrt(2.0))


def background(frames: np.ndarray, threshold: float) -> np.ndarray:
    """The scene without the object (see the module docstring)."""
    k = max(END_FRAMES, int(END_FRACTION * len(frames)))
    first = np.median(frames[:k], axis=0)
    last = np.median(frames[-k:], axis=0)
    differ = (_diff(first, last) > threshold).astype(np.uint8)
    differ = cv2.morphologyEx(differ, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    n, labels, stats, cent = cv2.connectedComponentsWithStats(differ)
    out = last.copy()
    big = [i for i in range(1, n) if stats[i, cv2.CC_STAT_AREA] >= MIN_AREA_PX]
    if big:
        lowest = max(big, key=lambda i: cent[i][1])  # the object at rest: the lowest region in the image
        region = cv2.dilate((labels == lowest).astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
        out[region] = first[region]
    return out.astype(np.float32)


def object_mask(frame: np.ndarray, bg: np.ndarray, threshold: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The largest region of the frame that differs from the background, cleaned (open, then close, 3x3), with its
    edge at half the object's contrast; and the coverage of each pixel (1 inside, the difference over the object's
    contrast on the one-pixel rings either side of the edge: a sub-pixel outline for the moments). None when there is
    no region of MIN_AREA_PX."""
    diff = _diff(frame, bg)
    region = _largest(diff > threshold)
    if region is None:
        return None
    # the edge at half the object's contrast (where a pixel is half covered): an unbiased outline and extent
    contrast = float(np.median(diff[region]))
    near = cv2.dilate(region.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    mask = _largest((diff > max(threshold, 0.5 * contrast)) & near)
    if mask is None:
        return None
    m8 = mask.astype(np.uint8)
    ring = cv2.dilate(m8, np.ones((3, 3), np.uint8)).astype(bool) & ~cv2.erode(m8, np.ones((3, 3), np.uint8)).astype(bool)
    cover = mask.astype(np.float64)
    cover[ring] = np.clip(diff[ring] / max(contrast, 1e-6), 0.0, 1.0)
    return mask, cover


def moment_height(cover: np.ndarray) -> tuple[float, float]:
    """(centroid row, 4 sigma of the rows) of a coverage image [px]: the height of a disc or an ellipse of that
    sigma."""
    rows = cover.sum(axis=1)
    y = np.arange(len(rows), dtype=np.float64)
    w = float(rows.sum())
    cy = float((rows * y).sum() / w)
    return cy, 4.0 * float(np.sqrt(max(0.0, (rows * (y - cy) ** 2).sum() / w)))


def _largest(mask: np.ndarray) -> np.ndarray | None:
    """The largest connected region of a mask after a 3x3 open and close; None when it is under MIN_AREA_PX."""
    m = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, np.ones((3, 3), np.uint8))
    n, labels, stats, _ = cv2.connectedComponentsWithStats(m)
    if n <= 1:
        return None
    i = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    if stats[i, cv2.CC_STAT_AREA] < MIN_AREA_PX:
        return None
    return labels == i


def _extent(profile: np.ndarray) -> float:
    """The object's extent along an axis [px]: the columns (or rows) that hold at least a tenth of the widest one's
    pixels (and 2), so that a stray edge pixel of noise does not widen the box."""
    return float(np.count_nonzero(profile >= max(2.0, 0.1 * float(profile.max()))))


def track_object(frames: np.ndarray, fps: float) -> Track:
    """Track the object through the frames (InputError when it is never found)."""
    thr = noise_threshold(frames)
    bg = background(frames, thr)
    rows: list[tuple[float, ...]] = []
    for i, f in enumerate(frames):
        found = object_mask(f, bg, thr)
        if found is None:
            continue
        m, cover = found
        ys, xs = np.nonzero(m)
        cy, height = moment_height(cover)
        cx = float((cover.sum(axis=0) * np.arange(cover.shape[1])).sum() / cover.sum())
        rows.append((float(i), i / fps, cx, cy, float(ys.max()) + 0.5, float(ys.min()) - 0.5, height,
                     _extent(m.sum(axis=0)), _extent(m.sum(axis=1)), float(len(ys))))
    if not rows:
        raise InputError("the object was never found in the video (no region differs from the background)")
    a = np.array(rows)
    med = float(np.median(a[:, 9]))
    keep = (a[:, 9] <= AREA_OUTLIER * med) & (a[:, 9] >= med / AREA_OUTLIER)
    a = a[keep]
    if len(a) < 0.25 * len(frames) or len(a) < 6:
        raise InputError(f"the object was found in only {len(a)} of {len(frames)} frames; the video needs a static "
                         "camera and an object that stands out from the background")
    c = a.T
    return Track(frames=len(frames), index=c[0].astype(int), t_s=c[1], cx=c[2], cy=c[3], bottom=c[4], top=c[5],
                 moment_height=c[6], box_width=c[7], box_height=c[8], area=c[9], threshold=thr, fps=fps)


__all__ = ["Track", "background", "moment_height", "noise_threshold", "object_mask", "track_object"]
