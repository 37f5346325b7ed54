"""Sizes that measure a thin good's material, not the object as built (#35): 'a yoga mat 6 mm thick, rolled up' is a
6 mm sheet (the roll keeps its size), 'a 3 m length of 10 mm rope' is 3 m of rope 10 mm thick (coiled when it is
longer than L0 builds), 'a 41 in resistance band loop' a band 41 in long laid flat. The bound sizes become the plan's
own parameters (a sheet's or strip's thickness, a strip's width and length), the size the object is built at follows
from them, and its mass is the lexicon's typical mass scaled by its material's length and cross-section."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from contracts.lexicon import LexiconEntry
from contracts.request import MAX_SIZE_M
from contracts.shape import ShapeProgram
from tasks.geometry import grammar
from tasks.geometry.grammar.goods import HANK_MIN_TURNS, StrapParams, coiled_as_hank

STOCK_MAX_M = 0.0127  # sheet stock is said up to half an inch thick ('10mm EVA foam', '12 mm neoprene'): a bare size
# no larger on a sheet good is its thickness [m]

_UNITS = {"mm": 0.001, "millimeter": 0.001, "millimetre": 0.001, "millimeters": 0.001, "millimetres": 0.001,
          "cm": 0.01, "centimeter": 0.01, "centimetre": 0.01, "centimeters": 0.01, "centimetres": 0.01, "m": 1.0,
          "meter": 1.0, "metre": 1.0, "meters": 1.0, "metres": 1.0, "in": 0.0254, "inch": 0.0254, "inches": 0.0254,
          '"': 0.0254, "ft": 0.3048, "foot": 0.3048, "feet": 0.3048, "yd": 0.9144, "yard": 0.9144, "yards": 0.9144}
# a tube's diameters: 'OD', 'outer diameter', 'ID', 'inner diameter', 'bore' ('8 mm OD 5 mm ID', 'ID 6 mm, OD 9 mm')
_DIAMETERS = (r"(?:outer|outside|external|inner|inside|internal)\s+diam(?:eter)?|o\.?d\.?|i\.?d\.?|bore")
_MEASURE = re.compile(r"(?:\b(length|thickness|diameter|width|" + _DIAMETERS + r")\s*(?:of|:|=)?\s*)?"
                      r"(\d+(?:\.\d+)?)\s*"
                      r"(mm|millimet(?:er|re)s?|cm|centimet(?:er|re)s?|m|met(?:er|re)s?|inch(?:es)?|in|\"|ft|foot|"
                      r"feet|yd|yards?)(?![a-z])(?:\s*(?:in\s+)?(long|length|thick|thickness|wide|width|diameter|dia|"
                      r"across|round|gauge|" + _DIAMETERS + r")(?![a-z]))?", re.I)
THIN_PLANS = frozenset({"sheet", "strap"})
HANK_RADIUS_M = 0.3  # a long rope coiled by hand: loops at most about an arm span round (0.6 m across) [m]
HANK_RADIUS_MIN_M = 0.08  # the tightest loop a hand coils [m]
HANK_RADIUS_PER_SQRT = 0.5  # a coil's loop radius over sqrt(length x cord diameter): 10 m of XLR cable (6.5 mm) in
# 25 cm loops, 15 m of garden hose (19 mm) in 53 cm loops, a 60 m climbing rope (9.8 mm) at the arm span [-]
CROSS_SECTION_MAX = 0.06  # a bare size under this share of the good's typical size measures its cross-section [-]
COIL_NOT_CORD = 8.0  # a round cord's bare or stated diameter over this many times its own is the coil's size [-]
CROSS_WORDS = {"thick": "thickness", "thickness": "thickness", "diameter": "diameter", "dia": "diameter",
               "gauge": "diameter", "wide": "width", "width": "width", "across": "diameter", "round": "diameter",
               "od": "diameter", "outer": "diameter", "outside": "diameter", "external": "diameter", "id": "inner",
               "inner": "inner", "inside": "inner", "internal": "inner", "bore": "inner"}


def hank_radius(length_m: float, diameter_m: float) -> float:
    """The loop radius a hand coils a cord of this length and diameter into [m]."""
    return float(np.clip(HANK_RADIUS_PER_SQRT * np.sqrt(length_m * diameter_m), HANK_RADIUS_MIN_M, HANK_RADIUS_M))


def _cross_word(word: str) -> str | None:
    """What a size word measures ('8 mm OD' the outer diameter, '5 mm ID' the bore), None when it is no cross word."""
    word = re.sub(r"[.\s]+", " ", word.lower()).strip()
    return CROSS_WORDS.get(word) or CROSS_WORDS.get(word.replace(" ", "")) or CROSS_WORDS.get(word.split(" ")[0])


@dataclass
class Bound:
    """Sizes bound to the material: plan parameters, the longest extent to build at (None: as stated or typical),
    the mass factor over the entry's typical mass, the size words consumed, and notes."""

    params: dict = field(default_factory=dict)
    longest_m: float | None = None
    mass_factor: float = 1.0
    consumed: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def _unit_longest(plan: str, params: dict) -> float:
    p = grammar.plan_parameters(plan, params)
    return float(grammar.program_extents(ShapeProgram(name=plan, category="unit", parts=grammar.PLANS[plan][1](p)),
                                         64).max())


def _measures(text: str) -> list[tuple[str | None, float, str]]:
    """(what the size measures: 'length', 'thickness', 'diameter', 'width' or None for a bare size, metres, words)."""
    out: list[tuple[str | None, float, str]] = []
    for m in _MEASURE.finditer(text.lower()):
        unit = m.group(3).lower()
        key = unit if unit in _UNITS else next((k for k in _UNITS if unit.startswith(k[:4]) and len(k) > 2), "cm")
        metres = float(m.group(2)) * _UNITS[key]
        prefix = (m.group(1) or "").lower()
        if prefix and out and out[-1][2].lower().endswith(prefix):  # 'a 3 m length of 10 mm rope': 'length' is 3 m's
            prefix = ""
        word = (m.group(4) or prefix).lower()
        what = _cross_word(word) if word else None
        what = what or ("length" if word in ("long", "length") else None)
        out.append((what, metres, m.group(0).strip()))
    return out


def bind(text: str, entry: LexiconEntry | None, states: list[str]) -> Bound | None:
    """The sizes of `text` that measure the thin good `entry` (a sheet's thickness; a strip's length, width,
    thickness or diameter) as plan parameters, or None when none does (the object is sized as built)."""
    if entry is None or entry.plan not in THIN_PLANS or entry.plan not in grammar.PLANS:
        return None
    measures = _measures(text)
    if not measures:
        return None
    params = dict(entry.params)
    state = states[0] if states else params.get("state")
    if state is not None and state in grammar.plan_states(entry.plan):
        params["state"] = state  # (to build it in: a long rope is coiled when it is straight past L0's size)
    typical = entry.size_m
    base_state = {**entry.params}
    length0 = typical / _unit_longest(entry.plan, base_state)  # the material's own length (a strip's, a flat sheet's)
    bound = Bound()
    cross = [(w, v, s) for w, v, s in measures if (w in ("thickness", "diameter", "width", "inner") or w is None)
             and v < CROSS_SECTION_MAX * max(typical, length0)]
    if entry.plan == "sheet":
        t0 = float(grammar.plan_parameters("sheet", params).thickness)  # type: ignore[attr-defined]
        own = t0 * length0  # the sheet's typical thickness [m]
        thick = [(v, s) for w, v, s in cross if w == "thickness"] or [(v, s) for w, v, s in cross
                                                                       if w is None and (v <= STOCK_MAX_M or
                                                                                         own / 2.5 <= v <= own * 2.5)]
        if not thick:  # (a bare size too small for any object L0 builds, 'a 6 mm yoga mat', is its thickness too, and
            return None  # so is one near the sheet's own thickness: 'a 5cm memory foam topper'; '4 inch' on a
        v, s = thick[0]  # bandage is its width)
        params["thickness"] = v / length0
        bound.mass_factor = params["thickness"] / t0
        bound.consumed.append(s)
        bound.notes.append(f"'{s}' is the sheet's own thickness")
    else:  # a strip, band, rope or cord
        p0 = grammar.plan_parameters("strap", params)
        closed = bool(getattr(p0, "closed", False))
        lengths = [(v, s) for w, v, s in measures if (w == "length" or w is None) and (v, s) not in
                   [(c[1], c[2]) for c in cross]]
        length = length0
        if lengths:
            v, s = lengths[0]
            length = 2.0 * v if closed else v  # a closed band's size is its length laid flat, doubled
            bound.consumed.append(s)
            bound.notes.append(f"'{s}' is the {'band laid flat' if closed else 'strip'}'s own length")
        w0 = float(p0.width)  # type: ignore[attr-defined]
        t0 = w0 if p0.round else float(p0.thickness)  # type: ignore[attr-defined]  # (a round cord is as thick as wide)
        width, thickness = w0 * length0, t0 * length0
        bore0 = float(getattr(p0, "bore", 0.0))
        if bore0 > 0 and any("hose" in n for n in entry.nouns):  # a hose's bare size is its nominal bore ('a 5/8
            cross = [("inner" if w is None else w, v, s) for w, v, s in cross]  # inch garden hose')
        inner = [(v, s) for w, v, s in cross if w == "inner"]
        outer = [v for w, v, _s in cross if w == "diameter"]
        if inner and bore0 > 0 and not outer:  # '6 mm ID' alone: the wall the tube has at its own bore ratio
            width = thickness = inner[0][0] / bore0
        coil_words = [s for w, v, s in cross if p0.round and w in (None, "diameter")  # type: ignore[attr-defined]
                      and v > COIL_NOT_CORD * w0 * length0]
        cross = [c for c in cross if c[2] not in coil_words]  # 'a 60 m climbing rope, 40 cm across': the coil's
        # size, not a 40 cm cord
        for w, v, s in cross:
            if w == "inner":
                bound.consumed.append(s)
                bound.notes.append(f"'{s}' is its inner diameter")
                continue
            if w in ("diameter",) or (w is None and p0.round) or (w == "thickness" and p0.round):  # type: ignore[attr-defined]
                width = thickness = v
            elif w == "thickness":
                thickness = v
            elif w == "width" or w is None:
                width = v
            bound.consumed.append(s)
            bound.notes.append(f"'{s}' is its {w or ('diameter' if p0.round else 'width')}")  # type: ignore[attr-defined]
        if not bound.consumed:
            return None
        params["width"] = min(width / length, 0.3)
        params["thickness"] = min(thickness / length, 0.1)
        if _unit_longest("strap", params) * length > MAX_SIZE_M and "rolled" in grammar.plan_states("strap") \
                and params.get("state") != "loop":
            params["state"] = "rolled"  # longer than L0 builds straight: coiled
            bound.notes.append(f"{length:g} m of it is built coiled")
        rolled = params.get("state", entry.params.get("state")) == "rolled"
        hank = rolled and (bool(params.get("hank")) or (isinstance(p0, StrapParams) and coiled_as_hank(p0)))
        spiral = _unit_longest("strap", params) * length  # the coil as a flat spiral [m]
        loose = bool(p0.round) and spiral > HANK_RADIUS_M * 2.5  # type: ignore[attr-defined]
        if rolled and (hank or loose or spiral > MAX_SIZE_M):  # a long coil wound
            # as tight (a round cord whose flat spiral would be wider than a hand coils it: loops, a 15 m battle rope)
            tight = np.sqrt(0.55 * length / (1.45 * np.pi * max(width, 1e-6)))  # as its cord allows (r1 - r0 =
            params["turns"] = float(np.clip(max(tight, float(p0.turns)), 1.0, 8.0))  # type: ignore[attr-defined]  # 0.55 r1 = turns x width)
            if hank or tight > (HANK_MIN_TURNS if p0.round else 8.0):  # type: ignore[attr-defined]  # loops laid one on
                # another (a rope's hank): a flat strip past what the mesher sees as a spiral, a round cord sooner
                params["hank"] = True
                loop = hank_radius(length, width)
                params["turns"] = float(np.clip(length / (2 * np.pi * loop), 2.0, 60.0))
                bound.notes.append(f"coiled in {params['turns']:.0f} loops of {2 * loop:.2g} m")
        bound.longest_m = _unit_longest("strap", params) * length
        bound.mass_factor = (length / length0) * (width * thickness) / (w0 * t0 * length0 ** 2)
        if bore0 > 0:  # a tube weighs its wall: (OD^2 - ID^2) against the entry's own
            bore = min(inner[0][0] / max(width, 1e-9), 0.95) if inner else bore0
            bound.mass_factor *= (1.0 - bore ** 2) / (1.0 - bore0 ** 2)
    if params.get("state") == (states[0] if states else entry.params.get("state")) or "state" not in params:
        params.pop("state", None)  # the state the text or the entry gives is applied as a state (concepts.build)
    bound.params = params
    return bound


def strip_consumed(text: str, consumed: list[str]) -> str:
    """The text without the size phrases a binding consumed (so they do not size the object as built too)."""
    for s in consumed:
        text = re.sub(re.escape(s), " ", text, count=1, flags=re.I)
    return re.sub(r"\s+", " ", text).strip()
