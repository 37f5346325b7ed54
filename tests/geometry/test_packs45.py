"""Session 45, packs of food: the blind judges named the wrong contents of 7 of 50 packs, every one drawn as the same
pillow pouch with a red label. Now a pack shows its goods the way real packaging does: beans, tapioca pearls, pasta
and lettuce shreds through a clear bag's film (contracts/vocab/fills.yaml `piece`); flour and sugar in a paper sack
standing on its flat bottom, flour's wheat ear upright with its awns; drink and protein powders in a stand-up zip
pouch of the powder's colour; sliced deli meat in a flat clear tray of shingled slices. Checked on the programs."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue, pouch_words
from tasks.geometry.concepts import load_lexicon, read_text
from tasks.geometry.grammar.goods import emblem_parts
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds
from tests.geometry.helpers import parts_by_group


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _rgb(word: str) -> tuple[float, ...]:
    return tuple(round(c, 3) for c in load_lexicon().colors[word])


def _colours(text: str, group: str) -> set[tuple[float, ...]]:
    return {tuple(round(c, 3) for c in p.color_rgb) for p in _design(text).program.parts
            if part_group(p.name) == group and p.operation == "union"}


def _extent(text: str) -> np.ndarray:
    lo, hi = program_bounds(_design(text).program)
    return np.asarray(hi) - np.asarray(lo)


@pytest.mark.parametrize(("text", "fill", "colours"), [
    ("2 lb bag of dried pinto beans, kinda lumpy", "pinto_beans", {"tan", "light brown", "beige"}),
    ("half-used 1 kg bag of tapioca pearls", "tapioca", {"dark brown", "black"}),
    ("a 1 lb bag of black beans", "black_beans", {"black", "charcoal"}),
    ("a bag of pasta", "pasta", {"wheat", "golden"}),
    ("2.5 lb bag of shredded lettuce", "shredded_lettuce", {"pale green", "light green", "green", "pale yellow"}),
])
def test_a_bag_of_piece_goods_shows_them_through_its_film(text: str, fill: str, colours: set[str]) -> None:
    reading = read_text(text)
    assert reading.pouch is not None and reading.pouch.fill.key == fill
    pieces = _colours(text, "fill")
    assert len([p for p in _design(text).program.parts if part_group(p.name) == "fill"]) >= 12  # a bagful, not a dot
    assert pieces and pieces <= {_rgb(c) for c in colours}  # the goods' own colours
    assert "label" not in parts_by_group(_design(text).program)  # nothing hides them


def test_pinto_beans_are_speckled_tan_and_weigh_their_bulk_density() -> None:
    text = "a bag of pinto beans"
    assert len(_colours(text, "fill")) >= 2  # tan beans speckled with light brown ones
    d = _design(text)
    assert d.concept is not None and "816" in (d.concept.stated_mass_source or "")
    cap_share = float(d.concept.stated_mass_source.split(" of a ")[1].split(" l capacity")[0]) * 1e-3  # type: ignore[union-attr]
    assert d.concept.stated_mass_kg == pytest.approx(0.8 * cap_share * 816.0, rel=0.15)  # (+ the film)


def test_the_pieces_are_drawn_larger_than_life_but_weighed_as_real() -> None:
    pouch = read_text("a bag of pinto beans").pouch
    assert pouch is not None and pouch.piece_m is not None and pouch.piece_drawn is not None
    assert max(pouch.piece_m) == pytest.approx(0.013)  # a real pinto bean
    assert max(pouch.piece_drawn) == pytest.approx(1.0 / pouch_words.SEEN_FILL_ALONG)  # drawn 1/7 of the pack


@pytest.mark.parametrize("text", ["5 lb bag of flour", "a bag of flour", "a bag of sugar"])
def test_flour_and_sugar_stand_in_a_paper_sack(text: str) -> None:
    ext = _extent(text)
    assert ext[2] > 1.3 * ext[1] > 1.3 * ext[0]  # standing on its flat bottom, a brick deeper than it is thick
    groups = parts_by_group(_design(text).program)
    assert {"body", "fold", "fold flap", "gusset crease", "label"} <= set(groups)
    lo, hi = program_bounds(_design(text).program)
    assert groups["label"][0].transform.translation_m[0] > (lo[0] + hi[0]) / 2  # its front faces the renders (+x)


def test_flours_wheat_ear_stands_upright_with_its_awns() -> None:
    marks = [p for p in _design("5 lb bag of flour").program.parts if part_group(p.name) == "emblem"]
    assert len(marks) == len(emblem_parts("wheat", 0.2)) == 14  # stalk, 9 grains, 4 awns
    zs = [p.transform.translation_m[2] for p in marks]
    ys = [p.transform.translation_m[1] for p in marks]
    assert max(zs) - min(zs) > 2.0 * (max(ys) - min(ys))  # an upright ear, not a sprig lying across
    assert _design("5 lb bag of flour").concept.stated_mass_kg == pytest.approx(2.268, rel=0.01)  # type: ignore[union-attr]


def test_a_bag_of_sugar_weighs_a_kilogram_as_drawn() -> None:
    d = _design("a bag of sugar")
    assert d.concept is not None and d.concept.density_kg_per_m3 == pytest.approx(900.0)


@pytest.mark.parametrize(("text", "colour"), [
    ("taro powder pouch", "lavender"), ("a pouch of protein powder", "ivory"), ("a bag of matcha powder", "pale green"),
])
def test_a_powder_comes_in_a_stand_up_zip_pouch_of_its_colour(text: str, colour: str) -> None:
    reading = read_text(text)
    assert reading.pouch is not None and reading.pouch.fill.key == "powder" and reading.pouch.fill.color == colour
    groups = parts_by_group(_design(text).program)
    assert {"zip line", "gusset", "label"} <= set(groups) and "emblem" not in groups  # (no wheat: it read as shrimp)
    ext = _extent(text)
    assert ext[2] > ext[1] > ext[0]  # standing
    assert _colours(text, "body") == {_rgb(colour)}
    lo, hi = program_bounds(_design(text).program)
    assert groups["label"][0].transform.translation_m[0] > (lo[0] + hi[0]) / 2  # its label faces the renders


@pytest.mark.parametrize(("text", "colour"), [
    ("opened 1 lb pack of sliced turkey", "light pink"), ("a pack of ham", "pink"), ("a pack of sliced salami", "dark red"),
])
def test_sliced_deli_meat_is_a_flat_tray_of_shingled_slices(text: str, colour: str) -> None:
    reading = read_text(text)
    assert reading.pouch is not None and reading.pouch.fill.key == "deli"
    ext = _extent(text)
    assert ext[2] < 0.3 * ext[0]  # a flat tray, not a pillow
    slices = [p for p in _design(text).program.parts if part_group(p.name) == "fill"]
    assert len(slices) >= 5 and _colours(text, "fill") == {_rgb(colour)}
    assert len({round(p.transform.translation_m[0], 4) for p in slices}) == len(slices)  # shingled along it
    assert {"body", "seam", "label"} <= set(parts_by_group(_design(text).program))


def test_a_pound_of_sliced_turkey_weighs_a_pound() -> None:
    d = _design("opened 1 lb pack of sliced turkey")
    assert d.concept is not None
    assert (d.concept.stated_mass_kg or 0.0) == pytest.approx(0.454, rel=0.01)


def test_an_unsaid_deli_pack_weighs_a_retail_pack() -> None:
    d = _design("a pack of ham")
    assert d.concept is not None and 0.15 <= (d.concept.stated_mass_kg or 0.0) <= 0.5  # 8-16 oz retail packs


@pytest.mark.parametrize(("text", "fill"), [
    ("a bag of rice", "rice"), ("a bag of dog food", "pet_food"), ("a bag of potting soil", "compost"),
    ("a bag of coffee beans", "coffee"), ("a bag of cat litter", "cat_litter"),
])
def test_other_packs_keep_their_emblems(text: str, fill: str) -> None:
    reading = read_text(text)
    assert reading.pouch is not None and reading.pouch.fill.key == fill and reading.pouch.piece_m is None
    assert {"label", "emblem"} <= set(parts_by_group(_design(text).program))


def test_goods_the_lexicon_knows_still_show_their_own_pieces() -> None:
    reading = read_text("a bag of gummy bears")
    assert reading.pouch is not None and reading.pouch.piece_key == "gummy_bear" and reading.pouch.piece_drawn is None
