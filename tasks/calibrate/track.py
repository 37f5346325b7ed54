"""Segment the object in every frame by background difference and track its centre, bottom and height (pixels).

The background: a static camera sees the object held (or entering) at the start and resting at the end, so a median
over all frames holds the resting object. Instead the medians of the first and of the last frames are taken; where
they agree they are the background; where they differ, the lowest region that differs clearly (by twice the
threshold: the object at rest, image y down; a shadow that moved or the exposure drifting differ barely) takes the
first frames' median and the rest (the object before its release, the hand that held it) the last frames'. That
region at rest is also the object's reference: its area and its colour in the last frames.

The object in a frame is a connected region that differs from the background by more than a threshold set from the
image noise (or by twice it, so that the object over a shadowed patch comes apart from the shadow): with a reference,
the region of the reference's area (within AREA_OUTLIER) whose colour is closest to the reference's, so that a hand,
an arm or a shadow moving in the frame is not taken for it; without one, the largest region. A frame with no such
region is dropped and counted; so is a frame where the object touches the frame's edge (partly out of the picture,
its centre and extent would be wrong), counted apart.
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
GAIN_WINDOW = 2.5  # object sizes over which the scene's lighting gain is taken (a median: the object is a fifth of it)
CLEAR_CONTRAST = 2.0  # a region that differs by this many thresholds (its median) is an object, not a shading change


@dataclass(frozen=True)
class Reference:
    """The object as the last frames show it at rest: its area [px] and mean colour (RGB)."""

    area: float
    colour: tuple[float, float, float]


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
    at_edge: int = 0
    duplicates: int = 0
    reference: Reference | None = None
    repeated: np.ndarray | None = None  # per frame: a repeat of the one before (left out)

    @property
    def last_frame(self) -> int:
        """The video's last frame that is not a repeat."""
        if self.repeated is None or not self.repeated.any():
            return self.frames - 1
        return int(np.flatnonzero(~self.repeated)[-1])

    def consecutive(self, row: int) -> bool:
        """Whether track row `row` follows row - 1 with no frame between them but repeats."""
        a, b = int(self.index[row - 1]), int(self.index[row])
        return b - a == 1 or (self.repeated is not None and bool(self.repeated[a + 1:b].all()))

    @property
    def dropped(self) -> int:
        """Frames without the object (at_edge of them with the object touching the frame's edge), repeats of the
        frame before left aside."""
        return self.frames - self.duplicates - len(self.index)


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
    return scene_background(frames, threshold)[0]


def scene_background(frames: np.ndarray, threshold: float) -> tuple[np.ndarray, Reference | None]:
    """The scene without the object and the object's reference from its place at rest (None when the first and last
    frames show no clear difference: the object never rests in view, or rests where it started)."""
    k = max(END_FRAMES, int(END_FRACTION * len(frames)))
    first = np.median(frames[:k], axis=0)
    last = np.median(frames[-k:], axis=0)
    d = _diff(first, last)
    out = last.copy()
    ref = None
    # the object at rest: the lowest region that differs clearly (a shadow or an exposure drift does not; it may
    # surround the object, so the regions are taken at the clear level), grown by its softer edge
    clear = cv2.morphologyEx((d > CLEAR_CONTRAST * threshold).astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    n, labels, stats, cent = cv2.connectedComponentsWithStats(clear)
    found = [i for i in range(1, n) if stats[i, cv2.CC_STAT_AREA] >= MIN_AREA_PX]
    if found:
        lowest = max(found, key=lambda i: cent[i][1])  # the object at rest: the lowest region in the image
        core = (labels == lowest).astype(np.uint8)
        at_rest = (cv2.dilate(core, np.ones((5, 5), np.uint8)).astype(bool) & (d > threshold)) | core.astype(bool)
        c = last[at_rest].mean(axis=0)
        ref = Reference(float(np.count_nonzero(at_rest)), (float(c[0]), float(c[1]), float(c[2])))
    else:  # nothing clear: the lowest region that differs at all
        differ = cv2.morphologyEx((d > threshold).astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
        n, labels, stats, cent = cv2.connectedComponentsWithStats(differ)
        big = [i for i in range(1, n) if stats[i, cv2.CC_STAT_AREA] >= MIN_AREA_PX]
        if not big:
            return out.astype(np.float32), None
        at_rest = labels == max(big, key=lambda i: cent[i][1])
    region = cv2.dilate(at_rest.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    out[region] = first[region]
    return out.astype(np.float32), ref


def object_mask(frame: np.ndarray, bg: np.ndarray, threshold: float, ref: Reference | None = None
                ) -> tuple[np.ndarray, np.ndarray] | None:
    """The region of the frame that differs from the background and is the object (the module docstring: the one
    most like `ref`, else the largest), cleaned (open, then close, 3x3), with its edge at half the object's contrast;
    and the coverage of each pixel (1 inside, the difference over the object's contrast on the one-pixel rings either
    side of the edge: a sub-pixel outline for the moments). None when no region is the object."""
    if ref is not None:
        bg = bg * lighting_gain(frame, bg, ref)[..., None]
    diff = _diff(frame, bg)
    region = _largest(diff > threshold) if ref is None else _most_like(frame, diff, threshold, ref)
    if region is None:
        return None
    # the edge at half the object's contrast (where a pixel is half covered): an unbiased outline and extent
    contrast = float(np.median(diff[region]))
    near = cv2.dilate(region.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    strong = diff > max(threshold, 0.5 * contrast)
    if ref is not None:  # a pixel is the object's when its colour is nearer the object's than the background's: the
        # object's shadow (a darker background) and a dull reflection of it in a glossy floor are not the object
        f = frame.astype(np.float32)
        strong &= np.linalg.norm(f - np.asarray(ref.colour, np.float32), axis=-1) < np.linalg.norm(f - bg, axis=-1)
    mask = _largest(strong & near)
    if mask is None:
        return None
    m8 = mask.astype(np.uint8)
    ring = cv2.dilate(m8, np.ones((3, 3), np.uint8)).astype(bool) & ~cv2.erode(m8, np.ones((3, 3), np.uint8)).astype(bool)
    cover = mask.astype(np.float64)
    cover[ring] = np.clip(diff[ring] / max(contrast, 1e-6), 0.0, 1.0)
    return mask, cover


def lighting_gain(frame: np.ndarray, bg: np.ndarray, ref: Reference) -> np.ndarray:
    """How much brighter the frame's scene is than the background, pixel by pixel: the ratio of their brightness,
    median-filtered over GAIN_WINDOW object sizes (the object covers too little of that window to move the median, a
    soft shadow or the camera's exposure is a gain that varies slowly), clipped to [1/2, 2]."""
    h, w = frame.shape[:2]
    size = 2.0 * float(np.sqrt(ref.area / np.pi))
    step = max(1, int(size / 4))
    lum_f = cv2.resize(frame.astype(np.float32).mean(axis=-1), (max(1, w // step), max(1, h // step)),
                       interpolation=cv2.INTER_AREA)
    lum_b = cv2.resize(bg.astype(np.float32).mean(axis=-1), (max(1, w // step), max(1, h // step)),
                       interpolation=cv2.INTER_AREA)
    q = np.clip(128.0 + 100.0 * np.log((lum_f + 8.0) / (lum_b + 8.0)), 0, 255).astype(np.uint8)
    k = int(GAIN_WINDOW * size / step) // 2 * 2 + 1
    q = cv2.medianBlur(q, min(k, 2 * (min(q.shape) // 2) - 1) if min(q.shape) > 2 else 1)
    gain = np.exp((q.astype(np.float32) - 128.0) / 100.0)
    return np.clip(cv2.resize(gain, (w, h), interpolation=cv2.INTER_LINEAR), 0.5, 2.0)


def _most_like(frame: np.ndarray, diff: np.ndarray, threshold: float, ref: Reference) -> np.ndarray | None:
    """Of the regions differing by more than the threshold and by more than twice it, the one of the reference's
    area (within AREA_OUTLIER) whose mean colour is closest to the reference's; None when none has its area."""
    best, pick = np.inf, None
    want = np.asarray(ref.colour)
    for level in (threshold, CLEAR_CONTRAST * threshold):
        m = cv2.morphologyEx((diff > level).astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
        m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, np.ones((3, 3), np.uint8))
        n, labels, stats, _ = cv2.connectedComponentsWithStats(m)
        if n <= 1:
            continue
        flat = labels.ravel()
        count = np.bincount(flat, minlength=n).astype(np.float64)
        sums = np.stack([np.bincount(flat, frame[..., c].ravel().astype(np.float64), n) for c in range(3)], 1)
        mean = sums.astype(np.float64) / np.maximum(count, 1.0)[:, None]
        for i in range(1, n):
            a = stats[i, cv2.CC_STAT_AREA]
            if a < MIN_AREA_PX or not ref.area / AREA_OUTLIER <= a <= ref.area * AREA_OUTLIER:
                continue
            dist = float(np.linalg.norm(mean[i] - want))
            if dist < best:
                best, pick = dist, labels == i
    return pick


def duplicate_frames(frames: np.ndarray) -> np.ndarray:
    """Which frames repeat the one before (fewer than MIN_AREA_PX pixels changed by more than MIN_THRESHOLD: the
    compression's noise, no object moved) while the next one does not: a clip re-timed to a higher rate shows each picture twice, and the repeat's time stamp is not when it was
    taken. A still scene's compressed frames also come out alike, but all of them in a row: those are kept. Only
    where a quarter of the moving frames repeat (the clip is re-timed), else none."""
    n = len(frames)
    same = np.zeros(n, bool)
    for i in range(1, n):
        changed = np.count_nonzero(_diff(frames[i], frames[i - 1]) > MIN_THRESHOLD)
        same[i] = changed < MIN_AREA_PX
    repeat = same & ~np.append(same[1:], False)
    moving = ~same | repeat
    return repeat if repeat.sum() >= 0.25 * max(1, moving.sum()) else np.zeros(n, bool)


def touches_edge(mask: np.ndarray) -> bool:
    """Whether the mask reaches the frame's border (the object partly out of the picture)."""
    return bool(mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())


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
    bg, ref = scene_background(frames, thr)
    rows: list[tuple[float, ...]] = []
    at_edge = 0
    repeats = duplicate_frames(frames)
    for i, f in enumerate(frames):
        if repeats[i]:
            continue
        found = object_mask(f, bg, thr, ref)
        if found is None:
            continue
        m, cover = found
        if touches_edge(m):
            at_edge += 1
            continue
        ys, xs = np.nonzero(m)
        cy, height = moment_height(cover)
        cx = float((cover.sum(axis=0) * np.arange(cover.shape[1])).sum() / cover.sum())
        rows.append((float(i), i / fps, cx, cy, float(ys.max()) + 0.5, float(ys.min()) - 0.5, height,
                     _extent(m.sum(axis=0)), _extent(m.sum(axis=1)), float(len(ys))))
    if not rows:
        raise InputError("the object was never found in the video (no region differs from the background)"
                         + (f"; it touched the frame's edge in {at_edge} frames" if at_edge else ""))
    a = np.array(rows)
    med = float(np.median(a[:, 9]))
    keep = (a[:, 9] <= AREA_OUTLIER * med) & (a[:, 9] >= med / AREA_OUTLIER)
    a = a[keep]
    if len(a) < 0.25 * (len(frames) - repeats.sum()) or len(a) < 6:
        raise InputError(f"the object was found in only {len(a)} of {len(frames)} frames; the video needs a static "
                         "camera and an object that stands out from the background")
    c = a.T
    return Track(frames=len(frames), index=c[0].astype(int), t_s=c[1], cx=c[2], cy=c[3], bottom=c[4], top=c[5],
                 moment_height=c[6], box_width=c[7], box_height=c[8], area=c[9], threshold=thr, fps=fps,
                 at_edge=at_edge, duplicates=int(repeats.sum()), reference=ref, repeated=repeats)


__all__ = ["Reference", "Track", "background", "moment_height", "noise_threshold", "object_mask", "scene_background",
           "duplicate_frames", "touches_edge", "track_object"]
