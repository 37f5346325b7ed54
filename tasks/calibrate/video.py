"""Read a video's frames (OpenCV) and its frame rate; frames wider than MAX_WIDTH_PX are downscaled as read."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from contracts.errors import InputError

MAX_WIDTH_PX = 640  # tracking resolution: a 4K clip costs what a small one does
MAX_FRAMES = 4000  # more than 4000 frames: the file is refused (a drop lasts seconds)
MIN_FRAMES = 8


@dataclass
class Video:
    """The frames (N, H, W, 3) uint8 RGB, the frame rate and where it came from, and the downscale applied."""

    frames: np.ndarray
    fps: float
    fps_source: str
    downscale: float

    @property
    def times_s(self) -> np.ndarray:
        """Each frame's time from the first [s]."""
        return np.arange(len(self.frames)) / self.fps


def read_video(path: Path, fps: float | None = None) -> Video:
    """All frames of a video file; `fps` (the option) overrides the file's rate, and is needed when it has none.
    InputError (one line) when the file is missing, unreadable, too short or too long, or has no frame rate."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"video not found: {path}")
    cap = cv2.VideoCapture(str(path))
    try:
        if not cap.isOpened():
            raise InputError(f"{path}: not a readable video")
        file_fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
        frames: list[np.ndarray] = []
        scale = 1.0
        while True:
            ok, bgr = cap.read()
            if not ok:
                break
            if len(frames) >= MAX_FRAMES:
                raise InputError(f"{path}: more than {MAX_FRAMES} frames; cut the clip to the drop")
            h, w = bgr.shape[:2]
            if w > MAX_WIDTH_PX:
                scale = MAX_WIDTH_PX / w
                bgr = cv2.resize(bgr, (MAX_WIDTH_PX, max(1, round(h * scale))), interpolation=cv2.INTER_AREA)
            frames.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
    finally:
        cap.release()
    if not frames:
        raise InputError(f"{path}: not a readable video (no frame could be decoded)")
    if len(frames) < MIN_FRAMES:
        raise InputError(f"{path}: only {len(frames)} frames; a drop needs at least {MIN_FRAMES}")
    if fps is not None:
        rate, source = float(fps), "option"
    elif 0.0 < file_fps < 1e5:
        rate, source = file_fps, "file"
    else:
        raise InputError(f"{path}: the file states no frame rate; give it with --fps")
    return Video(np.stack(frames), rate, source, scale)


def write_video(path: Path, frames: np.ndarray, fps: float, quality: int = 85) -> Path:
    """Write RGB frames as an MJPEG .avi (each frame JPEG-compressed at `quality`; the frame rate in the header) or
    through imageio-ffmpeg for .mp4 (H.264)."""
    path = Path(path)
    if path.suffix.lower() == ".avi":
        h, w = frames.shape[1:3]
        vw = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"MJPG"), fps, (w, h))
        vw.set(cv2.VIDEOWRITER_PROP_QUALITY, quality)
        for f in frames:
            vw.write(cv2.cvtColor(f, cv2.COLOR_RGB2BGR))
        vw.release()
        return path
    import imageio.v3 as iio  # only for .mp4 (ffmpeg)

    iio.imwrite(path, frames, fps=fps, codec="libx264", quality=quality // 10)
    return path
