"""Session 42's redraw (helper r1): objects the blind judges could not name as built, each now its own hand-drawn
shape (tasks/geometry/shapes/redraw42_r1.yaml) read from the prompt as typed, at its real mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("soft fabric cone collar for a medium dog", "soft_cone_collar", 0.14),
    ("folded vetbed fleece mat", "vetbed_folded", 0.5),
    ('pair of hand wraps rolled up, 180"', "hand_wrap_rolled", 0.12),
    ("boil and bite mouthguard", "mouthguard", 0.02),
    ("damp gym towel", "gym_towel", 0.4),
    ("curved focus mitt", "focus_mitt", 0.35),
    ("dozen red roses wrapped in kraft paper", "rose_bouquet", 0.7),
    ("hank of natural raffia", "raffia_hank", 0.1),
    ("big fluffy hydrangea head, cut stem", "hydrangea_stem", 0.15),
]


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_prompt_reads_as_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("entry", sorted({e for _t, e, _kg in CASES}))
def test_each_shape_is_hand_drawn_within_the_part_budget(entry: str) -> None:
    assert 3 <= len(catalogue_program(entry).parts) <= 64


def test_a_pair_of_rolled_hand_wraps_is_two_rolls_and_a_stated_sheet_length_keeps_the_plan() -> None:
    """'a pair of' builds the rolled wrap twice; 'rolled, 180 inch' (the sheet's length) stays the sheet plan's."""
    pair = catalogue.design_from_text('pair of hand wraps rolled up, 180"')
    assert len(pair.program.parts) == 2 * len(catalogue_program("hand_wrap_rolled").parts)
    assert catalogue.design_from_text("pair of boxing hand wraps, rolled, 180 inch").entry == "hand_wrap"


@pytest.mark.parametrize(("text", "entry"), [("a hydrangea", "hydrangea_stem"), ("a bouquet of roses", "rose_bouquet"),
                                             ("a sweaty gym towel", "gym_towel"), ("a hand towel", "hand_towel"),
                                             ("raffia ribbon", "raffia_hank"), ("a dog cone", "soft_cone_collar"),
                                             ("an inflatable cone collar", "inflatable_collar")])
def test_the_new_nouns(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
