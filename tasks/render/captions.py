"""Text on video frames: a few lines in the top-left corner (OpenCV's Hershey font, dark on a light backdrop)."""

from __future__ import annotations

import numpy as np


def caption(image: np.ndarray, lines: list[str], origin_px: tuple[int, int] = (18, 34),
            scale: float | None = None) -> np.ndarray:
    """The image with the lines written from origin_px, all sizes times scale (default: the image's height over 720
    lines); a copy."""
    import cv2  # opencv: imported where used (the card and the CLI do not need it)

    out = np.ascontiguousarray(image).copy()
    scale = image.shape[0] / 720.0 if scale is None else scale
    for i, text in enumerate(lines):
        org = (int(origin_px[0] * scale), int((origin_px[1] + 30 * i) * scale))
        cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.75 * scale, (30, 30, 35), max(1, int(2 * scale)),
                    cv2.LINE_AA)
    return out
