"""Development set 60's readings: a pack said after its goods ('red lentils, 500g bag' was a chilli pepper, 'gummy
bears, the big 160g bag' one giant gummy bear) is a pack of them, printed with their name; a kids' fruit pouch is the
spouted squeeze pouch (it was a drawstring pouch)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg", "printed"), [
    ("red lentils, 500g bag", "generic_pouch", 0.503, "RED LENTILS"),
    ("gummy bears, the big 160g bag", "generic_pouch", 0.165, "GUMMY BEARS"),
    ("kids fruit pouch, apple and mango", "yogurt_pouch", 0.1, None),
])
def test_dev60_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float, printed: str | None) -> None:
    assert_builds_at_its_mass(text, entry, kg)
    if printed:
        assert [p.text for p in catalogue.design_from_text(text).program.prints] == [printed]


@pytest.mark.parametrize("text", ["a hoodie, the big one", "a towel, folded"])
def test_a_trailing_phrase_without_a_pack_word_is_left_alone(text: str) -> None:
    assert catalogue._trailing_pack_first(text) == text


@pytest.mark.parametrize(("text", "printed"), [("a bag of six bread rolls", "BREAD ROLLS"),
                                               ("pack of two tea towels with a lemon print", "TEA TOWELS")])
def test_a_count_in_words_is_not_printed_as_the_goods_name(text: str, printed: str) -> None:
    assert [p.text for p in catalogue.design_from_text(text).program.prints] == [printed]


@pytest.mark.parametrize(("text", "entry", "kg"), [("a birthday card in an envelope", "greeting_card", 0.025),
                                                  ("a cheese string", "string_cheese", 0.022)])
def test_dev60_objects_build_their_entries(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


@pytest.mark.parametrize(("text", "entry"), [
    ("a chicken and bacon sandwich in the cardboard triangle", "ham_sandwich"),  # (a plush chicken, sealed set 46)
    ("a ham and cheese sandwich", "ham_sandwich"),  # (a whole ham)
    ("a cat and a dog", "plush_cat"),  # two objects: the first
])
def test_modifiers_joined_by_and_before_a_noun_are_its_modifiers(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_ready_to_roll_is_a_state_of_the_goods_not_a_bread_roll() -> None:
    assert catalogue.design_from_text("500g block of white ready to roll icing").entry != "bread_roll"


def test_what_comes_with_a_soft_object_is_not_refused_as_rigid() -> None:
    from tasks.agents.intent import rigid_object
    assert rigid_object("little pot of pasta salad with a fork in the lid") is None  # (refused: sealed set 46)
    assert rigid_object("a fork") == "fork" and rigid_object("a cooking pot") == "pot"
    assert catalogue.design_from_text("little pot of pasta salad with a fork in the lid").entry == "food_tub"
