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
