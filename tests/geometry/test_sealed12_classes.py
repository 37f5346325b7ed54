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
    assert d.entry == "play_dough" and d.concept.shape_from == "ball"
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
