"""Session 47's redraw (helper f): a fresh user's prompts the blind judges could not name as built, each read as its
entry (tasks/geometry/shapes/redraw47_f.yaml draws the new ones and the redrawn brie, burrata and tailor's ham) at its
real mass (within 2x); the near kinds they were confused with still read as before."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue, phrase
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("1kg brie wheel", "brie", 1.0),
    ("burrata", "burrata", 0.2),
    ("pork belly slab", "pork_belly_slab", 1.5),
    ("one raw pork dumpling", "raw_dumpling", 0.025),
    ("ball of dough", "dough_ball", 0.3),
    ("pack of wonton wrappers", "wonton_wrappers", 0.454),
    ("sheepskin hanging on the rail, put it in the crate", "sheepskin", 3.3),
    ("grab that rolled up fleece off the skirting table", "sheep_fleece", 3.0),
    ("pick up the clump of dags on the board", "dags", 0.15),
    ("bag of clipped fur by the table pls", "bag_of_fur", 0.5),
    ("deflated ball in the corner", "soccer_ball", 0.43),
    ("tailors ham", "tailors_ham", 0.65),
]


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_prompt_reads_as_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("shape", ["brie", "burrata", "pork_belly_slab", "raw_dumpling", "wonton_wrappers",
                                   "sheepskin", "dags", "bag_of_fur", "tailors_ham"])
def test_each_shape_is_hand_drawn_within_the_part_budget(shape: str) -> None:
    assert 3 <= len(catalogue_program(shape).parts) <= 64


def test_the_brie_is_a_wide_wheel_with_a_wedge_cut_showing_its_paste() -> None:
    """A stated 1 kg is the brie's own mass: built at its ~22 cm, not a camembert's 11 cm; its cut shows the paste."""
    d = catalogue.design_from_text("1kg brie wheel")
    assert any(p.name.startswith("reveal cut") and p.operation == "subtract" for p in d.program.parts)
    assert (d.concept.typical_size_m or 0.0) >= 0.2  # type: ignore[union-attr]
    assert catalogue.design_from_text("camembert").entry == "camembert"


def test_a_dumpling_is_the_head_noun_not_pork() -> None:
    """The tagger takes 'dumpling' for a participle; it stays the object ('pork dumpling' was ground meat)."""
    assert "dumpling" in phrase.ING_NOUNS
    assert catalogue.design_from_text("a chicken dumpling").entry == "dumpling"
    assert catalogue.design_from_text("pork dumpling").entry == "dumpling"


def test_a_deflated_ball_is_a_soccer_ball_dented() -> None:
    d = catalogue.design_from_text("deflated ball in the corner")
    assert "deflated" in (d.concept.states or [])  # type: ignore[union-attr]
    assert any(p.name == "dent" for p in d.program.parts)


def test_the_burrata_is_knotted_and_split_with_its_cream_run_out() -> None:
    """The hand drawing: gathered and knotted on top, split, its cream run out onto the board (already slumped)."""
    names = [p.name for p in catalogue.design_from_text("a burrata").program.parts]
    assert any(n.startswith("stracciatella") for n in names) and any(n.startswith("knot") for n in names)


@pytest.mark.parametrize(("text", "entry"), [
    ("camembert", "camembert"), ("a wedge of brie cheese", "brie"), ("a ball of fresh mozarella", "fresh_mozzarella"),
    ("a rubber ball", "rubber_ball"), ("a ball", "rubber_ball"), ("deflated rubber ball", "rubber_ball"),
    ("a deflated beach ball", "beach_ball"), ("fleece blanket", "throw_blanket"), ("fleece jacket", "jacket"),
    ("bin bag", "trash_bag"), ("a dumpling", "dumpling"), ("a wonton", "wonton"), ("pork belly", "pork_belly_strip"),
    ("raw wool", "sheep_fleece"), ("a ball of dough", "dough_ball"), ("a pressing ham", "tailors_ham"),
])
def test_the_near_kinds_read_as_before(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
