"""Which tiles of a splat frame the pixel kernel must draw on the CPU, and the pictures their other tiles show.

A tile that no Gaussian reaches shows its background alone: over a given picture (the robot and the room of the
pick-and-place video) the picture's own pixels (8-bit colours survive the kernel's round trip through 0..1 unchanged);
in the studio or the flat scene the empty scene's pixels, drawn once per camera by the same kernel and kept, unless
the object's shadow may fall on the tile. Only the other tiles run the kernel: the same bytes as drawing every tile,
for a fraction of the work when the object fills a small part of the frame (the wide view of a robot, the top of a
drop). Numpy only; lengths in metres, the camera frame of tasks.render.camera.Camera.frame().
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable

import numpy as np

from tasks.render.studio import ShadowMap

KEPT_SCENES = 8  # empty-scene pictures kept (a few cameras' worth: 2.8 MB each at 1280 x 720)
MARGIN_PX = 2.0  # the shadow's projected box, widened by this on each side


def busy_tiles(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Whether each tile's slice of the sorted list holds a Gaussian (n_tiles,) bool."""
    return np.asarray(end) > np.asarray(start)


def shadow_tiles(shadow: ShadowMap, rot: np.ndarray, eye: np.ndarray, focal: float, width: int, height: int,
                 tile: int, tiles_x: int, tiles_y: int) -> np.ndarray:
    """The tiles (n_tiles,) bool whose pixels may see the table inside the shadow map (where the kernel samples it;
    outside it the darkening is exactly 0): the box round the map's rectangle on the table (z = 0) as the camera
    sees it, widened by MARGIN_PX; every tile when a corner lies behind the camera. An empty map (no_shadow) reaches
    none."""
    out = np.zeros((tiles_y, tiles_x), bool)
    dark = np.asarray(shadow.darkening)
    if not np.any(dark):
        return out.ravel()
    ny, nx = dark.shape
    ox, oy = shadow.origin_m
    xs = (ox + 0.5 * shadow.cell_m, ox + (nx - 0.5) * shadow.cell_m)  # where the bilinear sample is taken
    ys = (oy + 0.5 * shadow.cell_m, oy + (ny - 0.5) * shadow.cell_m)
    corners = np.array([[x, y, 0.0] for x in xs for y in ys])
    c = (corners - np.asarray(eye, np.float64)) @ np.asarray(rot, np.float64).T
    if np.any(c[:, 2] <= 1e-6):
        out[:] = True
        return out.ravel()
    u = focal * c[:, 0] / c[:, 2] + 0.5 * width
    v = focal * c[:, 1] / c[:, 2] + 0.5 * height
    x0, x1 = int(np.floor((u.min() - MARGIN_PX) / tile)), int(np.floor((u.max() + MARGIN_PX) / tile))
    y0, y1 = int(np.floor((v.min() - MARGIN_PX) / tile)), int(np.floor((v.max() + MARGIN_PX) / tile))
    out[max(y0, 0):max(y1 + 1, 0), max(x0, 0):max(x1 + 1, 0)] = True
    return out.ravel()


class EmptyScenes:
    """The pictures (H * W * 3,) uint8 of empty scenes, by key (device, camera, scene), the last KEPT_SCENES."""

    def __init__(self, kept: int = KEPT_SCENES) -> None:
        self.kept = kept
        self._pictures: OrderedDict[Hashable, np.ndarray] = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Hashable, draw: Callable[[], np.ndarray]) -> np.ndarray:
        """The picture of `key`, drawn by draw() the first time (read-only: copy it before drawing over it)."""
        with self._lock:
            picture = self._pictures.get(key)
            if picture is not None:
                self._pictures.move_to_end(key)
                return picture
        picture = np.ascontiguousarray(draw(), np.uint8).reshape(-1)
        picture.flags.writeable = False
        with self._lock:
            self._pictures[key] = picture
            while len(self._pictures) > self.kept:
                self._pictures.popitem(last=False)
        return picture


EMPTY_SCENES = EmptyScenes()
