"""Sizes in words: every unit is understood or refused, comparisons resolve to a size, the rest is warned about."""

from __future__ import annotations

import pytest

from contracts.errors import InputError
from contracts.lexicon import load_lexicon
from tasks.geometry import catalogue
from tasks.geometry.size_words import REFERENCE_SIZES_M


@pytest.mark.parametrize("text", ["a plush turtle, 10 km long", "a sponge 3 kilometres wide", "a ball 2 miles across",
                                  "a foam cube, 5 um"])
def test_a_size_in_a_unit_too_large_or_small_is_refused_not_dropped(text: str) -> None:
    with pytest.raises(InputError, match="outside the supported range"):
        catalogue.design_from_text(text)


@pytest.mark.parametrize(("text", "axis", "metres"), [
    ("a foam block 3 dm long", 0, 0.3), ("a cushion, 1 yard wide", 1, 0.9144), ("a plush dog, 2 ft tall", 2, 0.6096),
    ("a rubber duck 100 millimetres long", 0, 0.1)])
def test_every_supported_unit_binds_to_its_axis(text: str, axis: int, metres: float) -> None:
    assert catalogue.design_from_text(text).size.extents_m[axis] == pytest.approx(metres)


def test_the_size_of_a_lexicon_object_is_that_objects_typical_size_and_not_the_object_made() -> None:
    d = catalogue.design_from_text("a plush bear the size of an orange")
    assert d.entry == "teddy_bear"
    assert d.size.longest_m == pytest.approx(load_lexicon().entries["orange"].size_m)
    assert not d.warnings


def test_two_word_comparison_and_body_references() -> None:
    d = catalogue.design_from_text("a yellow sponge the size of a tennis ball")
    assert d.entry == "kitchen_sponge"
    assert d.size.longest_m == pytest.approx(load_lexicon().entries["tennis_ball"].size_m)
    assert catalogue.design_from_text("a fist-sized foam ball").size.longest_m == REFERENCE_SIZES_M["fist"]
    assert catalogue.design_from_text("a palm sized squishy").size.longest_m == REFERENCE_SIZES_M["palm"]


@pytest.mark.parametrize(("text", "said"), [("a teddy the size of a car", "the size of a car"),
                                            ("a zorblat-sized sponge", "zorblat-sized"),
                                            ("a rubber duck, 10 furlongs long", "10 furlongs")])
def test_a_size_not_understood_is_warned_about(text: str, said: str) -> None:
    d = catalogue.design_from_text(text)
    assert d.size.longest_m is None and d.size.extents_m == (None, None, None)
    assert any(said in w for w in d.warnings), d.warnings


@pytest.mark.parametrize("text", ["a life-size plush cat", "a size 5 football", "a small-sized sponge"])
def test_words_that_keep_the_typical_size_give_no_warning(text: str) -> None:
    d = catalogue.design_from_text(text)
    assert d.size.longest_m is None and not any("size" in w for w in d.warnings)
