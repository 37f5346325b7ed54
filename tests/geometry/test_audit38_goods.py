"""Session 38's audit, goods group: household goods, food, toys and car soft parts the blind judges could not name
(built as a generic block, a bread roll or a plain blob), now hand-written shapes with the parts a person names them
by (tasks/geometry/shapes/audit38_goods.yaml, entries in contracts/lexicon/audit38_goods.yaml). Checked on the
programs, built once each."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _missing(text: str, names: set[str]) -> set[str]:
    """The names that no part's name contains."""
    return {n for n in names if not any(n in p.name for p in _design(text).program.parts)}


def _extent(text: str) -> np.ndarray:
    lo, hi = program_bounds(_design(text).program)
    return hi - lo


def _colours(text: str, group: str) -> set[tuple[float, ...]]:
    return {tuple(round(c, 2) for c in p.color_rgb) for p in _design(text).program.parts
            if part_group(p.name) == group and p.operation == "union"}


@pytest.mark.parametrize(("text", "entry", "groups"), [
    ("heating pad", "heating_pad", {"pad", "quilt seam", "cord", "controller", "controller button", "plug"}),
    ("car seat cover", "car_seat_cover", {"seat", "backrest", "headrest", "back panel", "seat bolster"}),
    ("seat cover", "car_seat_cover", {"backrest", "headrest"}),
    ("steering wheel cover", "steering_wheel_cover", {"ring", "hollow", "inner slot", "grip ridge"}),
    ("spool of ribbon", "ribbon_spool", {"ribbon", "flange", "core hole", "ribbon tail"}),
    ("raw chicken drumstick", "chicken_drumstick", {"meat", "taper", "bone", "knuckle"}),
    ("foam sit pad", "foam_sit_pad", {"base", "top layer", "fold", "dimple"}),
    ("foam positioning wedge", "positioning_wedge", {"wedge", "slope", "slope piping", "zip", "handle"}),
    ("fabric scraps bundle", "fabric_scrap_bundle", {"scrap", "polka dot", "twine top", "bow knot"}),
    ("pinata", "pinata", {"body fringe", "neck fringe", "head fringe", "left ear", "leg", "tail streamer"}),
    ("CV boot", "cv_boot", {"bellows", "convolution", "bore", "clamp big", "clamp small"}),
    ("streamer roll", "streamer_roll", {"roll", "core", "core hole", "strip", "crinkle"}),
    ("poop bags roll", "poop_bag_roll", {"roll", "core hole", "bag", "perforation", "paw pad"}),
    ("yellow play-doh", "play_dough", {"body", "tub", "label", "lid", "thumb print"}),
    ("lump of modeling clay", "modelling_clay", {"body", "thumb print", "stick"}),
    ("modeling clay block", "modelling_clay", {"body", "stick"}),
    ("foam ear plugs", "foam_earplug", {"plug", "second plug"}),
    ("cinnamon roll", "cinnamon_roll", {"bun", "swirl", "side groove", "coil end", "icing drizzle"}),
    ("tube of cookie dough", "cookie_dough_tube", {"body", "wrapper", "crimp left", "clip right", "picture"}),
    ("1 lb ground beef chub", "ground_beef_chub", {"body", "mince", "label", "gather", "clip"}),
    ("pack of hot dogs", "hot_dog_pack", {"tray", "frank", "label", "seal rim"}),
    ("foil balloon", "foil_balloon", {"centre", "point", "crimp seam", "neck"}),
    ("bouncy ball", "bouncy_ball", {"ball", "swirl"}),
    ("slime in a tub", "slime_tub", {"body", "tub", "tub inside", "slime fill", "drip", "lid"}),
    ("squishy toy shaped like a donut", "squishy_donut", {"body", "icing", "hole", "sprinkle", "left eye", "mouth"}),
    ("foam stress cube", "stress_cube", {"body", "thumb dent", "logo", "face", "face eye"}),
    ("a squished peach", "peach", {"fruit", "blush", "groove", "stem", "leaf"}),
    ("sock puppet", "sock_puppet", {"body", "stripe", "cuff rib", "head", "heel", "toe", "mouth", "left eye"}),
    ("a bath sponge", "bath_sponge", {"sponge", "second lobe", "pore", "side pore"}),
    ("soft baby rattle", "plush_rattle", {"head", "mane petal", "muzzle", "ring handle", "ring stripe"}),
    ("mozzarella ball in brine pouch", "mozzarella_pouch", {"pouch", "ball", "seal left", "crimp", "label"}),
    ("whole raw fish", "whole_fish", {"body", "belly", "flank stripe", "tail fin", "dorsal fin", "gill", "eye", "pupil", "spot"}),
    ("raw squid", "whole_squid", {"body", "left fin", "head", "left eye", "arm", "left tentacle", "speckle"}),
])
def test_objects_have_their_named_parts(text: str, entry: str, groups: set[str]) -> None:
    design = _design(text)
    assert design.entry == entry, (text, design.entry)
    assert not _missing(text, groups), (text, _missing(text, groups))
    assert len(design.program.parts) <= 64


def test_non_food_rolls_are_not_bread() -> None:
    for text in ("streamer roll", "poop bags roll", "a roll of poop bags", "crepe paper streamer"):
        assert _design(text).entry != "bread_roll", text
    assert _design("a bread roll").entry == "bread_roll"


def test_a_named_wedge_object_is_not_cut_into_a_wedge() -> None:
    """'foam positioning wedge' is the object itself, hand-drawn: not a diagonal wedge cut off a block."""
    assert not any(p.name.startswith("cut face") for p in _design("foam positioning wedge").program.parts)
    x, y, z = _extent("foam positioning wedge")
    assert x > 1.5 * z and y > 1.3 * z  # a long, wide, sloping block


def test_proportions() -> None:
    x, y, z = _extent("heating pad")
    assert x > 1.5 * y and z < 0.1 * y  # a flat oblong pad with its cord and controller alongside
    x, y, z = _extent("steering wheel cover")
    assert abs(x - y) < 0.05 * x and z < 0.2 * x  # a ring
    x, y, z = _extent("car seat cover")
    assert z > x and z > y  # a seat back standing up
    x, y, z = _extent("pinata")
    assert z > x > y  # a donkey standing, taller than long
    x, y, z = _extent("1 lb ground beef chub")
    assert x > 2.0 * y  # a chub, long and round
    x, y, z = _extent("pack of hot dogs")
    assert z < 0.25 * min(x, y)  # a flat pack


def test_colour_layouts() -> None:
    assert len({c for g in ("body fringe", "neck fringe", "leg") for c in _colours("pinata", g)}) >= 5  # rainbow rows
    assert len(_colours("bouncy ball", "swirl")) >= 3 and _colours("bouncy ball", "ball").isdisjoint(
        _colours("bouncy ball", "swirl"))
    assert _colours("heating pad", "controller").isdisjoint(_colours("heating pad", "pad"))
    assert _colours("cinnamon roll", "swirl").isdisjoint(_colours("cinnamon roll", "bun"))
    assert _colours("pack of hot dogs", "label").isdisjoint(_colours("pack of hot dogs", "frank"))
    # the play dough's lump and lid take the said colour; its tub stays white
    blue = _design("blue play-doh").program.parts
    assert {p.color_rgb for p in blue if p.name in ("body", "lid")} != {p.color_rgb for p in blue if p.name == "tub"}
    assert len({p.color_rgb for p in blue if p.name in ("body", "lid")}) == 1


def test_food_lies_like_food() -> None:
    """A raw fish and a raw squid lie flat on their side, as on a plate or a fishmonger's ice, not upright like a toy."""
    for text in ("whole raw fish", "raw squid"):
        x, y, z = _extent(text)
        assert z < 0.3 * x, text
    assert _colours("whole raw fish", "belly").isdisjoint(_colours("whole raw fish", "body"))  # olive back, white belly
    assert _colours("raw squid", "speckle").isdisjoint(_colours("raw squid", "body"))


def test_sock_puppet_stands_worn() -> None:
    x, y, z = _extent("sock puppet")
    assert z > x > y  # the sock's leg upright, its foot bent forward as the head
    assert _colours("sock puppet", "stripe").isdisjoint(_colours("sock puppet", "body"))
