"""Marching cubes: signed-distance / occupancy fields -> watertight, outward-oriented triangle meshes."""

from __future__ import annotations

import numpy as np
import trimesh
from skimage.measure import marching_cubes

from contracts.errors import InputError
from contracts.shape import ShapeProgram
from tasks.geometry import prints
from tasks.geometry.sdf import grid_program_sdf, part_colors, program_bounds

_CHUNK = 1_000_000
# a slender object (a pool noodle, a rope) keeps at least this many cells across its middle extent, up to
# MAX_RESOLUTION_FACTOR x the resolution along its longest (64 cells along a 1.5 m noodle left 2.7 across it)
MIN_CELLS_ACROSS = 12
MAX_RESOLUTION_FACTOR = 4
COLOR_SHARPNESS = 0.6  # how far apart parts blend their colours on the surface / the grid spacing (a label or an eye
# raised less than ~2 of these takes its neighbour's colour) [-]
_LEVEL_NUDGE = 1e-3  # field samples closer to the level than this x the largest step across it are moved off it [-]


def mesh_from_field(field: np.ndarray, origin: np.ndarray, spacing: float, level: float = 0.0,
                    one_body: bool = True) -> trimesh.Trimesh:
    """Closed mesh of {field < level}; the field is padded with 'outside' so the surface always closes.
    one_body: keep only the largest body (marching cubes can leave specks); False keeps every body."""
    padded = np.pad(np.asarray(field, dtype=np.float64), 1, mode="constant", constant_values=max(level, 0.0) + spacing)
    if not (padded.min() < level < padded.max()):
        raise InputError("the shape has no volume (no inside region at this resolution)")
    # A sample within a hair of the level puts the surface vertices of every edge leaving it on top of each other
    # (nanometres apart); merging them then pinches the surface into non-manifold edges (a 6 cm heart drawing lost
    # watertightness this way). Such samples count as outside, nudged off the level by a small fraction of the
    # largest field step across the surface, so every vertex lies >= ~1e-3 of a cell from the grid nodes.
    nudge = _LEVEL_NUDGE * _crossing_step(padded, level)
    padded = np.where(np.abs(padded - level) < nudge, level + nudge, padded)
    verts, faces, _, _ = marching_cubes(padded, level=level, spacing=(spacing,) * 3, allow_degenerate=False)
    verts = verts + np.asarray(origin, dtype=np.float64) - spacing
    mesh = trimesh.Trimesh(verts, faces, process=True)
    mesh.merge_vertices()
    mesh = orient_outward(mesh)
    return largest_body(mesh) if one_body else mesh


def _crossing_step(field: np.ndarray, level: float) -> float:
    """Largest |difference| between neighbouring samples on opposite sides of the level (field units)."""
    inside = field < level
    step = 0.0
    for ax in range(field.ndim):
        d = np.abs(np.diff(field, axis=ax))
        cross = np.diff(inside, axis=ax)
        if cross.any():
            step = max(step, float(d[cross].max()))
    return step


def orient_outward(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Flip faces so that the enclosed volume is positive."""
    if mesh.is_watertight and mesh.volume < 0:
        mesh.invert()
    return mesh


def largest_body(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Keep the connected body with the largest volume (marching cubes can leave specks)."""
    return split_largest(mesh)[0]


def split_largest(mesh: trimesh.Trimesh) -> tuple[trimesh.Trimesh, int, float]:
    """The connected body with the largest volume, how many others there are, and their share of the volume [-]
    (a body that is not watertight counts as no volume)."""
    if mesh.body_count <= 1:
        return mesh, 0, 0.0
    bodies = mesh.split(only_watertight=False)
    vols = np.array([abs(b.volume) if b.is_watertight else 0.0 for b in bodies])
    keep = int(np.argmax(vols))
    total = float(vols.sum())
    return bodies[keep], len(bodies) - 1, (1.0 - float(vols[keep]) / total) if total > 0 else 0.0


def sample_program(program: ShapeProgram, resolution: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Signed distances of a program on a grid with `resolution` cells along its longest extent."""
    bounds = program_bounds(program)
    size = bounds[1] - bounds[0]
    spacing = float(size.max()) / resolution
    origin = bounds[0] - 2.0 * spacing
    shape = tuple(int(n) for n in np.ceil(size / spacing).astype(int) + 5)
    axes = [origin[i] + spacing * np.arange(shape[i]) for i in range(3)]
    step = max(1, _CHUNK // (shape[1] * shape[2]))  # slabs of x of about _CHUNK points (bounds the temporaries)
    d = np.concatenate([grid_program_sdf([axes[0][i : i + step], axes[1], axes[2]], program)
                        for i in range(0, shape[0], step)])
    return d, origin, spacing



def solid_bounds(program: ShapeProgram, resolution: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) corners [m] of the solid a program describes, from its signed distances on a grid (its parts' boxes
    overstate blends, turns and cuts); a solid thinner than a cell (a film) is its primitives' bounds."""
    field_, origin, spacing = sample_program(program, resolution)
    idx = np.argwhere(field_ < 0)
    if idx.size == 0:
        lo, hi = program_bounds(program)
        return np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    return origin + idx.min(axis=0) * spacing, origin + (idx.max(axis=0) + 1) * spacing


VOLUME_CELLS_ACROSS = 8  # cells across its thinnest extent when a body slips between a coarse grid's points [-]
MESH_CELLS_ACROSS = 3  # the same, for its mesh [-]
MAX_THIN_RESOLUTION = 600  # the most cells along the longest extent for that finer grid [-]


def thin_resolution(program: ShapeProgram, resolution: int, cells_across: int) -> int:
    """Cells along the longest extent that put `cells_across` cells across the thinnest one (more than
    `resolution`, at most MAX_THIN_RESOLUTION)."""
    lo, hi = program_bounds(program)
    size = np.sort(np.asarray(hi) - np.asarray(lo))
    across = int(np.ceil(cells_across * size[2] / max(float(size[0]), 1e-12)))  # longest / thinnest
    return min(MAX_THIN_RESOLUTION, max(resolution + 1, across))


def sample_solid(program: ShapeProgram, resolution: int, cells_across: int) -> tuple[np.ndarray, np.ndarray, float]:
    """sample_program, sampled again finer (thin_resolution) when no grid point falls inside the body: a body
    thinner than a cell (a deflated air mattress: 4 cm thick, 2.3 m long; its volume was 0, its density a division
    by zero and its mesh an error)."""
    field, origin, spacing = sample_program(program, resolution)
    if not (field < 0).any():
        field, origin, spacing = sample_program(program, thin_resolution(program, resolution, cells_across))
    return field, origin, spacing


def program_volume(program: ShapeProgram, resolution: int = 40) -> float:
    """The volume of the solid a program describes [m^3], from its signed distances on a grid (a finer one for a
    body thinner than a cell: sample_solid)."""
    field_, _origin, spacing = sample_solid(program, resolution, VOLUME_CELLS_ACROSS)
    return float(np.count_nonzero(field_ < 0)) * spacing ** 3

def slender_resolution(program: ShapeProgram, resolution: int) -> int:
    """Cells along the longest extent that leave MIN_CELLS_ACROSS across the middle one (at most
    MAX_RESOLUTION_FACTOR x resolution; a sheet's thin side is not counted)."""
    size = np.sort(program_bounds(program)[1] - program_bounds(program)[0])
    wanted = int(np.ceil(MIN_CELLS_ACROSS * size[2] / max(float(size[1]), 1e-12)))
    return min(MAX_RESOLUTION_FACTOR * resolution, max(resolution, wanted))


def mesh_program(program: ShapeProgram, resolution: int) -> trimesh.Trimesh:
    """Watertight, vertex-coloured mesh of a shape program (program frame, metres); `resolution` cells along its
    longest extent, more for a slender one (slender_resolution)."""
    field, origin, spacing = sample_solid(program, slender_resolution(program, resolution), MESH_CELLS_ACROSS)
    mesh = mesh_from_field(field, origin, spacing)
    if program.prints:  # (fine enough under the words to carry them in its vertex colours)
        mesh = prints.refine_under_prints(mesh, program, spacing)
    rgb = part_colors(mesh.vertices, program, sharpness_m=COLOR_SHARPNESS * spacing)
    if program.prints:
        rgb = prints.printed_colors(mesh.vertices, rgb, program, mesh.vertex_normals)
    mesh.visual = trimesh.visual.ColorVisuals(mesh, vertex_colors=linear_to_srgb8(rgb))
    if program.target_extent_m is not None:
        scale_to_extents(mesh, np.asarray(program.target_extent_m, dtype=np.float64))
    return mesh


def scale_to_extents(mesh: trimesh.Trimesh, extents: np.ndarray) -> None:
    """Scale a mesh per axis about its bounding-box centre so its extents equal `extents` [m] (in place)."""
    centre = mesh.bounds.mean(axis=0)
    factors = np.asarray(extents, dtype=np.float64) / mesh.extents
    mesh.vertices = (mesh.vertices - centre) * factors + centre


def linear_to_srgb8(rgb: np.ndarray) -> np.ndarray:
    """Linear RGB in [0, 1] -> sRGB uint8 RGBA."""
    c = np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    out = np.full((len(c), 4), 255, dtype=np.uint8)
    out[:, :3] = np.round(s * 255).astype(np.uint8)
    return out
