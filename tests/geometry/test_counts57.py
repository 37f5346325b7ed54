"""Session 57: a count said without a number is read ('a few slices of ham' was one slice, 28 g of the deli's
150 g), a bottle said half full keeps its water when it is also crushed (it weighed 12 g, the empty shell), and a
hyphened compound WordNet knows reaches its entry ('a ten-gallon hat' was a felt hat: 'ten-gallon' read as a
volume)."""

from __future__ import annotations

import functools

import pytest

from tasks.geometry import catalogue
from tasks.geometry.wordnet import wordnet
from tests.geometry.test_mass_classes import planned_mass

HAM_SLICE_KG = 0.028  # the lexicon's ham slice (USDA: 1 slice ~28 g)


@functools.lru_cache(maxsize=1)
def _one_slice_kg() -> float:
    return planned_mass("a slice of ham")


@pytest.mark.parametrize(("text", "count"), [
    ("few slices of ham folded in deli paper", 3),
    ("a couple of slices of ham", 2),
    ("several slices of ham", 4),
])
def test_a_count_without_a_number_weighs_that_many(text: str, count: int) -> None:
    assert catalogue.design_from_text(text).entry == "ham_slice"
    one = _one_slice_kg()
    assert one == pytest.approx(HAM_SLICE_KG, rel=0.35)
    assert planned_mass(text) == pytest.approx(count * one, rel=0.15)  # (pieces side by side: where they touch,
    # their meshes' union loses up to ~12 %)


def test_a_half_full_bottle_keeps_its_water_when_crushed_and_an_emptied_one_does_not() -> None:
    half = planned_mass("half full plastic water bottle, kinda crushed")
    assert 0.5 <= half / 0.265 <= 2.0  # 12 g shell + 250 ml of water
    assert planned_mass("a crushed plastic water bottle") < 0.02  # crushed alone: its contents are gone


def test_a_hyphened_compound_is_its_wordnet_synonym_the_lexicon_lists() -> None:
    assert wordnet().lemma("ten-gallon hat") == "ten-gallon_hat"
    assert wordnet().lemma("t-shirts") is not None
    assert catalogue.design_from_text("a brown ten-gallon hat").entry == "cowboy_hat"
    assert catalogue.design_from_text("a 10-gallon bucket hat").entry != "cowboy_hat"
