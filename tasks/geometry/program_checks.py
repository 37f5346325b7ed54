"""Contract checks of a proposed ShapeProgram before meshing: finite numbers, part count and sizes, one body."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy import ndimage

from contracts.shape import Part, ShapeProgram
from contracts.shape_design import ShapeBounds
from tasks.geometry.sdf import part_sdf, program_bounds, program_sdf


def _non_finite(value: Any, path: str) -> list[str]:
    """Paths of the non-finite numbers in a dumped model."""
    if isinstance(value, float):
        return [] if math.isfinite(value) else [path]
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in _non_finite(v, f"{path}.{k}" if path else str(k))]
    if isinstance(value, (list, tuple)):
        return [p for i, v in enumerate(value) for p in _non_finite(v, f"{path}[{i}]")]
    return []


def _dimensions(part: Part) -> dict[str, float]:
    """The primitive's size parameters that must lie in the contract's part-size range (zeros allowed are left out)."""
    prim = part.primitive
    dims: dict[str, float] = {}
    for name, value in prim.model_dump().items():
        if not name.endswith("_m") or name == "edge_radius_m":
            continue
        values = value if isinstance(value, (list, tuple)) else [value]
        for i, v in enumerate(values):
            if name in ("length_m", "radius_bottom_m", "radius_top_m") and v == 0:
                continue  # a sphere-capsule, a pointed cone
            dims[f"{name}[{i}]" if len(values) > 1 else name] = float(v)
    return dims


def _edge_problem(part: Part) -> str | None:
    """Rounding radii larger than the primitive can hold."""
    prim = part.primitive
    edge = getattr(prim, "edge_radius_m", 0.0)
    if prim.kind == "rounded_box" and edge > 0.5 * min(prim.size_m):
        return f"edge_radius_m {edge:g} m exceeds half its smallest size {0.5 * min(prim.size_m):g} m"
    if prim.kind == "cylinder" and edge > min(prim.radius_m, 0.5 * prim.height_m):
        return f"edge_radius_m {edge:g} m exceeds its radius or half height"
    if prim.kind == "cone" and edge > 0.5 * prim.height_m:
        return f"edge_radius_m {edge:g} m exceeds half its height"
    if prim.kind == "torus" and prim.minor_radius_m > prim.major_radius_m:
        return f"minor_radius_m {prim.minor_radius_m:g} m exceeds major_radius_m {prim.major_radius_m:g} m"
    return None


def _part_problems(i: int, part: Part, b: ShapeBounds, max_extent: float) -> list[str]:
    label = f"part {i} '{part.name}'"
    out = []
    lo, hi = b.part_size_m
    for name, v in _dimensions(part).items():
        if not lo <= v <= hi:
            out.append(f"{label}: {part.primitive.kind} {name} = {v:g} m is outside [{lo:g}, {hi:g}] m")
    if (edge := _edge_problem(part)) is not None:
        out.append(f"{label}: {edge}")
    slo, shi = b.part_scale
    if any(not slo <= s <= shi for s in part.transform.scale):
        out.append(f"{label}: transform.scale {list(part.transform.scale)} outside [{slo:g}, {shi:g}]")
    if any(abs(t) > max_extent for t in part.transform.translation_m):
        out.append(f"{label}: translation_m {list(part.transform.translation_m)} is farther than {max_extent:g} m "
                   "from the origin")
    if part.blend_m > b.max_blend_m:
        out.append(f"{label}: blend_m {part.blend_m:g} m exceeds {b.max_blend_m:g} m")
    if any(not 0.0 <= c <= 1.0 for c in part.color_rgb):
        out.append(f"{label}: color_rgb {list(part.color_rgb)} must be linear RGB in [0, 1]")
    return out


def one_body_problem(program: ShapeProgram, b: ShapeBounds) -> str | None:
    """Why the parts do not form one solid body (sampled on a coarse grid), naming the detached parts."""
    bounds = program_bounds(program)
    size = bounds[1] - bounds[0]
    h = float(size.max()) / b.check_resolution
    axes = [np.arange(bounds[0][k] - h, bounds[1][k] + 1.5 * h, h) for k in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    inside = (program_sdf(pts, program) < 0).reshape(tuple(len(a) for a in axes))
    if not inside.any():
        return f"the program encloses no volume (nothing inside at {h * 1000:.3g} mm sampling)"
    labels, n = ndimage.label(inside)
    if n <= 1:
        return None
    counts = np.bincount(labels.ravel())[1:]
    main = int(np.argmax(counts)) + 1
    share = 1.0 - counts[main - 1] / counts.sum()
    if share <= b.max_detached_share:
        return None
    flat = labels.ravel()
    detached = []
    for i, part in enumerate(program.parts):
        if part.operation != "union" and i > 0:
            continue
        own = (part_sdf(pts, part) < 0) & (flat > 0)
        if own.any() and np.mean(flat[own] == main) < 0.5:
            detached.append(f"{i} '{part.name}'")
    who = f"; detached parts: {', '.join(detached)}" if detached else ""
    return (f"the parts form {n} separate bodies ({100 * share:.2g} % of the volume outside the largest); every union "
            f"part must overlap the body built before it{who}")


def program_problems(program: ShapeProgram, bounds: ShapeBounds) -> list[str]:
    """Every way a program breaks the L0 contract's shape bounds (empty when it may be meshed)."""
    bad = _non_finite(program.model_dump(mode="python"), "")
    if bad:
        return [f"non-finite numbers at {', '.join(bad[:6])}"]
    out = []
    if len(program.parts) > bounds.max_parts:
        out.append(f"{len(program.parts)} parts; at most {bounds.max_parts}")
    if program.parts[0].operation != "union":
        out.append(f"the first part must be a union, not '{program.parts[0].operation}' (it is the body the others "
                   "change)")
    hi = bounds.extent_m[1]
    if program.target_extent_m is not None and (min(program.target_extent_m) < bounds.part_size_m[0]
                                                or not bounds.extent_m[0] <= max(program.target_extent_m) <= hi):
        out.append(f"target_extent_m {list(program.target_extent_m)}: every side must be >= "
                   f"{bounds.part_size_m[0]:g} m and the longest in [{bounds.extent_m[0]:g}, {hi:g}] m")
    for i, part in enumerate(program.parts):
        out += _part_problems(i, part, bounds, hi)
    if out:
        return out
    box = program_bounds(program)
    longest = float((box[1] - box[0]).max())
    if not bounds.extent_m[0] <= longest <= hi:
        return [f"the whole object is {longest:.3g} m long; its longest side must be in [{bounds.extent_m[0]:g}, "
                f"{hi:g}] m"]
    body = one_body_problem(program, bounds)
    return [body] if body else []


def check_program(program: ShapeProgram, bounds: ShapeBounds) -> str | None:
    """One line listing a program's contract violations, or None when it may be meshed."""
    problems = program_problems(program, bounds)
    return "; ".join(problems[:8]) if problems else None
