"""Fit a shape program's orthographic silhouette to a photo's mask: view, flip, per-axis scale, in-plane pose (IoU)."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.optimize import minimize

from contracts.shape import ShapeProgram
from tasks.geometry.meshing import sample_program

# camera = VIEW_ROTATION[view] @ program: camera x is image right, z image up, y points away from the camera
VIEW_ROTATION: dict[str, np.ndarray] = {
    "side": np.eye(3),  # looking along the program's y: its length to the right, its height up
    "front": np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),  # looking along -x at its front
    "top": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),  # looking down on it
}
FIT_CELLS = 128  # fit grid cells along the silhouette's longest side [-]
SIDE_TILT_DEG = 30.0  # largest in-plane tilt tried for side and front views (a toy lying on its back is a top view)
_SRC_RES = 64  # program occupancy grid cells along its longest extent [-]
_SILHOUETTES: dict[str, dict[str, tuple[np.ndarray, np.ndarray, float]]] = {}


@dataclass(frozen=True)
class ProgramFit:
    """Program frame [m] -> camera frame [units of the mask's longest side]: c = R(angle) diag(scale) F V p + t."""

    view: str
    flipped: bool
    angle_deg: float
    scale: tuple[float, float, float]  # camera x, y (depth), z [units / m]
    translation: tuple[float, float]  # camera x, z [units]
    iou: float

    def matrix(self) -> np.ndarray:
        """3x3 linear part program [m] -> camera [units]."""
        a = np.radians(self.angle_deg)
        rot = np.array([[np.cos(a), 0.0, -np.sin(a)], [0.0, 1.0, 0.0], [np.sin(a), 0.0, np.cos(a)]])
        flip = np.diag([-1.0, -1.0, 1.0]) if self.flipped else np.eye(3)
        return rot @ np.diag(self.scale) @ flip @ VIEW_ROTATION[self.view]

    def to_program(self, cam: np.ndarray) -> np.ndarray:
        """Camera points (N, 3) [units] -> program frame [m]."""
        t = np.array([self.translation[0], 0.0, self.translation[1]])
        return (cam - t) @ np.linalg.inv(self.matrix()).T


def fitted_silhouette(program: ShapeProgram, fit: ProgramFit, shape: tuple[int, int], cells: int) -> np.ndarray:
    """The fitted program's silhouette on a [x cell, z cell] grid of `cells` per unit (bool)."""
    src = program_silhouettes(program)[fit.view]
    sx, sz = fit.scale[0], fit.scale[2]
    return _render(src, fit.flipped, fit.angle_deg, sx, sz, np.asarray(fit.translation), shape, cells) > 0.5


def program_silhouettes(program: ShapeProgram) -> dict[str, tuple[np.ndarray, np.ndarray, float]]:
    """Per view: occupancy image [camera x index, camera z index] (float), its origin (x, z) [m] and spacing [m]."""
    key = program.model_dump_json()
    if key not in _SILHOUETTES:
        _SILHOUETTES.clear()  # one program at a time (the fit, then the reconstruction)
        _SILHOUETTES[key] = _silhouettes(program)
    return _SILHOUETTES[key]


def _silhouettes(program: ShapeProgram) -> dict[str, tuple[np.ndarray, np.ndarray, float]]:
    field, origin, spacing = sample_program(program, _SRC_RES)
    occ = field < 0.0
    out: dict[str, tuple[np.ndarray, np.ndarray, float]] = {}
    for view, rot in VIEW_ROTATION.items():
        depth_axis = int(np.argmax(np.abs(rot[1])))
        right_axis, up_axis = int(np.argmax(np.abs(rot[0]))), int(np.argmax(np.abs(rot[2])))
        sil = occ.any(axis=depth_axis)
        kept = [a for a in range(3) if a != depth_axis]
        if kept != [right_axis, up_axis]:
            sil = sil.T
        out[view] = (np.asarray(sil, dtype=np.float32), np.array([origin[right_axis], origin[up_axis]]), spacing)
    return out


def _soft_iou(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.minimum(a, b).sum() / max(np.maximum(a, b).sum(), 1e-9))


def _render(src: tuple[np.ndarray, np.ndarray, float], flipped: bool, angle_deg: float, sx: float, sz: float,
            t: np.ndarray, shape: tuple[int, int], cells: int = FIT_CELLS) -> np.ndarray:
    """The program silhouette drawn into a [x index, z index] grid of `cells` per unit."""
    img, origin, spacing = src
    a = np.radians(angle_deg)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    lin = rot @ np.diag([sx * (-1.0 if flipped else 1.0), sz]) * cells
    # index (i, j) -> program (x, z) = origin + (i, j) * spacing -> camera units -> cell index (minus the centre)
    g = np.eye(3)
    g[:2, :2] = lin * spacing
    g[:2, 2] = lin @ origin + np.asarray(t) * cells - 0.5
    swap = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    m = (swap @ g @ swap)[:2]  # OpenCV's x is the second array index
    return cv2.warpAffine(img, m, (shape[1], shape[0]), flags=cv2.INTER_LINEAR, borderValue=0.0)


def fit_program(program: ShapeProgram, target: np.ndarray, views: tuple[str, ...] = tuple(VIEW_ROTATION)) -> ProgramFit:
    """Best view (of `views`) / flip / per-axis scale / pose of the program for a mask [x cell, z cell] at FIT_CELLS
    per unit."""
    target = target.astype(np.float32)
    shape = target.shape
    ti, tk = np.nonzero(target > 0.5)
    t_lo, t_hi = np.array([ti.min(), tk.min()]), np.array([ti.max() + 1, tk.max() + 1])
    t_ctr = (t_lo + t_hi) / 2.0 / FIT_CELLS
    t_size = (t_hi - t_lo) / FIT_CELLS
    sources = program_silhouettes(program)
    starts = []
    for view, src in sources.items():
        if view not in views:
            continue
        angles = range(0, 360, 45) if view == "top" else (0.0,)
        for flipped in (False, True):
            for ang in angles:
                # unit scale first, then match the bounding box per axis and centre it
                s0 = 0.5 / (max(src[0].shape) * src[2])  # the program spans half a unit
                probe = _render(src, flipped, ang, s0, s0, np.array(shape) / 2.0 / FIT_CELLS, shape)
                pi, pk = np.nonzero(probe > 0.5)
                if len(pi) == 0:
                    continue
                p_size = np.array([pi.max() + 1 - pi.min(), pk.max() + 1 - pk.min()]) / FIT_CELLS
                sx, sz = s0 * t_size / np.maximum(p_size, 1e-6)
                mid = np.array(shape) / 2.0 / FIT_CELLS
                probe = _render(src, flipped, ang, sx, sz, mid, shape)
                pi, pk = np.nonzero(probe > 0.5)
                if len(pi) == 0:
                    continue
                p_ctr = np.array([pi.min() + pi.max() + 1, pk.min() + pk.max() + 1]) / 2.0 / FIT_CELLS
                t0 = mid + t_ctr - p_ctr
                params = np.array([np.log(sx), np.log(sz), *t0, float(ang)])
                starts.append((_soft_iou(_render(src, flipped, ang, sx, sz, t0, shape), target), view, flipped, params))
    starts.sort(key=lambda s: -s[0])
    chosen = [next(s for s in starts if s[1] == view) for view in VIEW_ROTATION if any(s[1] == view for s in starts)]
    chosen += [s for s in starts if all(s is not c for c in chosen)][:1]
    best: ProgramFit | None = None
    for _, view, flipped, p0 in chosen:
        src = sources[view]
        a0 = p0[4]

        def loss(p: np.ndarray, src=src, flipped=flipped, a0=a0, view=view) -> float:  # noqa: ANN001
            if view != "top" and abs(p[4]) > SIDE_TILT_DEG:
                return 1.0 + abs(p[4])
            return 1.0 - _soft_iou(_render(src, flipped, p[4], np.exp(p[0]), np.exp(p[1]), p[2:4], shape), target)

        simplex = np.array([p0] + [p0 + d for d in np.diag([0.08, 0.08, 0.03, 0.03, 8.0])])
        res = minimize(loss, p0, method="Nelder-Mead",
                       options={"initial_simplex": simplex, "maxfev": 300, "xatol": 1e-3, "fatol": 1e-4})
        p = res.x
        sx, sz = float(np.exp(p[0])), float(np.exp(p[1]))
        hard = _render(src, flipped, p[4], sx, sz, p[2:4], shape) > 0.5
        iou = float((hard & (target > 0.5)).sum() / max((hard | (target > 0.5)).sum(), 1))
        if best is None or iou > best.iou:
            best = ProgramFit(view=view, flipped=flipped, angle_deg=(float(p[4]) + 180.0) % 360.0 - 180.0,
                              scale=(sx, float(np.sqrt(sx * sz)), sz), translation=(float(p[2]), float(p[3])), iou=iou)
    assert best is not None
    return best
