"""Classes sealed set 12's run found missing or misweighed (#35), fixed by class after it and checked here on other
phrasings than the set's: a pack of a number of sheets is a stack of that many (was one felt sheet, 0.18x), a state
after the noun is no unknown object ('burp cloths, folded and stacked' was a generic pouch), a newborn's garment is
a newborn's size (a newborn beanie weighed 4x), memory foam bath mats (0.34x in three sets), coated gardening gloves
(2.4x as leather work gloves), a bike's inner tube is no swim ring.

Real masses: typical retail figures (the source in each line)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


def test_a_pack_of_a_number_of_sheets_is_a_stack_of_that_many() -> None:
    d = catalogue.design_from_text("a pack of 6 craft felt squares")
    assert d.entry == "felt_sheet" and "stacked" in d.concept.states
    # craft listings: 23 x 30 cm felt sheets 10-30 g each
    assert 0.5 <= planned_mass("a pack of 6 craft felt squares") / (6 * 0.02) <= 2.0


def test_a_state_after_the_noun_is_not_an_unknown_object() -> None:
    d = catalogue.design_from_text("two muslin squares, folded and stacked")
    assert d.entry == "burp_cloth" and d.concept.fallback_level in ("exact", "synonym")


@pytest.mark.parametrize("text,kg", [("a newborn knitted hat", 0.02),  # retail newborn knit hats 15-30 g
                                     ("an infant fleece mitten", 0.012)])  # retail baby mittens 8-15 g each
def test_a_newborns_garment_is_a_newborns_size(text: str, kg: float) -> None:
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_wearer_words_size_garments_only() -> None:
    plush = catalogue.design_from_text("a newborn puppy plush")
    assert "newborn" not in plush.modifiers


@pytest.mark.parametrize("text,entry,kg", [
    ("a grey memory foam bath rug, 50 x 80 cm", "memory_foam_bath_mat", 0.6),  # retail 0.4-0.9 kg
    ("a pair of latex coated garden gloves", "garden_glove", 0.06),  # retail 45-80 g a pair
])
def test_sealed12_masses(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_bike_inner_tube_is_not_a_swim_ring() -> None:
    assert catalogue.design_from_text("a bike inner tube").entry != "swim_ring"


def test_a_ball_of_dough_is_a_ball() -> None:
    d = catalogue.design_from_text("a ball of modelling clay")
    assert d.entry == "modelling_clay" and d.concept.shape_from == "ball"  # (modelling clay split off play dough)
    assert catalogue.design_from_text("a ball of yarn").entry == "yarn_ball"  # a ball the lexicon's entry is


def test_a_flat_egg_rests_on_the_table_along_its_length() -> None:
    d = catalogue.design_from_text("a raw chicken fillet")
    body, front = d.program.parts[0], d.program.parts[1]
    bottom = [p.transform.translation_m[2] - p.primitive.radii_m[2] for p in (body, front)]
    assert abs(bottom[0] - bottom[1]) < 0.02 * d.program.parts[0].primitive.radii_m[0]  # no step under it


@pytest.mark.parametrize("text,entry,kg", [
    ("a fabric arm sling", "arm_sling", 0.15),  # medical supply: 0.1-0.2 kg
    ("a bicycle inner tube", "bike_inner_tube", 0.1),  # retail 700c butyl tubes 90-120 g
])
def test_sealed12_entries(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


@pytest.mark.parametrize("text,kg", [("a slow-rise squishy peach toy, 9 cm", 0.025),  # retail squishies 15-40 g
                                     ("slow rising squishy donut, 10 cm", 0.03)])
def test_a_slow_rising_squishy_is_its_shape_in_squishy_foam(text: str, kg: float) -> None:
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_plain_squishy_fruit_stays_fruit() -> None:
    assert planned_mass("a squishy ripe peach") > 0.1  # a ripe peach ~150 g, not a foam toy


def test_a_rolled_strip_stated_by_its_unrolled_length_is_built_not_refused() -> None:
    d = catalogue.design_from_text("a black boxing hand wrap, rolled up, 120 inches")
    assert d.entry == "hand_wrap" and "the sheet's length" in (d.size.stated or "")
    assert max(v for v in d.size.extents_m if v is not None) < 0.15  # a roll of a few cm, not a 3 m object
    # retail 180 in hand wraps 50-70 g each; a 120 in one 2/3 of that
    assert 0.5 <= planned_mass("a black boxing hand wrap, rolled up, 120 inches") / 0.04 <= 2.0
