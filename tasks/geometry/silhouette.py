"""Photo mask -> watertight, coloured mesh: a named object's parametric shape fitted to the silhouette, else a
generic reconstruction from the silhouette alone.

Method
- Frame: the mask's bounding box is cropped with a margin and resampled to `resolution` cells along its longest side
  (one unit); camera x = image right, camera z = image up, camera y = depth away from the camera (orthographic).
- Known object (the text, intent or file name names a program): `silhouette_fit.fit_program` picks the view (side,
  front, top), a left/right flip, per-axis scale and an in-plane tilt of the program's orthographic silhouette that
  maximise its IoU with the mask (bounding-box start, Nelder-Mead refinement); depth gets the geometric mean of the two
  fitted scales. The fitted program is then conformed to the photo: cut by the mask extruded along the view, and mask
  regions it does not cover are filled by the generic profile below. The IoU of the program alone is reported.
- Nothing known, or a template that fits with an IoU below MIN_FIT_IOU (0.8): a silhouette whose rows are each one
  run with their centres on one vertical axis (is_revolution: a bottle, a can, a cup, a fruit, a ball) becomes a
  solid of revolution about that axis, its radius per row the mean of the two half-widths, a tall one standing on a
  flat base (the ellipse of its bottom rim filled out); any other a closed inflation: at distance d from the outline,
  with rho the inscribed radius at the nearest medial-axis point, a rounded-box cross-section of depth rho whose
  edges round over 0.6 rho (limbs keep their own thickness), mirrored front to back, its resting rows continued below
  it while the depth is taken so it stands on a flat patch. Both are level sets: closed, never self-intersecting.
- Upright: the photo's vertical stays the object's z (the table it stands on is the ground); the view recorded is
  the fitted template's, else 'front' (the photo shows the object's front; 'side' for an asymmetric silhouette whose
  template fitted best from the side). The resting-pose step runs only on request (AssetRequest.pose='stable').
- Colours: surface points that face the camera and are not occluded take the photo's colour at their pixel; the hidden
  side takes the mean photo colour of each program part (known object) or a strongly blurred copy of the photo
  (generic), blended by how much the normal faces the camera, so nothing is smeared across the sides.

Limits
- One view: depth is a prior (the program's proportions, or round cross-sections), never measured; concavities seen
  face-on (a bowl from above) are filled, and the back is assumed symmetric to the front.
- Orthographic camera: strong perspective (a close-up) distorts proportions; the size comes from the text or
  --size-m, or the named object's typical size.
- The fit only scales, flips and tilts the whole program: articulated poses (a raised leg, a turned head) are taken
  from the mask by the conforming step, not by moving parts.
- The hidden side's colour is a guess: patterns on the back are not known.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
import trimesh
from pydantic import Field
from scipy import ndimage
from skimage.morphology import medial_axis

from contracts.base import Model
from contracts.shape import ShapeProgram
from tasks.geometry.meshing import linear_to_srgb8, mesh_from_field
from tasks.geometry.sdf import part_sdf, program_bounds, program_sdf, smooth_max, smooth_min
from tasks.geometry.silhouette_fit import FIT_CELLS, VIEW_ROTATION, ProgramFit, fit_program, fitted_silhouette

REVOLUTION_MAX_ASYMMETRY = 0.04  # row centres this far (90th percentile, x widest row) from one vertical axis [-]
REVOLUTION_MAX_MULTI_RUN = 0.03  # share of rows split in two or more runs (ears, legs, arms apart) a lathe allows [-]
REVOLUTION_END_TRIM = 0.04  # rows at the top and bottom left out of those two measures (segmentation ragged) [-]
LATHE_SMOOTH = 0.006  # the radius profile is smoothed over this share of the height (ragged mask rows) [-]
LATHE_FLAT_BASE_ASPECT = 1.2  # a lathe at least this tall for its width stands on a flat base [-]
LATHE_BASE_BAND = 0.15  # ... found within this share of its height from the bottom [-]
INFLATION_ROUNDNESS = 0.6  # edges of an inflated part rounded over this share of its inscribed radius [-]
GROUND_FOOT_BAND = 0.03  # an inflation rests on the rows within this share of its height from its lowest row [-]
GROUND_EXTEND = 0.25  # ... continued this far (x height) below it while its depth is taken [-]
LATHE_OVER_FIT_IOU = 0.9  # a template fitted below this gives way to a solid of revolution of the silhouette [-]
MIN_FIT_IOU = 0.8  # a program that fits worse than this is not what the photo shows: generic reconstruction [-]
FRONT_SYMMETRY_IOU = 0.85  # a silhouette built without a template is a front view above this mirror IoU [-]
FLAT_PROGRAM = 0.5  # a top view is fitted only to a program this flat (height / narrowest horizontal extent) [-]
RHO_SMOOTH_CELLS = 2.0  # smoothing of the medial radius map [cells]
BLEND_CELLS = 1.5  # smooth cut / union radius where the program meets the extruded mask and the filler [cells]
COLOUR_MAX_SIDE = 1024  # photos are reduced to at most this many pixels along a side for the reconstruction [px]
MAX_BEND = 2.0  # a line of the program is stretched or squeezed onto the mask's by at most this factor [-]
BEND_SMOOTH_CELLS = 2.0  # smoothing of those per-line maps along the lines [cells]
PAD_FRAC = 0.08  # margin around the mask's bounding box [-]
Vec3 = tuple[float, float, float]


class PhotoReconstruction(Model):
    """How a photo became a mesh, and where its camera is in the final frame."""

    method: str = Field(description="'program fit' | 'lathe' | 'medial-axis inflation'")
    entry: str | None = Field(default=None, description="named object whose program was fitted")
    view: str | None = Field(default=None, description="side | front | top: the program view that fitted best")
    fit_iou: float | None = Field(default=None, description="IoU of the fitted program's own silhouette with the "
                                  "mask (before it is bent onto the outline)")
    symmetry_iou: float = Field(description="IoU of the mask with its mirror image about a vertical axis")
    camera_right: Vec3 = Field(description="image right in the final frame (unit vector)")
    camera_up: Vec3 = Field(description="image up in the final frame (unit vector)")
    camera_forward: Vec3 = Field(description="viewing direction in the final frame (unit vector, away from the camera)")
    notes: list[str] = Field(default_factory=list)


@dataclass(frozen=True)
class PhotoFrame:
    """The cropped mask on a [x cell, z cell] grid and its mapping back to image pixels."""

    mask: np.ndarray
    cells: int  # cells per unit (the bounding box's longest side)
    left_px: float
    bottom_px: float
    unit_px: float

    def to_pixel(self, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Camera (x, z) [units] -> image (row, col) [px]."""
        return self.bottom_px - z * self.unit_px - 0.5, self.left_px + x * self.unit_px - 0.5


def photo_frame(mask: np.ndarray, cells: int) -> PhotoFrame:
    """Crop the mask with a margin and resample it to `cells` per unit on a [x, z] grid."""
    ys, xs = np.nonzero(mask)
    unit = float(max(ys.max() + 1 - ys.min(), xs.max() + 1 - xs.min()))
    pad = PAD_FRAC * unit + 2.0 * unit / cells
    left, top = xs.min() - pad, ys.min() - pad
    n_x = int(np.ceil((xs.max() + 1 - xs.min() + 2 * pad) / unit * cells))
    n_z = int(np.ceil((ys.max() + 1 - ys.min() + 2 * pad) / unit * cells))
    k = unit / cells
    m = np.array([[k, 0.0, left + 0.5 * k - 0.5], [0.0, k, top + 0.5 * k - 0.5]])
    img = cv2.warpAffine(mask.astype(np.float32), m, (n_x, n_z), flags=cv2.INTER_AREA | cv2.WARP_INVERSE_MAP)
    grid = (img[::-1].T >= 0.5)  # rows -> z up
    return PhotoFrame(mask=grid, cells=cells, left_px=float(left), bottom_px=float(top + n_z * k), unit_px=unit)


def mirror_symmetry(mask: np.ndarray) -> tuple[float, float]:
    """IoU of a [x, z] mask with its mirror about the vertical axis through its centroid, and that axis (cells)."""
    xs = np.nonzero(mask)[0]
    axis = float(xs.mean()) + 0.5
    idx = np.round(2 * axis - 1 - np.arange(mask.shape[0])).astype(int)
    ok = (idx >= 0) & (idx < mask.shape[0])
    mirrored = np.zeros_like(mask)
    mirrored[ok] = mask[idx[ok]]
    return float((mask & mirrored).sum() / max((mask | mirrored).sum(), 1)), axis


def medial_half_depth(mask: np.ndarray, roundness: float = 1.0) -> np.ndarray:
    """Half-depth [cells] of round cross-sections: sqrt(d (2 rho - d)), rho the nearest medial-axis radius; with
    roundness < 1 a fuller section, rho sqrt(1 - (1 - d / (roundness rho))^2): as deep, its edges rounded over
    roundness x rho (a cushion, a chair, a loaf are not lenses)."""
    skel, dist = medial_axis(np.pad(mask, 1), return_distance=True, rng=0)  # seeded tie-breaking: deterministic
    skel, dist = skel[1:-1, 1:-1], np.maximum(dist[1:-1, 1:-1] - 0.5, 0.0)
    d = np.maximum(ndimage.distance_transform_edt(mask) - 0.5, 0.0)  # to the outline, half a cell beyond the pixels
    if not skel.any():
        return d
    _, (ii, kk) = ndimage.distance_transform_edt(~skel, return_indices=True)
    rho = ndimage.grey_dilation(dist, size=3)[ii, kk]
    # the nearest skeleton point jumps between branches: smooth rho (inside the mask) so the surface has no terraces
    w = ndimage.gaussian_filter(mask.astype(np.float64), RHO_SMOOTH_CELLS)
    rho = ndimage.gaussian_filter(np.where(mask, rho, 0.0), RHO_SMOOTH_CELLS) / np.maximum(w, 1e-9)
    rho = np.maximum(rho, d)
    if roundness >= 1.0:
        return np.where(mask, np.sqrt(np.clip(d * (2.0 * rho - d), 0.0, None)), 0.0)
    # a rounded box: the circle's depth rho in the middle of a part, edges rounded over roundness x rho
    t = np.clip(d / np.maximum(roundness * rho, 1e-9), 0.0, 1.0)
    return np.where(mask, rho * np.sqrt(np.clip(1.0 - (1.0 - t) ** 2, 0.0, None)), 0.0)


def _grid(n_x: int, n_z: int, y_lo: float, y_hi: float, cells: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = (np.arange(n_x) + 0.5) / cells
    z = (np.arange(n_z) + 0.5) / cells
    n_y = int(np.ceil((y_hi - y_lo) * cells)) + 5
    y = y_lo - 2.0 / cells + np.arange(n_y) / cells
    return x, y, z


def _outline_field(mask: np.ndarray) -> np.ndarray:
    """Signed 2-D distance to the mask outline [cells], negative inside."""
    return np.where(mask, -ndimage.distance_transform_edt(mask) + 0.5, ndimage.distance_transform_edt(~mask) - 0.5)


@dataclass(frozen=True)
class Profile:
    """A silhouette read row by row (rows of constant z on a [x, z] grid): its left and right ends [cells], how many
    rows hold more than one run, and how well the rows share one vertical axis."""

    rows: np.ndarray  # z indices of the rows holding the mask
    left: np.ndarray  # first cell of each row
    right: np.ndarray  # one past the last cell of each row
    multi_run: float  # share of the rows (bar the ends) that hold more than one run [-]
    axis: float  # the shared vertical axis [cells]
    asymmetry: float  # 90th percentile of |row centre - axis| / widest row [-]


def row_profile(mask: np.ndarray) -> Profile:
    """The left/right profile of a [x, z] mask (see Profile)."""
    rows = np.flatnonzero(mask.any(axis=0))
    sub = mask[:, rows]
    left = np.argmax(sub, axis=0)
    right = sub.shape[0] - np.argmax(sub[::-1], axis=0)
    runs = (np.diff(sub.astype(np.int8), axis=0) == 1).sum(axis=0) + sub[0]
    trim = max(1, int(REVOLUTION_END_TRIM * len(rows)))
    core = slice(trim, len(rows) - trim) if len(rows) > 2 * trim + 2 else slice(None)
    centre = 0.5 * (left + right)
    axis = float(np.median(centre[core]))
    width = float((right - left).max())
    asym = float(np.percentile(np.abs(centre[core] - axis), 90)) / max(width, 1.0)
    return Profile(rows=rows, left=left, right=right, multi_run=float(np.mean(runs[core] > 1)), axis=axis,
                   asymmetry=asym)


def is_revolution(mask: np.ndarray) -> tuple[bool, Profile]:
    """True when the silhouette is that of a solid of revolution about a vertical axis (a bottle, a can, a cup, a
    fruit, a ball): every row one run (no limbs, ears or legs apart), the rows' centres on one vertical axis."""
    prof = row_profile(mask)
    ok = prof.multi_run <= REVOLUTION_MAX_MULTI_RUN and prof.asymmetry <= REVOLUTION_MAX_ASYMMETRY
    return bool(ok and len(prof.rows) >= 8), prof


def pixel_grid(mask: np.ndarray) -> np.ndarray:
    """An image mask [row, col] as a [x, z] grid (x right, z up) in pixels."""
    return np.ascontiguousarray(mask.T[:, ::-1])


def lathe_field(frame: PhotoFrame, pix: np.ndarray, prof: Profile) -> tuple[np.ndarray, np.ndarray]:
    """Field [x, y, z] (cells, negative inside) of the solid of revolution about the profile's vertical axis with the
    mean of the two half-widths as radius per row (the profile `prof` of the photo's mask `pix` [x, z] in pixels,
    sampled at the frame's cells); a tall object's base (the ellipse its bottom rim makes in a photo taken from above
    the table) is filled out to the rim's radius, so it stands on a flat base. Also the camera-y coordinates [units]."""
    height = len(prof.rows)
    radius_px = ndimage.gaussian_filter1d(0.5 * (prof.right - prof.left).astype(np.float64),
                                          max(1.0, LATHE_SMOOTH * height), mode="nearest")
    if height >= LATHE_FLAT_BASE_ASPECT * 2.0 * radius_px.max():
        band = max(2, int(LATHE_BASE_BAND * height))
        r_band = radius_px[:band]
        reach = int(np.argmax(r_band >= 0.95 * r_band.max()))  # the rim: where the base ellipse is widest
        radius_px[:reach] = r_band[reach]
    cells = frame.cells
    n_x, n_z = frame.mask.shape
    z_units = (np.arange(n_z) + 0.5) / cells
    z_pix = (pix.shape[1] - 1) - (frame.bottom_px - z_units * frame.unit_px - 0.5)  # pixel row, counted from the bottom
    inside = (z_pix >= prof.rows[0] - 0.5) & (z_pix <= prof.rows[-1] + 0.5)
    radius = np.where(inside, np.interp(z_pix, prof.rows, radius_px), -1.0) / frame.unit_px * cells
    axis = (prof.axis - frame.left_px) / frame.unit_px * cells  # the axis' x [cells]
    r_max = float(radius.max())
    x, y, z = _grid(n_x, n_z, -r_max / cells, r_max / cells, cells)
    dx = (np.arange(n_x) + 0.5 - axis)[:, None, None]
    dy = (y * cells)[None, :, None]
    field = np.sqrt(dx**2 + dy**2) - radius[None, None, :]
    # caps: the rows above the top and below the base are outside
    cap = np.where(inside, -np.inf, 1.0)
    lo, hi = np.flatnonzero(inside)[[0, -1]]
    cap = np.maximum(lo - 0.5 - np.arange(n_z), np.arange(n_z) - hi - 0.5) if inside.any() else cap
    field = np.maximum(field, cap[None, None, :])
    return field, y


def grounded_half_depth(mask: np.ndarray) -> np.ndarray:
    """medial_half_depth of a mask that stands on the table: the rows it rests on are continued below it before the
    depth is taken, so its base is as thick as the rows above it (a flat contact patch, not a knife edge)."""
    rows = np.flatnonzero(mask.any(axis=0))
    z0 = int(rows[0])
    height = int(rows[-1]) + 1 - z0
    foot: np.ndarray = np.asarray(mask[:, z0 : z0 + max(1, int(GROUND_FOOT_BAND * height))].any(axis=1))
    ext = max(2, int(GROUND_EXTEND * height))
    grown = np.zeros((mask.shape[0], mask.shape[1] + ext), bool)
    grown[:, ext:] = mask
    grown[:, : ext + z0] |= foot[:, None]
    half: np.ndarray = medial_half_depth(grown, INFLATION_ROUNDNESS)
    return half[:, ext:] * mask


def generic_field(frame: PhotoFrame, pix: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, str, float]:
    """Field [x, y, z] in cells (negative inside), y axis coordinates [units], method and mirror IoU: a solid of
    revolution about the vertical axis when the silhouette is one (is_revolution, judged on the photo's mask `pix`
    [x, z] in pixels, else on the frame's), else a closed inflation with round cross-sections per part (limbs stay
    limbs), mirrored front to back, standing on a flat base."""
    m = frame.mask
    sym, _ = mirror_symmetry(m)
    cells = frame.cells
    if pix is None:
        pix = m
        frame = PhotoFrame(mask=m, cells=cells, left_px=0.0, bottom_px=float(m.shape[1]), unit_px=float(cells))
    lathe, prof = is_revolution(pix)
    if lathe:
        field, y = lathe_field(frame, pix, prof)
        return field, y, "lathe", sym
    half = grounded_half_depth(m)
    h_max = float(half.max())
    x, y, z = _grid(m.shape[0], m.shape[1], -h_max / cells, h_max / cells, cells)
    height = np.where(m, half, 0.5 - ndimage.distance_transform_edt(~m))
    field = np.abs(y * cells)[None, :, None] - height[:, None, :]
    return field, y, "medial-axis inflation", sym


def fitted_field(frame: PhotoFrame, program: ShapeProgram, fit: ProgramFit) -> tuple[np.ndarray, np.ndarray]:
    """The fitted program, bent row- and column-wise onto the mask's outline, cut by the extruded mask, and the mask
    it still leaves uncovered filled by the generic profile [cells]."""
    m = frame.mask
    cells = frame.cells
    cam_y = (_program_box(program) @ fit.matrix().T)[:, 1]
    x, y, z = _grid(m.shape[0], m.shape[1], float(cam_y.min()), float(cam_y.max()), cells)
    ii, kk = np.meshgrid(np.arange(len(x)) + 0.5, np.arange(len(z)) + 0.5, indexing="ij")  # cell coordinates

    cover = fitted_silhouette(program, fit, m.shape, cells)
    # columns: the program's vertical extent onto the mask's; then rows: its horizontal extent onto the mask's
    a, b = _extent_map(cover, m)
    cover_v = ndimage.map_coordinates(cover.astype(np.float32), [ii - 0.5, a[:, None] * kk + b[:, None] - 0.5],
                                      order=1) > 0.5
    c, d = _extent_map(cover_v.T, m.T)
    xi = c[None, :] * ii + d[None, :]
    zi = np.interp(xi, ii[:, 0], a) * kk + np.interp(xi, ii[:, 0], b)
    # the program's distance [cells] at the bent coordinates, in the columns near the mask (the cut decides elsewhere)
    near = ndimage.binary_dilation(m, iterations=int(np.ceil(BLEND_CELLS)) + 2)
    prog = np.empty((len(x), len(z), len(y)))  # [x, z, y] here, so the 2-D selection indexes whole lines of sight
    pts = np.stack(np.broadcast_arrays(xi[near][:, None] / cells, y[None, :], zi[near][:, None] / cells), axis=-1)
    prog[near] = (program_sdf(fit.to_program(pts.reshape(-1, 3)), program) * min(fit.scale) * cells).reshape(-1, len(y))
    prog[~near] = _outline_field(m)[~near][:, None] + BLEND_CELLS
    prog = prog.transpose(0, 2, 1)
    covered = (prog < 0).any(axis=1)
    carved = smooth_max(prog, _outline_field(m)[:, None, :], BLEND_CELLS)
    # the generic profile where the program leaves the mask uncovered (fading out under the program's silhouette)
    gap = ndimage.gaussian_filter((m & ~covered).astype(np.float64), 1.0) * m
    half = medial_half_depth(m) * np.clip(2.0 * gap, 0.0, 1.0)
    y_mid = 0.5 * (cam_y.min() + cam_y.max()) * cells
    height = np.where(half > 0.3, half, -0.5 - ndimage.distance_transform_edt(half <= 0.3))
    filler = np.abs(y * cells - y_mid)[None, :, None] - height[:, None, :]
    return smooth_min(carved, filler, BLEND_CELLS), y


def _extent_map(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per line i of two [i, k] masks: (a, b) with k_src = a k_dst + b taking dst's extent along k onto src's;
    lines where either is empty take their nearest line's map; the maps are smoothed along i [cells]."""
    n = src.shape[0]
    a, b, ok = np.ones(n), np.zeros(n), np.zeros(n, bool)
    for i in range(n):
        s, t = np.flatnonzero(src[i]), np.flatnonzero(dst[i])
        if len(s) and len(t):
            scale = (s[-1] + 1 - s[0]) / (t[-1] + 1 - t[0])
            if 1.0 / MAX_BEND <= scale <= MAX_BEND:
                a[i], b[i], ok[i] = scale, s[0] - scale * t[0], True
    if not ok.any():
        return np.ones(n), np.zeros(n)
    _, near = ndimage.distance_transform_edt(~ok, return_indices=True)
    a, b = a[near[0]], b[near[0]]
    return ndimage.gaussian_filter1d(a, BEND_SMOOTH_CELLS), ndimage.gaussian_filter1d(b, BEND_SMOOTH_CELLS)


def _program_box(program: ShapeProgram) -> np.ndarray:
    b = program_bounds(program)
    return np.array([[b[i][0], b[j][1], b[k][2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])


def _colours(mesh: trimesh.Trimesh, frame: PhotoFrame, image: np.ndarray, photo_mask: np.ndarray,
             front_y: np.ndarray, hidden: np.ndarray) -> np.ndarray:
    """RGBA: the photo where the surface faces the camera and is the front-most, `hidden` (N, 3) uint8 elsewhere."""
    v = mesh.vertices
    row, col = frame.to_pixel(v[:, 0], v[:, 2])
    photo = sample_photo(image, photo_mask, row, col, 0.0)
    ix = np.clip((v[:, 0] * frame.cells).astype(int), 0, front_y.shape[0] - 1)
    iz = np.clip((v[:, 2] * frame.cells).astype(int), 0, front_y.shape[1] - 1)
    in_front = v[:, 1] <= front_y[ix, iz] + 2.0 / frame.cells
    facing = np.clip((-mesh.vertex_normals[:, 1] - 0.05) / 0.35, 0.0, 1.0) * in_front
    rgb = facing[:, None] * photo + (1.0 - facing[:, None]) * hidden
    out = np.full((len(v), 4), 255, np.uint8)
    out[:, :3] = np.clip(np.round(rgb), 0, 255).astype(np.uint8)
    return out


def sample_photo(image: np.ndarray, mask: np.ndarray, rows: np.ndarray, cols: np.ndarray, blur_px: float) -> np.ndarray:
    """(N, 3) float RGB from the object's pixels (background replaced by the nearest object pixel, then blurred)."""
    rgb = image[:, :, :3]
    _, (ir, ic) = ndimage.distance_transform_edt(~mask, return_indices=True)
    filled = rgb[ir, ic].astype(np.float32)
    filled = cv2.GaussianBlur(filled, (0, 0), max(blur_px, 0.8))
    r = np.clip(np.round(rows).astype(int), 0, mask.shape[0] - 1)
    c = np.clip(np.round(cols).astype(int), 0, mask.shape[1] - 1)
    return filled[r, c].astype(np.float64)


def _front_depth(field: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Camera y of the first inside sample along each line of sight [units] (+inf where none)."""
    inside = field < 0
    first = np.argmax(inside, axis=1)
    return np.where(inside.any(axis=1), y[first], np.inf)


def reconstruct(mask: np.ndarray, image: np.ndarray, longest_m: float, resolution: int,
                program: ShapeProgram | None = None, entry: str | None = None
                ) -> tuple[trimesh.Trimesh, PhotoReconstruction]:
    """Watertight coloured mesh [m] of the masked object; camera frame (x right, y away, z up) turned so that a fitted
    program stands upright."""
    h, w = mask.shape
    if max(h, w) > COLOUR_MAX_SIDE:  # colours and the mask need no more pixels than this (keeps the EDTs cheap)
        k = COLOUR_MAX_SIDE / max(h, w)
        size = (max(8, round(w * k)), max(8, round(h * k)))
        image = cv2.resize(np.ascontiguousarray(image), size, interpolation=cv2.INTER_AREA)
        mask = cv2.resize(mask.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST).astype(bool)
    frame = photo_frame(mask, resolution)
    sym, _ = mirror_symmetry(frame.mask)
    notes: list[str] = []
    fit = rejected = None
    if program is not None:
        fit = fit_program(program, photo_frame(mask, FIT_CELLS).mask, views=_views(program))
        if fit.iou < MIN_FIT_IOU:
            notes.append(f"the photo's silhouette does not fit a '{entry}' template well enough (best IoU "
                         f"{fit.iou:.2f} < {MIN_FIT_IOU}, {fit.view} view): built from the silhouette instead")
            fit, rejected = None, fit
    lathe = None
    if fit is not None and fit.iou < LATHE_OVER_FIT_IOU:  # a symmetric silhouette's solid of revolution is exact
        lathe = generic_field(frame, pixel_grid(mask))
        if lathe[2] == "lathe":
            notes.append(f"the silhouette is a solid of revolution, which fits it better than the '{entry}' template "
                         f"(IoU {fit.iou:.2f}): built as one")
            fit = None
        else:
            lathe = None
    if fit is not None:
        field, y = fitted_field(frame, program, fit)  # type: ignore[arg-type]
        method, view = "program fit", fit.view
    elif lathe is not None:
        field, y, method, sym = lathe
        view = "front"
    else:
        field, y, method, sym = generic_field(frame, pixel_grid(mask))
        # the photo shows the object's front, unless a template seen from the side fitted best and the silhouette
        # has no left/right symmetry (a cat in profile)
        view = "side" if rejected is not None and rejected.view == "side" and sym < FRONT_SYMMETRY_IOU else "front"
    spacing = 1.0 / frame.cells
    mesh = mesh_from_field(field, np.array([0.5 * spacing, float(y[0]), 0.5 * spacing]), spacing, level=0.0)
    front = _front_depth(field, y)
    if fit is not None:
        hidden = _part_means(mesh, frame, image, mask, front, program, fit)  # type: ignore[arg-type]
    else:
        row, col = frame.to_pixel(mesh.vertices[:, 0], mesh.vertices[:, 2])
        hidden = sample_photo(image, mask, row, col, 0.12 * frame.unit_px)
    colors = _colours(mesh, frame, image, mask, front, hidden)
    mesh.vertices = mesh.vertices * longest_m
    # camera -> the object's frame: z up (the photo's vertical), the view recorded (a photo of the object's front is
    # seen by the 'front' render, from +x), a fitted program in its own frame
    upright = VIEW_ROTATION[view].T
    mesh.vertices = mesh.vertices @ upright.T
    mesh.visual = trimesh.visual.ColorVisuals(mesh, vertex_colors=colors)
    cam = upright @ np.eye(3)
    info = PhotoReconstruction(
        method=method, entry=entry if fit is not None else None, view=view,
        fit_iou=round(fit.iou, 4) if fit else None, symmetry_iou=round(sym, 4),
        camera_right=tuple(cam[:, 0]), camera_up=tuple(cam[:, 2]), camera_forward=tuple(cam[:, 1]), notes=notes)
    return mesh, info


def _views(program: ShapeProgram) -> tuple[str, ...]:
    """The views a program may be fitted in: a top view only for a flat one (a disc, a mat, a slice: photographed from
    above), so a standing object is never laid down to match a photo taken from the side."""
    lo, hi = program_bounds(program)
    ext = np.asarray(hi) - np.asarray(lo)
    flat = ext[2] <= FLAT_PROGRAM * min(ext[0], ext[1])
    return ("side", "front", "top") if flat else ("side", "front")


def _twin(name: str) -> str:
    """'left ear' <-> 'right ear' (the name itself when it has no side)."""
    for a, b in (("left", "right"), ("right", "left")):
        if a in name.split():
            return " ".join(b if w == a else w for w in name.split())
    return name


def _part_means(mesh: trimesh.Trimesh, frame: PhotoFrame, image: np.ndarray, mask: np.ndarray, front: np.ndarray,
                program: ShapeProgram, fit: ProgramFit) -> np.ndarray:
    """Hidden-side colour per vertex: the mean photo colour of the visible surface of its program part (the part's
    own colour where none of it is visible); vertices outside every part take the mean of the whole visible side."""
    v = mesh.vertices
    local = fit.to_program(v)
    d = np.stack([np.abs(part_sdf(local, p)) for p in program.parts], axis=1)
    label = d.argmin(axis=1)
    row, col = frame.to_pixel(v[:, 0], v[:, 2])
    photo = sample_photo(image, mask, row, col, 0.0)
    ix = np.clip((v[:, 0] * frame.cells).astype(int), 0, front.shape[0] - 1)
    iz = np.clip((v[:, 2] * frame.cells).astype(int), 0, front.shape[1] - 1)
    visible = (mesh.vertex_normals[:, 1] < -0.3) & (v[:, 1] <= front[ix, iz] + 2.0 / frame.cells)
    overall = photo[visible].mean(axis=0) if visible.any() else photo.mean(axis=0)
    own = linear_to_srgb8(np.array([p.color_rgb for p in program.parts]))[:, :3].astype(np.float64)
    means: dict[int, np.ndarray] = {}
    for i in range(len(program.parts)):
        vis = (label == i) & visible
        if vis.sum() >= 5:
            means[i] = photo[vis].mean(axis=0)
    names = [p.name for p in program.parts]
    out = np.empty_like(photo)
    for i, name in enumerate(names):
        twin = _twin(name)
        j = names.index(twin) if twin in names else -1
        # seen: its mean; hidden: its seen twin's ('left ear' <-> 'right ear'); else the program's own colour
        out[label == i] = means.get(i, means.get(j, own[i]))
    far = d.min(axis=1) * min(fit.scale) > 3.0 / frame.cells  # filler regions, away from any part
    out[far] = overall
    return out


def follow_camera(info: PhotoReconstruction, before: np.ndarray, after: np.ndarray) -> PhotoReconstruction:
    """The camera axes carried through the linear map that took the vertices `before` to `after` (same order)."""
    b = before - before.mean(axis=0)
    a = after - after.mean(axis=0)
    lin, *_ = np.linalg.lstsq(b, a, rcond=None)  # after = before @ lin

    def carry(v: Vec3) -> Vec3:
        w = np.asarray(v) @ lin
        return tuple(float(c) for c in w / np.linalg.norm(w))  # type: ignore[return-value]

    return info.model_copy(update={"camera_right": carry(info.camera_right), "camera_up": carry(info.camera_up),
                                   "camera_forward": carry(info.camera_forward)})


def silhouette_iou(vertices: np.ndarray, faces: np.ndarray, info: PhotoReconstruction, mask: np.ndarray,
                   cells: int = 256) -> float:
    """IoU of a mesh's orthographic silhouette from the photo's camera with the photo's mask, after matching their
    bounding boxes' centres and longest sides (one uniform scale: proportions are not fitted here)."""
    ys, xs = np.nonzero(mask)
    unit = float(max(ys.max() + 1 - ys.min(), xs.max() + 1 - xs.min()))
    ctr = np.array([(xs.min() + xs.max() + 1) / 2.0, (ys.min() + ys.max() + 1) / 2.0])
    size = int(cells * 1.3)
    k = cells / unit
    m = np.array([[k, 0.0, size / 2.0 - k * ctr[0]], [0.0, k, size / 2.0 - k * ctr[1]]])
    target = cv2.warpAffine(mask.astype(np.float32), m, (size, size), flags=cv2.INTER_AREA) >= 0.5
    uv = np.stack([vertices @ np.asarray(info.camera_right), -(vertices @ np.asarray(info.camera_up))], axis=1)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    px = (uv - (lo + hi) / 2.0) * (cells / float((hi - lo).max())) + size / 2.0
    drawn = np.zeros((size, size), np.uint8)
    tris = np.round(px[faces] * 16).astype(np.int32)
    for tri in tris:  # one by one: fillPoly's even-odd rule would cancel overlapping front and back faces
        cv2.fillConvexPoly(drawn, tri, 1, lineType=cv2.LINE_8, shift=4)
    got = drawn.astype(bool)
    return float((got & target).sum() / max((got | target).sum(), 1))
