"""Session 43's redraw (r3): objects the blind judges could not name as built (sealed set 29). Each prompt now reads as
an entry with a hand-written shape (tasks/geometry/shapes/redraw43_r3.yaml) drawn with the cues a person names it by,
and its built mass is within 2x of the real object's: a purple velvet church kneeler (was the throw cushion's thin
slab, 'a purple mouse pad') as a plump purple cushion with a gold cross and a brass carry ring; a rolled red felt
Pentecost banner (was a generic block, 'a red bar of soap') rolled with its V-pointed end laid out, a white dove, flames
and gold trim; a fresh mozzarella ball (was a ball under basil leaves, 'a white turnip') whole beside two slices with a
basil leaf; a proofed ball of pizza dough (was a slumped disc, 'a bar of soap') as a pale dome on a floured board; a
calzone stuffed with ricotta and ham (was a flat half-moon at a tenth of its mass: 'stuffed' read as plush) puffed
with a rope edge, char spots, sauce and basil; a flood sandbag (was a pouch with a cap, 'a tube of lotion') as a
tan filled sack, tied, its gathered top ruffled on the ground. Checked on the programs: the readings in the default
run, the built masses under -m slow."""

from __future__ import annotations

import functools

import pytest

from contracts.lexicon import load_lexicon
from tasks.agents.intent import match_material, own_nouns
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import drawn_mass_kg, planned_mass

# prompt as typed, entry, the real object's mass [kg]
CASES = [
    ("purple velvet church kneeler cushion", "church_kneeler", 0.7),
    ("rolled red felt pentecost banner", "felt_banner_rolled", 0.5),
    ("fresh mozzarella ball, 125 g", "fresh_mozzarella", 0.125),
    ("ball of pizza dough 250g, proofed", "pizza_dough", 0.25),
    ("a folded calzone stuffed with ricotta and ham", "calzone", 0.45),
    ("a filled sandbag for flood protection", "sandbag", 16.0),
]


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


@pytest.mark.parametrize(("text", "entry", "_kg"), CASES)
def test_the_prompt_reads_as_the_entry(text: str, entry: str, _kg: float) -> None:
    d = _design(text)
    assert d.entry == entry
    assert len(d.program.parts) <= 64


def test_a_stuffed_calzone_is_bread_not_plush() -> None:
    """'stuffed' names the plush material; a calzone's own nouns take it ('stuffed calzone'), so L1 weighs bread."""
    d = _design("a folded calzone stuffed with ricotta and ham")
    assert match_material("a folded calzone stuffed with ricotta and ham", None, "bread", own_nouns(d.concept)) == "bread"


def test_the_proofed_dough_is_drawn_proofed_and_a_plain_dough_ball_still_slumps() -> None:
    """'proofed' slumps a round body; the pizza dough is drawn proofed on its board, so it is not slumped again."""
    assert "slumped" not in (_design("ball of pizza dough 250g, proofed").concept.states or [])
    assert _design("a ball of bread dough").entry == "dough_ball"
    assert "slumped" in (_design("a proved dough ball").concept.states or [])


@pytest.mark.slow
@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_built_mass_is_within_2x_of_the_real_mass(text: str, entry: str, kg: float) -> None:
    """L1's mass as the blind bench weighs it (tests.geometry.test_mass_classes.planned_mass): the density over the
    volume built at the final size, or the mass the request states ('125 g')."""
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (entry, planned_mass(text), kg)


@pytest.mark.slow
@pytest.mark.parametrize("entry", [e for _t, e, _k in CASES])
def test_the_density_is_the_sourced_mass_over_the_built_volume(entry: str) -> None:
    """Density is the sourced mass over the built shape's volume at size_m (L0's draft mesh, 48 cells)."""
    e, mass = load_lexicon().entries[entry], drawn_mass_kg(entry)
    assert 0.85 * e.mass_kg <= mass <= 1.15 * e.mass_kg, (entry, mass, e.mass_kg)
