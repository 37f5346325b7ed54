"""Compositional shape grammar: body plans (functions of named parameters) -> painted, sized ShapePrograms."""

from __future__ import annotations

import functools
import json
import typing
from collections.abc import Callable
from typing import Any

import numpy as np
from pydantic import Field, ValidationError

from contracts.base import Model
from contracts.errors import InputError
from contracts.shape import Part, ShapeProgram
from tasks.geometry.grammar import animals, food, goods, things
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import MESH_CELLS_ACROSS, mesh_program, sample_solid
from tasks.geometry.sdf import program_bounds

RGB = tuple[float, float, float]

# plan name -> (parameter model, builder); every builder returns unpainted parts in its unit frame
PLANS: dict[str, tuple[type[Model], Callable[[Any], list[Part]]]] = {
    "quadruped": (animals.QuadrupedParams, animals.quadruped),
    "biped_seated": (animals.SeatedBipedParams, animals.biped_seated),
    "biped_standing": (animals.StandingBipedParams, animals.biped_standing),
    "bird": (animals.BirdParams, animals.bird),
    "fish": (animals.FishParams, animals.fish),
    "cetacean": (animals.CetaceanParams, animals.cetacean),
    "pinniped": (animals.PinnipedParams, animals.pinniped),
    "cephalopod": (animals.CephalopodParams, animals.cephalopod),
    "turtle": (animals.TurtleParams, animals.turtle),
    "insect": (animals.InsectParams, animals.insect),
    "segmented": (animals.SegmentedParams, animals.segmented),
    "snake": (animals.SnakeParams, animals.snake),
    "round_fruit": (food.RoundFruitParams, food.round_fruit),
    "pear": (food.PearParams, food.pear),
    "elongated": (food.ElongatedParams, food.elongated),
    "berry": (food.BerryParams, food.berry),
    "floret": (food.FloretParams, food.floret),
    "mushroom": (food.MushroomParams, food.mushroom),
    "loaf": (food.LoafParams, food.loaf),
    "bun": (food.BunParams, food.bun),
    "poultry": (food.PoultryParams, food.poultry),
    "croissant": (food.CroissantParams, food.croissant),
    "pretzel": (food.PretzelParams, food.pretzel),
    "muffin": (food.MuffinParams, food.muffin),
    "nigiri": (food.NigiriParams, food.nigiri),
    "pie": (food.PieParams, food.pie),
    "cushion": (things.CushionParams, things.cushion),
    "ball": (things.BallParams, things.ball),
    "block": (things.BlockParams, things.block),
    "disc": (things.DiscParams, things.disc),
    "ring": (things.RingParams, things.ring),
    "tube": (things.TubeParams, things.tube),
    "cone": (things.ConeParams, things.cone_plan),
    "bottle": (things.BottleParams, things.bottle),
    "star": (things.StarParams, things.star),
    "heart": (things.HeartParams, things.heart),
    "bone": (things.BoneParams, things.bone),
    "egg": (things.EggParams, things.egg),
    "cloud": (things.CloudParams, things.cloud),
    "cactus": (things.CactusParams, things.cactus),
    "blob": (things.BlobParams, things.blob),
    "pouf": (things.PoufParams, things.pouf),
    "sheet": (goods.SheetParams, goods.sheet),
    "pouch": (goods.PouchParams, goods.pouch),
    "glove": (goods.GloveParams, goods.glove),
    "sock": (goods.SockParams, goods.sock),
    "hat": (goods.HatParams, goods.hat),
    "tool": (goods.ToolParams, goods.tool),
    "mould": (goods.MouldParams, goods.mould),
    "garment": (goods.GarmentParams, goods.garment),
    "bag": (goods.BagParams, goods.bag),
    "strap": (goods.StrapParams, goods.strap),
    "rope": (goods.RopeParams, goods.rope),
    "book": (goods.BookParams, goods.book),
    "holey": (food.HoleyParams, food.holey),
    "layered": (food.LayeredParams, food.layered),
    "leafy_head": (food.LeafyHeadParams, food.leafy_head),
    "collapsible": (food.CollapsibleParams, food.collapsible),
}

# colours a part keeps unless the request or the entry names one (eyes and noses are dark)
_DARK = {"eye", "nose", "pupil", "mouth"}
BLACK: RGB = (0.02, 0.02, 0.02)
# fittings a part keeps unless the entry or the request names their colour: a zip, its pull, a button, a buckle
_HARDWARE = {"zip", "pull", "button", "buckle", "plug", "coupling"}
METAL: RGB = (0.32, 0.32, 0.34)


def plan_names() -> list[str]:
    """All body plans."""
    return list(PLANS)


def plan_parameters(plan: str, params: dict[str, Any] | None = None) -> Model:
    """Validated parameters of a plan (InputError naming the plan and the bad field)."""
    if plan not in PLANS:
        raise InputError(f"unknown body plan '{plan}' (known: {', '.join(PLANS)})")
    model = PLANS[plan][0]
    try:
        return model(**(params or {}))
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(x) for x in first["loc"])
        raise InputError(f"body plan '{plan}': parameter {where}: {first['msg']}") from exc


def part_color(name: str, colors: dict[str, RGB]) -> RGB:
    """Colour of a part: its own name, then what it is ('front left leg' -> 'leg', 'legs'), then the body's."""
    group = part_group(name)
    for key in (name.lower(), group, group + "s", group.split()[-1], group.split()[-1] + "s"):
        if key in colors:
            return colors[key]
    if group.split()[-1] in _DARK:
        return BLACK
    if group.split()[-1] in _HARDWARE:
        return METAL
    for key in ("body", "main"):
        if key in colors:
            return colors[key]
    return (0.6, 0.6, 0.6)


def paint(parts: list[Part], colors: dict[str, RGB]) -> list[Part]:
    """Parts with colours from a part-or-group -> linear RGB map."""
    return [p.model_copy(update={"color_rgb": part_color(p.name, colors)}) for p in parts]


def scale_parts(parts: list[Part], factor: float) -> list[Part]:
    """Parts scaled uniformly about the origin (every length: radii, sizes, translations, blends)."""
    out = []
    for p in parts:
        d = p.model_dump()
        for k, v in d["primitive"].items():
            if k.endswith("_m"):
                d["primitive"][k] = [x * factor for x in v] if isinstance(v, (list, tuple)) else v * factor
        d["transform"]["translation_m"] = [x * factor for x in d["transform"]["translation_m"]]
        d["blend_m"] = d["blend_m"] * factor
        out.append(Part(**d))
    return out


def build_program(plan: str, params: dict[str, Any] | None, colors: dict[str, RGB], name: str, category: str,
                  size_m: float | None = None) -> ShapeProgram:
    """The painted ShapeProgram of a body plan; its longest extent is size_m [m] when given."""
    p = plan_parameters(plan, params)
    parts = paint(PLANS[plan][1](p), colors)
    program = ShapeProgram(name=name, category=category, parts=parts)
    if size_m is not None:
        program = resize(program, size_m)
    return program


def program_extents(program: ShapeProgram, resolution: int = 48) -> np.ndarray:
    """Extents (x, y, z) [m] of the solid a program describes, from its signed distances on a grid (within about a
    cell; the primitives' bounding boxes overstate rotated and subtracted parts)."""
    field, _, spacing = sample_solid(program, resolution, MESH_CELLS_ACROSS)
    inside = field < 0
    if not inside.any():
        raise InputError(f"program '{program.name}' has no volume")
    ext = []
    for ax in range(3):
        idx = np.flatnonzero(inside.any(axis=tuple(a for a in range(3) if a != ax)))
        ext.append((idx[-1] - idx[0] + 1) * spacing)
    return np.asarray(ext)


def resize(program: ShapeProgram, size_m: float) -> ShapeProgram:
    """The program scaled so its longest extent is size_m [m]."""
    longest = float(program_extents(program).max())
    return program.model_copy(update={"parts": scale_parts(list(program.parts), size_m / longest)})


def plan_states(plan: str) -> tuple[str, ...]:
    """The states a plan's object can be in (its params model's `state` field: 'flat', 'rolled' ...); () for none."""
    if plan not in PLANS:
        raise InputError(f"unknown body plan '{plan}' (known: {', '.join(PLANS)})")
    field = PLANS[plan][0].model_fields.get("state")
    if field is None:
        return ()
    return tuple(typing.get_args(field.annotation))


class StateChange(Model):
    """How an object built in another state relates to the same object in its lexicon state (same sheet)."""

    size_m: float = Field(gt=0, description="longest extent in the new state [m]")
    density_factor: float = Field(gt=0, description="multiply the entry's density by this: the built volume of the "
                                  "entry's state over the new state's, per sheet (thin sheets are built thicker than "
                                  "they are when flat, at their real thickness when rolled) [-]")
    mass_factor: float = Field(gt=0, description="objects in the new state per object in the entry's (a stack of "
                               "`layers` sheets is that many) [-]")


def state_change(plan: str, params: dict[str, Any] | None, size_m: float, state: str,
                 also: dict[str, Any] | None = None) -> StateChange:
    """The size, density and mass factors of the object of `plan` with `params` (longest extent size_m [m]) when it is
    built in `state` instead: e.g. a 1.83 m flat yoga mat rolled up is a 0.61 m roll of the same mass. Build it with
    build_program(plan, {**params, 'state': state}, ..., size_m=change.size_m), give it the entry's density times
    density_factor, and expect the entry's typical mass times mass_factor at that size. `also`: parameters that
    change with the state only (a towel folded into a strip before it is rolled: the strip's width and layers)."""
    states = plan_states(plan)
    if state not in states:
        raise InputError(f"body plan '{plan}' has no state '{state}' (its states: {', '.join(states) or 'none'})")
    base = plan_parameters(plan, params)
    new = plan_parameters(plan, {**(params or {}), **(also or {}), "state": state})
    a, b = _unit_solid(plan, base), _unit_solid(plan, new)
    scale = size_m / a[0]
    layers_a = getattr(base, "layers", 1) if getattr(base, "state", "") == "stacked" else 1
    layers_b = getattr(new, "layers", 1) if state == "stacked" else 1
    per_sheet = (a[1] / layers_a) / (b[1] / layers_b)
    return StateChange(size_m=b[0] * scale, density_factor=per_sheet, mass_factor=layers_b / layers_a)


@functools.lru_cache(maxsize=256)
def _unit_solid_cached(plan: str, params_json: str) -> tuple[float, float]:
    params = plan_parameters(plan, json.loads(params_json))
    program = ShapeProgram(name=plan, category="state", parts=PLANS[plan][1](params))
    ext = program_bounds(program)[1] - program_bounds(program)[0]
    mesh = mesh_program(program, int(min(1024, max(96, 6 * ext.max() / ext.min()))))  # 6 cells through a strip
    return float(mesh.extents.max()), float(mesh.volume)


def _unit_solid(plan: str, params: Model) -> tuple[float, float]:
    """(longest extent, volume) of a plan's unit-frame solid."""
    return _unit_solid_cached(plan, params.model_dump_json())
