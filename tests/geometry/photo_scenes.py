"""Synthetic photos of everyday objects standing on a table in front of a wall (tests and benchmarks/photo_bench.py):
a squeeze bottle and a plastic cup (solids of revolution whose base is the ellipse a camera above the table sees), a
teddy bear from the front (ears, arms and feet apart from the body) and an armchair from the front (legs)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

SCENES = ("squeeze_bottle", "plastic_cup", "teddy_bear", "armchair", "ball")


def _room(h: int, w: int) -> np.ndarray:
    img = np.zeros((h, w, 3), np.float32)
    img[: int(0.55 * h)] = (200, 200, 205)
    img[int(0.55 * h):] = (140, 105, 80)
    return img


def _paint(img: np.ndarray, mask: np.ndarray, colour: tuple[float, float, float]) -> None:
    """The object's colour, darker towards its left and right edges (a lit, round body)."""
    xs = np.nonzero(mask)[1]
    cx, half = xs.mean(), (np.ptp(xs) + 1) / 2.0
    f = np.clip(1.0 - 0.18 * ((np.arange(img.shape[1]) - cx) / half) ** 2, 0.75, 1.1)
    tex = np.asarray(colour, np.float32)[None, None, :] * f[None, :, None]
    img[mask] = np.broadcast_to(tex, img.shape)[mask]


def scene_mask(name: str, h: int = 900, w: int = 700) -> np.ndarray:
    """The true object mask of a scene (bool, h x w); scenes are drawn for 900 x 700 and scaled."""
    m = np.zeros((900, 700), np.uint8)
    cx = 350
    if name == "squeeze_bottle":
        cv2.rectangle(m, (cx - 80, 380), (cx + 80, 780), 1, -1)
        cv2.ellipse(m, (cx, 780), (80, 18), 0, 0, 180, 1, -1)
        cv2.fillPoly(m, [np.array([[cx - 80, 380], [cx - 30, 260], [cx + 30, 260], [cx + 80, 380]])], 1)
        cv2.rectangle(m, (cx - 28, 170), (cx + 28, 262), 1, -1)
        cv2.rectangle(m, (cx - 33, 150), (cx + 33, 178), 1, -1)
    elif name == "plastic_cup":
        cv2.fillPoly(m, [np.array([[cx - 130, 420], [cx + 130, 420], [cx + 95, 760], [cx - 95, 760]])], 1)
        cv2.ellipse(m, (cx, 760), (95, 20), 0, 0, 180, 1, -1)
        cv2.ellipse(m, (cx, 420), (130, 28), 0, 180, 360, 1, -1)
    elif name == "teddy_bear":
        cv2.ellipse(m, (cx, 600), (130, 160), 0, 0, 360, 1, -1)  # body
        cv2.circle(m, (cx, 370), 105, 1, -1)  # head
        for s in (-1, 1):
            cv2.circle(m, (cx + s * 85, 280), 40, 1, -1)  # ears
            cv2.ellipse(m, (cx + s * 150, 560), (45, 95), s * -30, 0, 360, 1, -1)  # arms
            cv2.ellipse(m, (cx + s * 85, 760), (60, 50), 0, 0, 360, 1, -1)  # feet
    elif name == "armchair":
        cv2.rectangle(m, (170, 300), (530, 640), 1, -1)  # back and seat
        cv2.rectangle(m, (120, 470), (220, 700), 1, -1)
        cv2.rectangle(m, (480, 470), (580, 700), 1, -1)  # arms
        cv2.rectangle(m, (140, 690), (170, 760), 1, -1)
        cv2.rectangle(m, (530, 690), (560, 760), 1, -1)  # legs
    elif name == "ball":
        cv2.circle(m, (cx, 620), 150, 1, -1)
    else:
        raise KeyError(name)
    if (h, w) != m.shape:
        m = cv2.resize(m, (w, h), interpolation=cv2.INTER_NEAREST)
    return m.astype(bool)


COLOURS = {"squeeze_bottle": (40, 120, 200), "plastic_cup": (230, 60, 50), "teddy_bear": (170, 120, 60),
           "armchair": (60, 130, 80), "ball": (240, 200, 40)}


def scene_image(name: str, h: int = 900, w: int = 700, seed: int = 0) -> np.ndarray:
    """RGB uint8 photo of a scene."""
    mask = scene_mask(name, h, w)
    img = _room(h, w)
    _paint(img, mask, COLOURS[name])
    img += np.random.default_rng(seed).normal(0, 3, img.shape).astype(np.float32)
    return img.clip(0, 255).astype(np.uint8)


def write_scene(name: str, path: Path, h: int = 900, w: int = 700) -> Path:
    """Write a scene's photo (PNG or JPEG by the suffix) and return its path."""
    path.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(path), cv2.cvtColor(scene_image(name, h, w), cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, 92])
    return path
