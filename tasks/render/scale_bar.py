"""A scale bar drawn into an orthographic still: a round length (1, 2 or 5 x 10^k m) as a bar with end ticks and its
label ("5 cm") in the bottom-left corner, so that a still says how big the object is (a 6 cm makeup pad and a 25 cm
plate are the same disc without it).

    from tasks.render.scale_bar import bar_length_m, draw_scale_bar

    draw_scale_bar(img, metres_per_pixel)   # in place, on a (H, W, 3) uint8 image

The label is drawn with a 5 x 7 pixel font held here (digits, '.', 'c', 'm', ' '): no font file or drawing library.
"""

from __future__ import annotations

import numpy as np

GLYPHS = {  # 5 x 7, '#' is ink
    "0": (".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."),
    "1": ("..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."),
    "2": (".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"),
    "3": ("####.", "....#", "....#", ".###.", "....#", "....#", "####."),
    "4": ("...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."),
    "5": ("#####", "#....", "####.", "....#", "....#", "#...#", ".###."),
    "6": (".###.", "#....", "#....", "####.", "#...#", "#...#", ".###."),
    "7": ("#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."),
    "8": (".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."),
    "9": (".###.", "#...#", "#...#", ".####", "....#", "....#", ".###."),
    ".": (".....", ".....", ".....", ".....", ".....", ".##..", ".##.."),
    "c": (".....", ".....", ".###.", "#....", "#....", "#....", ".###."),
    "m": (".....", ".....", "##.#.", "#.#.#", "#.#.#", "#.#.#", "#.#.#"),
    " ": (".....",) * 7,
}
INK = (40, 40, 40)
MAX_FRACTION = 0.32  # the bar is at most this fraction of the image's width


def bar_length_m(metres_per_pixel: float, width_px: int) -> float:
    """The longest round length (1, 2 or 5 x 10^k m) no longer than MAX_FRACTION of the image's width."""
    limit = MAX_FRACTION * width_px * metres_per_pixel
    exp = int(np.floor(np.log10(limit)))
    for k in (exp, exp - 1):
        for m in (5.0, 2.0, 1.0):
            if m * 10.0**k <= limit * (1 + 1e-9):
                return m * 10.0**k
    return 10.0**(exp - 1)


def length_label(length_m: float) -> str:
    """'5 mm', '2 cm', '50 cm', '1 m' (the unit that keeps the number at least 1)."""
    for unit, scale in (("m", 1.0), ("cm", 0.01), ("mm", 0.001)):
        if length_m >= scale * (1 - 1e-9):
            value = length_m / scale
            return f"{value:g} {unit}" if value >= 1 else f"{value:.1f} {unit}"
    return f"{length_m * 1000:.2g} mm"


def _text_mask(text: str, scale: int) -> np.ndarray:
    """Boolean (7 scale, 6 scale len - scale) mask of text in the font."""
    cols = []
    for ch in text:
        g = np.array([[c == "#" for c in row] for row in GLYPHS[ch]])
        cols += [g, np.zeros((7, 1), bool)]
    mask = np.concatenate(cols[:-1], axis=1)
    return np.kron(mask, np.ones((scale, scale), bool))


def draw_scale_bar(img: np.ndarray, metres_per_pixel: float, margin_px: int | None = None) -> float:
    """Draw the bar and its label into img (H, W, 3) uint8 in place; returns the bar's length [m]."""
    h, w = img.shape[:2]
    length = bar_length_m(metres_per_pixel, w)
    px = max(int(round(length / metres_per_pixel)), 2)
    scale = max(1, round(w / 200))
    margin = margin_px if margin_px is not None else max(4, w // 48)
    thick = max(2, scale + 1)
    y1 = h - margin
    x0 = margin
    img[y1 - thick:y1, x0:x0 + px] = INK
    img[y1 - thick - 3 * scale:y1, x0:x0 + thick] = INK  # end ticks
    img[y1 - thick - 3 * scale:y1, x0 + px - thick:x0 + px] = INK
    mask = _text_mask(length_label(length), scale)
    ty = y1 - thick - 4 * scale - mask.shape[0]
    tx = x0 + thick + scale
    mh, mw = mask.shape
    region = img[max(ty, 0):ty + mh, tx:tx + mw]
    region[mask[:region.shape[0], :region.shape[1]]] = INK
    return length
