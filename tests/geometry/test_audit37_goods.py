"""Session 37's audit, goods group: household goods, foam, rubber, silicone and kitchen things the blind judges could
not name as built from their plans (a plain block, ring, cone or mould), now hand-written shapes with the parts a
person names them by (tasks/geometry/shapes/audit37_goods.yaml). Checked on the programs, built once each."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds, program_sdf


@functools.cache
def _program(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text).program


def _missing(text: str, names: set[str]) -> set[str]:
    """The names that no part's name contains."""
    return {n for n in names if not any(n in p.name for p in _program(text).parts)}


def _extent(text: str) -> np.ndarray:
    lo, hi = program_bounds(_program(text))
    return hi - lo


def _inside(text: str, point_frac: tuple[float, float, float]) -> bool:
    """Whether a point, given as fractions of the program's bounding box, is inside the solid."""
    lo, hi = program_bounds(_program(text))
    p = lo + np.asarray(point_frac) * (hi - lo)
    return bool(program_sdf(p[None, :], _program(text))[0] < 0)


def _colours(text: str, group: str) -> set[tuple[float, ...]]:
    return {tuple(round(c, 2) for c in p.color_rgb) for p in _program(text).parts
            if part_group(p.name) == group and p.operation == "union"}


@pytest.mark.parametrize(("text", "entry", "groups"), [
    ("a dish brush", "dish_brush", {"handle", "hanging hole", "head", "bristles"}),
    ("a bottle brush", "bottle_brush", {"handle", "hanging loop", "wire", "bristles", "foam tip"}),
    ("a chocolate mould", "chocolate_mould", {"cavity", "chocolate", "rim"}),
    ("a suction cup", "suction_cup", {"cup", "underside", "stem", "hook"}),
    ("a piping bag", "piping_bag", {"nozzle", "nozzle ridge", "twist", "frosting"}),
    ("a kickboard", "kickboard", {"nose", "hand hole left", "hand hole right", "top panel"}),
    ("a rubber doorstop", "door_wedge", {"slope", "ridge"}),
    ("a sink stopper", "sink_stopper", {"ridge", "stem", "knob"}),
    ("a menstrual cup", "menstrual_cup", {"open top", "inside", "rim", "stem", "grip ring"}),
    ("a cat bed", "cat_bed", {"rim", "floor", "front dip", "left ear", "right ear"}),
    ("a bop bag", "bop_bag", {"base", "face", "nose", "left eye", "mouth", "hat"}),
    ("a reading pillow", "reading_pillow", {"back", "left arm", "right arm", "neck roll", "handle"}),
    ("a rubber mask", "latex_mask", {"left eye hole", "nose", "hair", "left neck bolt", "neck opening"}),
    ("a squishmallow", "plush_toy_pillow", {"left eye", "left cheek", "belly", "left ear", "mouth"}),
    ("a silicone trivet", "silicone_pot_holder", {"ring", "spoke", "hub", "hanging tab"}),
    ("a flanged earplug", "flanged_earplug", {"stem", "flange", "grip"}),
    ("a hand warmer", "hand_warmer", {"lobe", "metal disc", "seal"}),
    ("a thai pad", "thai_pad", {"back panel", "arm strap", "grip handle", "logo"}),
])
def test_objects_have_their_named_parts(text: str, entry: str, groups: set[str]) -> None:
    design = catalogue.design_from_text(text)
    assert design.concept == entry or entry in str(design.concept), (text, design.concept)
    assert not _missing(text, groups), (text, _missing(text, groups))


def test_brushes_have_bristles_of_their_own_colour() -> None:
    for text in ("a dish brush", "a bottle brush", "a bath brush"):
        bristles = _colours(text, "bristles")
        assert len(bristles) == 1 and bristles.isdisjoint(_colours(text, "handle")), text
    assert sum(part_group(p.name) == "bristles" for p in _program("a dish brush").parts) >= 12  # tufts, not a block


def test_hollow_and_holed_things_are_open() -> None:
    assert not _inside("a cupcake liner", (0.5, 0.5, 0.7))  # a cup, open at the top
    assert not _inside("a menstrual cup", (0.5, 0.5, 0.8))
    assert not _inside("a jelly mould", (0.5, 0.72, 0.7))  # between the central tube and the wall
    assert _inside("a jelly mould", (0.5, 0.567, 0.5)) and not _inside("a jelly mould", (0.5, 0.5, 0.5))  # the tube
    assert not _inside("a silicone trivet", (0.5, 0.5 + 0.5 * 3.1 / 10.2, 0.5))  # between two rings
    assert not _inside("an inflatable collar", (0.5, 0.5, 0.5))  # the neck hole


def test_proportions_and_colours_name_them() -> None:
    e = _extent("a pregnancy pillow")
    assert e[0] > 1.5 * e[1] > 3 * e[2]  # a long flat U
    assert not _inside("a pregnancy pillow", (0.3, 0.5, 0.5))  # the open middle of the U
    e = _extent("a rubber doorstop")
    assert e[0] > 2.5 * e[2]  # a long low wedge
    assert len({c for p in _program("a stacking cup").parts for c in [tuple(p.color_rgb)]}) >= 5  # a rainbow set
    assert _colours("a chocolate mould", "chocolate") != _colours("a chocolate mould", "body")
    assert _colours("a cat bed", "floor") != _colours("a cat bed", "rim")
    assert _colours("a kickboard", "panel") != _colours("a kickboard", "body")
    e = _extent("a peanut ball")
    assert e[0] > 1.5 * e[1] and not _inside("a peanut ball", (0.5, 0.5, 0.93))  # a waist between two lobes
