"""Pixels to metres and the tracker's summary: the scale from the object's size (--size over its longest extent in
px), else from the drop height (--drop-height over the fall in px), else from gravity (9.81 m/s^2 over the free
fall's fitted acceleration in px/s^2); InputError when none is available."""

from __future__ import annotations

import numpy as np

from contracts.errors import InputError
from contracts.video_fit import TrackSummary, VideoScale
from tasks.calibrate.metrics import DropAnalysis
from tasks.calibrate.track import Track
from tasks.calibrate.video import Video
from tasks.realworld.physics import G_M_PER_S2


def video_scale(d: DropAnalysis, size_m: float | None, drop_height_m: float | None) -> VideoScale:
    """The scale, from the first source available (see the module docstring)."""
    g_px = 2.0 * d.fall.c if d.fall is not None else None
    if size_m is not None:
        mpp = size_m / d.longest_extent
        return VideoScale(metres_per_px=mpp, source="size", gravity_check=g_px * mpp if g_px else None,
                          detail=f"--size {size_m:g} m over the object's longest extent, {d.longest_extent:.1f} px "
                                 f"(median over the {d.extent_frames} frames)")
    drop_px = d.drop_px
    if drop_height_m is not None and drop_px is not None and drop_px > 0:
        mpp = drop_height_m / drop_px
        return VideoScale(metres_per_px=mpp, source="drop_height", gravity_check=g_px * mpp if g_px else None,
                          detail=f"--drop-height {drop_height_m:g} m over the fall of the object's bottom, "
                                 f"{drop_px:.1f} px")
    if g_px is not None and d.fall is not None and d.fall.frames >= 6:
        return VideoScale(metres_per_px=G_M_PER_S2 / g_px, source="gravity", gravity_check=G_M_PER_S2,
                          detail=f"9.81 m/s^2 over the free fall's acceleration, {g_px:.1f} px/s^2 (parabola over "
                                 f"{d.fall.frames} frames; the frame rate sets it)")
    raise InputError("no way to scale the video: give --size (the object's longest extent in metres) or "
                     "--drop-height (the fall of its bottom), the video shows too little free fall to scale by gravity")


def track_summary(tr: Track, d: DropAnalysis, video: Video) -> TrackSummary:
    """Frames tracked and dropped, the floor line and heights, the tracking confidence."""
    flight = tr.area[: d.contact[0]] if d.contact is not None and d.contact[0] > 2 else tr.area
    cv = float(np.std(flight) / np.mean(flight)) if len(flight) > 1 else 1.0
    consistency = float(min(1.0, max(0.0, 1.0 - cv)))
    tracked = len(tr.index) / max(1, tr.frames - tr.duplicates)
    h, w = video.frames.shape[1:3]
    return TrackSummary(frames=tr.frames, frames_tracked=len(tr.index), frames_dropped=tr.dropped,
                        frames_at_edge=tr.at_edge, frames_repeated=tr.duplicates, fps=video.fps,
                        fps_source="option" if video.fps_source == "option" else "file", frame_size_px=(w, h),
                        downscale=video.downscale, floor_y_px=d.floor_y, rest_height_px=d.rest_height,
                        flight_height_px=d.flight_height, longest_extent_px=d.longest_extent,
                        tracking_confidence=tracked * consistency, area_consistency=consistency,
                        threshold=tr.threshold)


__all__ = ["track_summary", "video_scale"]
