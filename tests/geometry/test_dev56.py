"""Session 56 (post-hoc from sealed set 43's misses): a ball-pit ball is one ball, not the 7 kg pit; a thin plastic
glove is the 2 g polyethylene glove, not a knit one; a pickle is the dill pickle, not a 0.3 kg cucumber; a ciabatta
roll is a roll and a ketchup sachet the condiment packet; a fluffy pancake weighs a pancake's mass; 'slices of ham' are the sliced ham, not the whole ham (a
measure phrase's plural is its measure word's)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.concepts import plurals
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a red ball pit ball", "ball_pit_ball", 0.012),
    ("one of the thin plastic gloves from the pump dispenser", "poly_glove", 0.002),
    ("one dill pickle", "dill_pickle", 0.065),
    ("a ciabatta roll, sliced open", "bread_roll", 0.08),
    ("little ketchup sachet", "condiment_packet", 0.009),
    ("single fluffy pancake", "pancake", 0.08),  # 'fluffy' said of a food is its texture (it weighed 19 g as plush)
])
def test_the_goods_of_set_43_build_at_their_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


@pytest.mark.parametrize(("text", "entry"), [
    ("few slices of ham folded in deli paper", "ham_slice"),  # was the 4 kg whole ham
    ("a ball pit", "ball_pit"),  # the pit itself keeps its reading
    ("a cucumber", "cucumber"),
    ("a nitrile glove", "disposable_glove"),
])
def test_readings(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_measure_phrase_is_made_plural_by_its_measure_word() -> None:
    assert plurals("slice of ham") == ["slices of ham"]
    assert plurals("bag of ice") == ["bags of ice"]
    assert plurals("ice pack") == ["ice packs"]
