"""The real clip beside the simulated one (issue #39): the video's key moments (release, first impact, top of the first
bounce, rest), the fitted material's drop simulated from the same release and drawn in the video's own camera (its
scale, floor line and the object's place, each particle a disc of half the spacing on the clip's empty background),
and one small JPEG strip of the pairs: the real frames on top, the simulated ones below."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from contracts.video_fit import KeyFrame
from tasks.calibrate.metrics import DropAnalysis
from tasks.calibrate.synthetic import Camera, draw, mpm_drop_positions
from tasks.calibrate.track import Track

TILE_HEIGHT_PX = 240  # each frame of the strip is scaled to this height (the strip stays a few tens of kB)
TILE_MIN_WIDTH_PX = 170  # a narrow frame is centred on a tile this wide (room for its caption)
CAPTION_PX = 34  # the caption band above each frame
JPEG_QUALITY = 80
SIM_COLOUR = (40, 110, 220)  # the simulated particles (RGB)
BACKGROUND_FRAMES = 25  # frames the clip's empty background is the median of


def key_frames(tr: Track, d: DropAnalysis) -> list[KeyFrame]:
    """The video's key moments as tracked: release, first impact, top of the first bounce (when the object left the
    floor and the clip shows the top), rest (at the settle time; else 'end of clip'); each at a tracked frame."""
    if d.release_t is None or len(tr.t_s) < 2:
        return []
    t0 = d.release_t
    rows: list[tuple[str, int]] = [("release", int(np.argmin(np.abs(tr.t_s - t0))))]
    if d.impact_t is not None:
        rows.append(("first impact", int(np.argmin(np.abs(tr.t_s - d.impact_t)))))
    if d.left_floor and d.contact is not None:
        above = tr.cy < d.rest_cy - (d.settle_tol_px or 1.0)  # image y is down: above the resting centroid
        j = d.contact[1] + 1
        while j < len(above) and not above[j]:  # still on the floor after the impact
            j += 1
        run = []
        while j < len(above) and above[j]:  # the first flight after it
            run.append(j)
            j += 1
        top = run[int(np.argmin(tr.cy[run]))] if run else None
        if top is not None and top != len(above) - 1:  # a top the clip shows (not a rise cut off by its end)
            rows.append(("top of first bounce", top))
    if d.settle_t is None:
        rows.append(("end of clip", len(tr.t_s) - 1))  # still moving there: no settle time
    else:
        rows.append(("rest", int(np.argmin(np.abs(tr.t_s - (t0 + d.settle_t))))))
    out, seen = [], set()
    for label, r in rows:
        if r in seen:
            continue
        seen.add(r)
        out.append(KeyFrame(label=label, t_s=float(tr.t_s[r]), frame=int(tr.index[r]),
                            sim_t_s=max(0.0, float(tr.t_s[r] - t0))))
    return out


@dataclass(frozen=True)
class SimDrawing:
    """The simulated particles (K, N, 3) at the key frames' simulated times (the first at the release), their spacing
    and the drop height they were released from [m]."""

    positions_m: np.ndarray
    spacing_m: float
    drop_height_m: float


def simulate_key_frames(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                        drop_height_m: float, fps: float, frames: list[KeyFrame], sim: SimConfig) -> SimDrawing:
    """The fitted material's drop (tasks.calibrate.synthetic.mpm_drop_positions: released with its bottom
    `drop_height_m` above the floor, as the fit's probe) sampled at the video's frame rate up to the last key frame;
    the particles at each key frame's simulated time."""
    last = max(k.sim_t_s for k in frames)
    x = mpm_drop_positions(positions_m, volumes_m3, physical, material, drop_height_m, fps, last + 1.0 / fps, sim,
                           hold_s=1.0 / fps)  # frame i at i / fps after the release
    picks = [min(len(x) - 1, int(round(k.sim_t_s * fps))) for k in frames]
    return SimDrawing(x[picks], physical.particle_spacing_m, drop_height_m)


def background(frames: np.ndarray, tr: Track) -> np.ndarray:
    """The clip's empty scene (float RGB): per pixel, the median of up to BACKGROUND_FRAMES tracked frames spread over
    the clip, each without the object's box (grown by a quarter and 3 px); the plain median where every one covers it
    (an object that never moved)."""
    rows = np.unique(np.linspace(0, len(tr.index) - 1, min(len(tr.index), BACKGROUND_FRAMES)).astype(int))
    h, w = frames.shape[1:3]
    stack = frames[tr.index[rows]].astype(np.float32)
    for k, r in enumerate(rows):
        half_w, half_h = 0.625 * tr.box_width[r] + 3, 0.625 * (tr.bottom[r] - tr.top[r]) + 3
        mid_y = 0.5 * (tr.bottom[r] + tr.top[r])
        x0, x1 = int(max(0, tr.cx[r] - half_w)), int(min(w, np.ceil(tr.cx[r] + half_w)))
        y0, y1 = int(max(0, mid_y - half_h)), int(min(h, np.ceil(mid_y + half_h)))
        stack[k, y0:y1, x0:x1] = np.nan
    plain = np.median(frames[tr.index[rows]].astype(np.float32), axis=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN pixel: the plain median below
        bg = np.nanmedian(stack, axis=0)
    return np.where(np.isnan(bg), plain, bg)


def sim_frames(drawing: SimDrawing, bg: np.ndarray, metres_per_px: float, floor_y_px: float,
               centre_x_px: float) -> list[np.ndarray]:
    """The simulated particles drawn in the video's camera (side view: x right, z up) on its background: the floor
    `drop_height_m` below the drawn bottom at release (as the video's drop height is measured) on the video's floor
    line, the object's centre where the video's was at release."""
    x = drawing.positions_m
    h, w = bg.shape[:2]
    floor_z = float(x[0][:, 2].min()) - 0.5 * drawing.spacing_m - drawing.drop_height_m
    cam = Camera(width_px=w, height_px=h, px_per_m=1.0 / metres_per_px, floor_z_m=floor_z, floor_y_px=floor_y_px,
                 centre_x_px=centre_x_px - float(x[0][:, 0].mean()) / metres_per_px)
    out = []
    for pts in x:
        px, py = cam.project(pts[:, 0], pts[:, 2])
        out.append(np.clip(draw(bg, np.stack([px, py], axis=1), 0.5 * drawing.spacing_m / metres_per_px,
                                SIM_COLOUR), 0, 255).astype(np.uint8))
    return out


def _tile(img: np.ndarray, lines: list[str]) -> np.ndarray:
    """A frame scaled to TILE_HEIGHT_PX, centred on a white tile at least TILE_MIN_WIDTH_PX wide, under a white
    caption band of `lines`."""
    h, w = img.shape[:2]
    scale = TILE_HEIGHT_PX / h
    frame = cv2.resize(np.ascontiguousarray(img), (max(1, int(round(w * scale))), TILE_HEIGHT_PX),
                       interpolation=cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR)
    width = max(frame.shape[1], TILE_MIN_WIDTH_PX)
    tile = np.full((CAPTION_PX + TILE_HEIGHT_PX, width, 3), 255, np.uint8)
    x0 = (width - frame.shape[1]) // 2
    tile[CAPTION_PX:, x0:x0 + frame.shape[1]] = frame
    for i, text in enumerate(lines):
        cv2.putText(tile, text, (3, 13 + 15 * i), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (20, 20, 20), 1, cv2.LINE_AA)
    return tile


def strip(real: list[np.ndarray], sim: list[np.ndarray], frames: list[KeyFrame]) -> np.ndarray:
    """The side-by-side strip (uint8 RGB): one column per key frame, the real frame above the simulated one."""
    cols = []
    for r, s, k in zip(real, sim, frames):
        top = _tile(r, [f"real: {k.label}"[:28], f"t = {k.t_s:.3f} s"])
        bottom = _tile(s, ["simulated", f"{k.sim_t_s:.3f} s after release"])
        width = max(top.shape[1], bottom.shape[1])
        cols.append(np.concatenate([np.pad(t, ((0, 0), (0, width - t.shape[1]), (0, 0)), constant_values=255)
                                    for t in (top, bottom)], axis=0))
    gap = np.full((cols[0].shape[0], 4, 3), 255, np.uint8)
    return np.concatenate([c for col in cols for c in (col, gap)][:-1], axis=1)


def write_jpeg(path: Path, img: np.ndarray, quality: int = JPEG_QUALITY) -> Path:
    """An RGB image as a JPEG file (parent folder made)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    ok, buf = cv2.imencode(".jpg", cv2.cvtColor(img, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:
        raise OSError(f"{path}: JPEG encoding failed")
    path.write_bytes(buf.tobytes())
    return path


__all__ = ["SimDrawing", "background", "key_frames", "sim_frames", "simulate_key_frames", "strip", "write_jpeg"]
