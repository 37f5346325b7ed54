"""Words printed on a part's outer face (a pack's product name on its label): placed on the part, rasterised with
OpenCV's Hershey font, coloured into the mesh's vertex colours, the mesh refined under the print so its vertices are
fine enough to carry the letters (red-green refinement: the mesh stays watertight)."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import cv2
import numpy as np
import trimesh

from contracts.shape import Print, ShapeProgram
from tasks.geometry.sdf import part_sdf, primitive_half_extent, rotation_matrix

# The views whose camera a print faces, (towards the camera, screen up): a print reads upright seen from the view its
# face turns to (the renders' front and side cameras, tasks.render.views; a face turned up, from the three-quarter
# view's camera, which sees it first: its screen-up on the ground is away from that camera)
_FACING = (((0.0, 0.0, 1.0), (-0.8, 0.6, 0.0)), ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)), ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
           ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)), ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)))
SEEN_FIRST = np.array([0.5, -0.3, 1.0])  # the way the renders see a body from (above, then its front) [-]
CENTRAL_SHARE = 0.5  # a part whose centre lies within this share of its half thickness of the body's is central [-]
FACE_SHARE = (0.86, 0.72)  # the text block's most of the face (along its reading direction, across it) [-]
MIN_FREE_SHARE = 0.22  # a band beside a label's picture narrower than this share of the face: print over the picture
FONT = cv2.FONT_HERSHEY_DUPLEX
RASTER_PX = 64  # the rasterised letters' height [px]
STROKE_PX = 7  # their stroke [px]: bold, as a pack's name is printed
EDGE_PER_LETTER = 1.0 / 14.0  # the refined mesh's edges under a print / its letters' height [-]
MAX_LEVELS = 3  # halvings of the mesh's edges under a print, at most
SURFACE_SHARE = 0.3  # ink lies within this share of the letters' height of its part's own surface [-]
MIN_SURFACE_M = 0.002  # and at least this near [m] (a blend moves the surface off the part's own)


@dataclass(frozen=True)
class Placement:
    """Where a print lies: its centre, reading direction r, up u and outward normal n (r x u = n), the half sizes of
    its text block along r and u, and the letters' height [m]."""

    centre: np.ndarray
    r: np.ndarray
    u: np.ndarray
    n: np.ndarray
    half_r: float
    half_u: float
    letter_m: float
    lines: int
    face_level: float  # the part's middle along n: only points beyond it (its outer face) take the ink


def _part(program: ShapeProgram, name: str):  # noqa: ANN202
    return next((p for p in program.parts if p.name == name), None)


def _pictures(program: ShapeProgram, name: str) -> list:
    """The pictures on a label (parts named 'emblem...' or 'picture...', other than the label itself)."""
    return [p for p in program.parts if p.name.startswith(("emblem", "picture")) and p.name != name]


def _inked_parts(program: ShapeProgram, name: str) -> list:
    """The parts a print's ink lies on: its own and, on a label, the label's pictures."""
    own = _part(program, name)
    return [own, *(_pictures(program, name) if "label" in name else [])] if own is not None else []


def _box(part) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001
    """(centre, axes as rows, half extents) of a part's bounding box in the program frame."""
    tf = part.transform
    axes = rotation_matrix(tf).T  # rows: the part's local x, y, z in the program frame
    half = primitive_half_extent(part) * np.abs(np.asarray(tf.scale, dtype=np.float64))
    return np.asarray(tf.translation_m, dtype=np.float64), axes, half


def _program_centre(program: ShapeProgram) -> np.ndarray:
    """Centre of the union parts' centres (which way is out from the body)."""
    return np.mean([np.asarray(p.transform.translation_m, dtype=np.float64) for p in program.parts
                    if p.operation == "union"], axis=0)


@functools.lru_cache(maxsize=64)
def text_mask(text: str, lines: int) -> np.ndarray:
    """The words as ink coverage in [0, 1], (rows, cols) float32, split into `lines` lines at spaces (balanced)."""
    rows = _split(text, lines)
    sizes = [cv2.getTextSize(r, FONT, 1.0, STROKE_PX)[0] for r in rows]
    scale = RASTER_PX / max(max(h for _, h in sizes), 1)
    widths = [int(np.ceil(w * scale)) for w, _ in sizes]
    pad = STROKE_PX
    line_h = int(RASTER_PX * 1.45)
    img = np.zeros((line_h * len(rows) + 2 * pad, max(widths) + 2 * pad), np.uint8)
    for k, (row, w) in enumerate(zip(rows, widths)):
        x = pad + (max(widths) - w) // 2
        y = pad + k * line_h + RASTER_PX
        cv2.putText(img, row, (x, y), FONT, scale, 255, STROKE_PX, cv2.LINE_AA)
    ys, xs = np.nonzero(img)
    img = img[max(ys.min() - pad, 0):ys.max() + pad + 1, max(xs.min() - pad, 0):xs.max() + pad + 1]
    return img.astype(np.float32) / 255.0


def _split(text: str, lines: int) -> list[str]:
    words = text.split()
    if lines <= 1 or len(words) < 2:
        return [text]
    best = min(range(1, len(words)), key=lambda k: abs(len(" ".join(words[:k])) - len(" ".join(words[k:]))))
    return [" ".join(words[:best]), " ".join(words[best:])]


def _lines(text: str, along: float, across: float) -> tuple[int, float]:
    """(lines, letter height [m]) that print the words largest in a block `along` x `across` [m]."""
    best = (1, 0.0)
    for lines in (1, 2) if " " in text else (1,):
        mask = text_mask(text, lines)
        h, w = mask.shape
        k = min(along / w, across / h)  # metres per pixel
        letter = k * RASTER_PX
        if letter > best[1] * 1.15:  # (two lines only when clearly larger)
            best = (lines, letter)
    return best


LONG_READING_GAIN = 1.5  # words on a face turned up read along its length when that makes them this much larger [-]


def _letter(text: str, half: np.ndarray, axes: np.ndarray, in_plane: list[int], r: np.ndarray) -> float:
    """The letter height [m] of words reading along r on a face of the part's in-plane half extents."""
    i = max(in_plane, key=lambda k: abs(float(np.dot(axes[k], r))))
    j = in_plane[0] if i == in_plane[1] else in_plane[1]
    return _lines(text, FACE_SHARE[0] * 2.0 * half[i], FACE_SHARE[1] * 2.0 * half[j])[1]


def placements(program: ShapeProgram, pr: Print) -> list[Placement]:
    """Where a print lies: its placement, and on a central part (a pack's body, a tube's) the same words on the
    opposite face too, as a real pack prints both sides (a tube turned over to rest on its stable side showed a blank
    face, development set 60)."""
    first = placement(program, pr)
    if first is None:
        return []
    back = placement(program, pr, back=True) if _central(program, pr.part) else None
    return [first] if back is None else [first, back]


def _central(program: ShapeProgram, name: str) -> bool:
    """Whether a part's centre lies within CENTRAL_SHARE of its half thickness of the body's (a pack's body)."""
    part = _part(program, name)
    if part is None:
        return False
    centre, axes, half = _box(part)
    k = int(np.argmin(half))
    return abs(float(np.dot(centre - _program_centre(program), axes[k]))) < CENTRAL_SHARE * half[k]


def placement(program: ShapeProgram, pr: Print, back: bool = False) -> Placement | None:
    """The print's place on its part's outer face (the face of the part's thinnest axis turned away from the body),
    reading upright from the view camera that face turns to; beside the label's picture (parts named 'emblem' or
    'picture') when the band left there is wide enough. None when the program has no such part."""
    part = _part(program, pr.part)
    if part is None:
        return None
    centre, axes, half = _box(part)
    k = int(np.argmin(half))
    offset = float(np.dot(centre - _program_centre(program), axes[k]))
    if _central(program, pr.part):  # a central part (a pack's body): its face the renders see first
        offset = float(np.dot(SEEN_FIRST, axes[k]))
    n = axes[k] * (1.0 if offset >= 0.0 else -1.0) * (-1.0 if back else 1.0)
    toward, up = max(_FACING, key=lambda f: float(np.dot(f[0], n)))
    u = np.asarray(up, dtype=np.float64) - np.dot(up, n) * n
    if np.linalg.norm(u) < 1e-6:
        return None
    in_plane = [i for i in range(3) if i != k]
    # read along the face's edge nearest the view's screen-right, upright in that view
    right = np.cross(u / np.linalg.norm(u), n)
    r = max((s * axes[i] for i in in_plane for s in (1.0, -1.0)), key=lambda a: float(np.dot(a, right)))
    along_long = max((s * axes[i] for i in in_plane for s in (1.0, -1.0)), key=lambda a: (
        float(np.dot(np.abs(a), half[in_plane[0]] * np.abs(axes[in_plane[0]]) + half[in_plane[1]]
                     * np.abs(axes[in_plane[1]]))), float(np.dot(a, right))))
    if float(np.dot(n, (0.0, 0.0, 1.0))) > 0.7 and _letter(pr.text, half, axes, in_plane, along_long) \
            > LONG_READING_GAIN * _letter(pr.text, half, axes, in_plane, r):
        r = along_long  # a face turned up, long and narrow (a tube lying down): the words along its length, larger
    u = np.cross(n, r)
    # the face's extents along r and u, and the pictures on it
    corners = np.array([centre + sa * half[in_plane[0]] * axes[in_plane[0]] + sb * half[in_plane[1]] * axes[in_plane[1]]
                        for sa in (-1, 1) for sb in (-1, 1)])
    rs, us = (corners - centre) @ r, (corners - centre) @ u
    lo_r, hi_r, lo_u, hi_u = rs.min(), rs.max(), us.min(), us.max()
    pictures = _pictures(program, pr.part)
    if pictures:
        pr_lo, pr_hi, pu_lo, pu_hi = np.inf, -np.inf, np.inf, -np.inf
        for p in pictures:
            c, ax, h = _box(p)
            pts = np.array([c + sx * h[0] * ax[0] + sy * h[1] * ax[1] + sz * h[2] * ax[2]
                            for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) - centre
            pr_lo, pr_hi = min(pr_lo, (pts @ r).min()), max(pr_hi, (pts @ r).max())
            pu_lo, pu_hi = min(pu_lo, (pts @ u).min()), max(pu_hi, (pts @ u).max())
        bands = [("u", pu_hi, hi_u), ("u", lo_u, pu_lo), ("r", pr_hi, hi_r), ("r", lo_r, pr_lo)]
        axis, a, b = max(bands, key=lambda t: t[2] - t[1])
        span = (hi_u - lo_u) if axis == "u" else (hi_r - lo_r)
        if b - a >= MIN_FREE_SHARE * span:
            if axis == "u":
                lo_u, hi_u = a, b
            else:
                lo_r, hi_r = a, b
    block_c = centre + 0.5 * (lo_r + hi_r) * r + 0.5 * (lo_u + hi_u) * u
    along, across = FACE_SHARE[0] * (hi_r - lo_r), FACE_SHARE[1] * (hi_u - lo_u)
    lines, letter = _lines(pr.text, along, across)
    mask = text_mask(pr.text, lines)
    k_px = letter / RASTER_PX
    return Placement(centre=block_c, r=r, u=u, n=n, half_r=0.5 * mask.shape[1] * k_px,
                     half_u=0.5 * mask.shape[0] * k_px, letter_m=letter, lines=lines,
                     face_level=float(np.dot(centre, n)))


def ink(points: np.ndarray, program: ShapeProgram, pr: Print, pl: Placement) -> np.ndarray:
    """Ink coverage in [0, 1] of the print at points (program frame), bilinear in its raster; 0 off its face."""
    rel = np.asarray(points, dtype=np.float64) - pl.centre
    a, b = rel @ pl.r, rel @ pl.u
    out = np.zeros(len(rel), np.float32)
    on = (np.abs(a) <= pl.half_r) & (np.abs(b) <= pl.half_u) & (np.asarray(points) @ pl.n > pl.face_level)
    if on.any():  # on the part's own surface or its pictures' (not on the pieces of a fill lying on it)
        idx = np.nonzero(on)[0]
        p = np.asarray(points, dtype=np.float64)[idx]
        near = np.min([np.abs(part_sdf(p, part)) for part in _inked_parts(program, pr.part)], axis=0)
        on[idx] = near <= max(SURFACE_SHARE * pl.letter_m, MIN_SURFACE_M)
    if not on.any():
        return out
    mask = text_mask(pr.text, pl.lines)
    h, w = mask.shape
    x = (a[on] + pl.half_r) / (2.0 * pl.half_r) * (w - 1)
    y = (pl.half_u - b[on]) / (2.0 * pl.half_u) * (h - 1)  # (rows from the top)
    x0, y0 = np.clip(np.floor(x).astype(int), 0, w - 2), np.clip(np.floor(y).astype(int), 0, h - 2)
    fx, fy = np.clip(x - x0, 0, 1), np.clip(y - y0, 0, 1)
    out[on] = (mask[y0, x0] * (1 - fx) * (1 - fy) + mask[y0, x0 + 1] * fx * (1 - fy)
               + mask[y0 + 1, x0] * (1 - fx) * fy + mask[y0 + 1, x0 + 1] * fx * fy)
    return out


DARK_INK, LIGHT_INK = np.array([0.01, 0.01, 0.012]), np.array([0.92, 0.92, 0.92])
LIGHT_SURFACE = 0.18  # a surface of more linear luminance than this takes dark ink, else light [-]


def ink_rgb(pr: Print, program: ShapeProgram, under: np.ndarray | None = None) -> np.ndarray:
    """The print's ink (linear RGB): its own; else, for each colour `under` it (N, 3), near-black on a light surface
    and white on a dark one (letters over a label's white picture on a blue label were white on white, development
    set 60); without `under`, against its part's colour."""
    if pr.color_rgb is not None:
        return np.asarray(pr.color_rgb, dtype=np.float64)
    if under is None:
        part = _part(program, pr.part)
        under = np.asarray([part.color_rgb if part is not None else (0.8, 0.8, 0.8)], dtype=np.float64)
    light = np.asarray(under, dtype=np.float64) @ np.array([0.2126, 0.7152, 0.0722]) > LIGHT_SURFACE
    return np.where(light[:, None], DARK_INK, LIGHT_INK)


FACING_COS = 0.5  # a surface turned further than 60 deg from a print's normal takes none of its ink (a picture's sides)


def printed_colors(points: np.ndarray, rgb: np.ndarray, program: ShapeProgram,
                   normals: np.ndarray | None = None) -> np.ndarray:
    """Linear RGB at points (program frame; with their outward normals, only those facing the print's way) with the
    program's prints inked over it."""
    out = np.asarray(rgb, dtype=np.float64).copy()
    for pr, pl in ((each, pl) for each in program.prints for pl in placements(program, each)):
        cover = ink(points, program, pr, pl)[:, None]
        if normals is not None:
            cover = cover * (np.asarray(normals) @ pl.n > FACING_COS)[:, None]
        out = out * (1.0 - cover) + np.broadcast_to(ink_rgb(pr, program, out), out.shape) * cover
    return out


def refine_under_prints(mesh: trimesh.Trimesh, program: ShapeProgram, spacing_m: float) -> trimesh.Trimesh:
    """The mesh with its faces under each print split (red-green: halved edges, neighbours closed so the mesh stays
    watertight) until their edges are about EDGE_PER_LETTER of the letters' height (at most MAX_LEVELS halvings)."""
    v, f = np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)
    for pl in (pl for pr in program.prints for pl in placements(program, pr)):
        levels = int(np.clip(np.ceil(np.log2(spacing_m / max(EDGE_PER_LETTER * pl.letter_m, 1e-9))), 0, MAX_LEVELS))
        for _ in range(levels):
            rel = v[f].mean(axis=1) - pl.centre
            near = (np.abs(rel @ pl.r) <= pl.half_r + spacing_m) & (np.abs(rel @ pl.u) <= pl.half_u + spacing_m) \
                & (v[f].mean(axis=1) @ pl.n > pl.face_level)
            if not near.any():
                break
            v, f = red_green(v, f, near)
    return trimesh.Trimesh(v, f, process=False)


def red_green(v: np.ndarray, f: np.ndarray, red: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One red-green refinement: the `red` faces split in four at their edges' midpoints, any face with two split
    edges made red too (repeated until none), a face with one split edge halved through it (green)."""
    edges = np.sort(f[:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1, 3)
    red = red.copy()
    while True:
        split = np.zeros(len(unique), bool)
        split[inverse[red].ravel()] = True
        count = split[inverse].sum(axis=1)
        grown = red | (count >= 2)
        if (grown == red).all():
            break
        red = grown
    mid = np.full(len(unique), -1, np.int64)
    ids = np.nonzero(split)[0]
    mid[ids] = len(v) + np.arange(len(ids))
    v = np.vstack([v, v[unique[ids]].mean(axis=1)])
    m = mid[inverse]  # (F, 3): the midpoint of edges (a, b), (b, c), (c, a), or -1
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    keep = f[count == 0]
    r = count == 3
    reds = np.concatenate([np.stack([a, m[:, 0], m[:, 2]], 1)[r], np.stack([m[:, 0], b, m[:, 1]], 1)[r],
                           np.stack([m[:, 2], m[:, 1], c], 1)[r], np.stack([m[:, 0], m[:, 1], m[:, 2]], 1)[r]])
    greens = []
    for e, (p0, p1) in enumerate((((a, m[:, 0], c), (m[:, 0], b, c)), ((a, b, m[:, 1]), (a, m[:, 1], c)),
                                  ((a, b, m[:, 2]), (m[:, 2], b, c)))):
        g = (count == 1) & (m[:, e] >= 0)
        greens += [np.stack(p0, 1)[g], np.stack(p1, 1)[g]]
    return v, np.concatenate([keep, reds, *greens]).astype(np.int64)
