"""Words that change how many of a good there are and what it holds: 'a pair of socks' (two, or one sock ball when
rolled), 'a zip bag half full of rice' (the fill's mass, tasks.geometry.fill_words), applied by concepts.build to
the object's body-plan parameters, its size and its mass."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contracts.concept import ConceptMatch
from contracts.lexicon import LexiconEntry
from contracts.shape import ShapeProgram
from tasks.geometry import fill_words, grammar
from tasks.geometry.grammar.goods import BAG_CAPACITY

FILLABLE_PLANS = frozenset({"bag", "pouch"})
PAIR_WORDS = frozenset({"pair"})


@dataclass
class GoodsChange:
    """What the words changed: the plan parameters, the size to build at, the concept (mass), whether to build the
    object twice side by side, and the fill's colour (painted on the 'fill' parts)."""

    params: dict
    size_m: float
    match: ConceptMatch
    duplicate: bool = False
    fill_color: str | None = None
    notes: tuple[str, ...] = ()


def _unit_longest(plan: str, params: dict) -> float:
    """The longest extent of a plan's unit-frame solid [-]."""
    p = grammar.plan_parameters(plan, params)
    return float(grammar.program_extents(ShapeProgram(name=plan, category="unit", parts=grammar.PLANS[plan][1](p)),
                                         64).max())


def bag_capacity_m3(plan: str, params: dict, size_m: float) -> float:
    """What a bag or pouch of this plan and size holds when filled round [m^3]: BAG_CAPACITY x height x width x
    min(height, width), its height the unit frame's length 1."""
    p = grammar.plan_parameters(plan, {**params, "fill": 0.0})
    height = size_m / _unit_longest(plan, p.model_dump())
    width = float(getattr(p, "width", 1.0)) * height
    return BAG_CAPACITY * height * width * min(height, width)


def apply(target: LexiconEntry, portion: str | None, text: str, params: dict, size_m: float,
          match: ConceptMatch) -> GoodsChange:
    """The change 'a pair of' and a stated fill make to the object built from `target` (its plan and params)."""
    out = GoodsChange(params=dict(params), size_m=size_m, match=match)
    plan = target.plan
    if plan is None or plan not in grammar.PLANS:
        return out
    fields = grammar.PLANS[plan][0].model_fields
    if portion in PAIR_WORDS:
        mass = match.typical_mass_kg * 2 if match.typical_mass_kg else None
        if "pair" in fields:  # the plan draws its pair (two socks side by side, or one ball of both when rolled)
            base = {**target.params, **out.params}
            k = _unit_longest(plan, {**base, "pair": True}) / _unit_longest(plan, base)
            out.params["pair"] = True
            out.size_m = size_m * k
            out.match = match.model_copy(update={"typical_mass_kg": mass, "typical_size_m": out.size_m})
        else:
            out.duplicate = True
            out.match = match.model_copy(update={"typical_mass_kg": mass})
        out.notes += ("a pair: two of them",)
    fill = fill_words.read_fill(text)
    if fill is not None and plan in FILLABLE_PLANS and "fill" in fields \
            and not any(" of " in f" {n} " for n in target.nouns):  # 'a bag of sugar' is its own entry
        cap = bag_capacity_m3(plan, {**target.params, **out.params}, out.size_m)
        fill_kg = fill.mass_kg(cap)
        shell = out.match.typical_mass_kg or 0.0
        out.params["fill"] = float(np.clip(fill.fraction, 0.05, 1.0))
        out.fill_color = fill.color
        source = (f"{fill.words}: {fill.fraction:g} of a {cap * 1e3:.3g} l capacity x {fill.bulk_density_kg_per_m3:g} "
                  f"kg/m^3 ({fill.source}) = {fill_kg * 1e3:.3g} g, plus the empty {target.key.replace('_', ' ')} "
                  f"{shell * 1e3:.3g} g")
        out.match = out.match.model_copy(update={"stated_mass_kg": shell + fill_kg, "stated_mass_source": source})
    return out


def duplicated(program: ShapeProgram) -> ShapeProgram | None:
    """The program twice: the second lying over the first, shifted half its width along its shorter horizontal axis
    (a pair of gloves laid one on the other: one body, as the mesher keeps one), or None past the part limit."""
    parts = list(program.parts)
    if 2 * len(parts) > 64 or any(p.operation != "union" for p in parts):
        return None
    ext = grammar.program_extents(program, 48)
    axis = 1 if ext[1] <= ext[0] else 0
    shift = [0.0, 0.0, 0.85 * float(ext[2])]
    shift[axis] = 0.45 * float(ext[axis])
    other = []
    for p in parts:
        t = p.transform.translation_m
        other.append(p.model_copy(update={"name": f"other {p.name}", "transform": p.transform.model_copy(update={
            "translation_m": (t[0] + shift[0], t[1] + shift[1], t[2] + shift[2])})}))
    return program.model_copy(update={"parts": parts + other})


def pair_up(program: ShapeProgram, match: ConceptMatch) -> tuple[ShapeProgram, ConceptMatch]:
    """The program built twice (duplicated) and the concept's typical size set to the pair's longest extent."""
    two = duplicated(program)
    if two is None:
        return program, match
    longest = float(grammar.program_extents(two, 48).max())
    return two, match.model_copy(update={"typical_size_m": longest})


def painted_fill(program: ShapeProgram, color: str) -> ShapeProgram:
    """The program with its 'fill' parts in the fill's colour (rice shows ivory through a clear bag)."""
    from contracts.lexicon import load_lexicon
    from tasks.geometry.grammar.parts import part_group

    rgb = load_lexicon().colors[color]
    return program.model_copy(update={"parts": [p.model_copy(update={"color_rgb": rgb}) if part_group(p.name) == "fill"
                                                else p for p in program.parts]})
