"""Details and states a blind reviewer needs to name an object (#35), on phrasings other than the fifth blind set's:
a die shows its pips, a blown-up balloon its tied knot, a frog or toad (plush, or a kind the lexicon lacks) its
bulging eyes on top and folded hind legs; a flat sheet's corners curl when the text says so; 'folded like ...' still
folds a garment.

Real masses: typical retail or reference figures (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, grammar
from tasks.geometry.grammar.parts import part_group
from tests.geometry.test_mass_classes import planned_mass


def _design(text: str) -> catalogue.Design:
    return catalogue.design_from_text(text)


def _names(text: str) -> list[str]:
    return [p.name for p in _design(text).program.parts]


@pytest.mark.parametrize("text", ["a squishy foam die", "a pair of fuzzy dice? no: a plush die, 12 cm",
                                  "giant soft dice for the playground", "a big foam die for board games"])
def test_a_die_has_its_21_pips_pressed_in(text: str) -> None:
    d = _design(text)
    assert d.entry == "foam_dice", (text, d.entry)
    pips = [p for p in d.program.parts if part_group(p.name) == "pip"]
    assert len(pips) == 21 and all(p.operation == "subtract" for p in pips)
    body = np.asarray(d.program.parts[0].color_rgb)
    assert np.abs(np.asarray(pips[0].color_rgb) - body).max() > 0.2  # the pips show in their own colour


def test_a_foam_die_weighs_like_one() -> None:
    mass = planned_mass("a soft foam die, 15 cm")
    assert 0.5 <= mass / 0.1 <= 2.0, mass  # retail listings of 15 cm foam dice (80-150 g)


@pytest.mark.parametrize("text", ["an inflated latex balloon", "a helium party balloon, yellow", "a round balloon"])
def test_a_blown_up_balloon_has_its_knot(text: str) -> None:
    d = _design(text)
    names = {part_group(n) for n in _names(text)}
    assert {"neck", "knot"} <= names, (text, names)
    ext = grammar.program_extents(d.program, 64)
    knot = next(p for p in d.program.parts if p.name == "knot")
    assert knot.transform.translation_m[0] > 0.4 * ext[0]  # at the narrow end, beyond the body


@pytest.mark.parametrize("text, entry", [("a plush frog", "plush_frog"), ("a stuffed toad, bean filled", "plush_frog"),
                                         ("a frog", "plush_frog"), ("a cuddly bullfrog", "plush_tree_frog"),
                                         ("a plush natterjack", None)])
def test_a_frog_has_eyes_on_top_and_folded_hind_legs(text: str, entry: str | None) -> None:
    d = _design(text)
    if entry is not None:
        assert d.entry == entry, (text, d.entry)
    groups = {part_group(p.name) for p in d.program.parts}
    assert {"eye bump", "thigh", "shin", "foot"} <= groups, (text, groups)
    head = next(p for p in d.program.parts if p.name == "head")
    bumps = [p for p in d.program.parts if part_group(p.name) == "eye bump"]
    assert all(b.transform.translation_m[2] > head.transform.translation_m[2] for b in bumps)
    assert not any("rear leg" in p.name for p in d.program.parts)


def test_a_plush_frog_weighs_like_one() -> None:
    mass = planned_mass("a plush frog")
    assert 0.5 <= mass / 0.15 <= 2.0, mass  # retail listings of 20-25 cm plush frogs (0.1-0.2 kg)


@pytest.mark.parametrize("text", ["a silicone baking mat with curling corners",
                                  "a placemat, its corners curled up", "a yoga mat with the edges curling up a bit"])
def test_curling_corners_lift_a_flat_sheets_corners(text: str) -> None:
    d = _design(text)
    curls = [p for p in d.program.parts if "curl" in p.name]
    assert len(curls) == 8, (text, [p.name for p in d.program.parts])
    flat = _design(text.split(" with ")[0].split(",")[0])
    assert grammar.program_extents(d.program, 96)[2] > 1.8 * grammar.program_extents(flat.program, 96)[2]
    assert "corners curling" in (d.concept.states or [])  # type: ignore[union-attr]


@pytest.mark.parametrize("text", ["a cotton t-shirt folded like in a shop", "a polo shirt, folded as if for sale",
                                  "a sweater folded like a store display"])
def test_folded_like_a_display_is_still_folded(text: str) -> None:
    d = _design(text)
    assert d.concept is not None and d.concept.body_plan == "garment"
    assert any(p.name.startswith("fold gap") for p in d.program.parts), text
    ext = np.sort(grammar.program_extents(d.program, 64))
    assert ext[0] < 0.3 * ext[2]  # a flat layered block
