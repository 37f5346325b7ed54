"""Session 41's redraw (helper r1): objects the blind judges could not name as built, each now its own hand-drawn
shape (tasks/geometry/shapes/redraw41_r1.yaml) read from the prompt as typed, at its real mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("plush tooth toy for kids, smiling, about 20 cm", "plush_tooth", 0.1),
    ('folding 26" mtb tire, folded up', "folded_bike_tire", 0.6),
    ("Gel saddle cover", "saddle_cover", 0.12),
    ("silicone swim cap", "swim_cap", 0.055),
    ("EVA foam kickboard for lap swimming", "kickboard", 0.2),
    ("soft plastic worm lure purple 10 inch", "worm_lure", 0.009),
    ("chalk ball", "chalk_ball", 0.06),
    ("chalk bag, half full", "chalk_bag", 0.15),
    ("a 26 inch mountain bike tire", "bike_tire", 0.7),
]


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_prompt_reads_as_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("entry", sorted({e for _t, e, _kg in CASES}))
def test_each_shape_is_hand_drawn_within_the_part_budget(entry: str) -> None:
    assert 3 <= len(catalogue_program(entry).parts) <= 64


def test_a_stress_ball_shaped_like_a_molar_takes_the_tooths_shape() -> None:
    d = catalogue.design_from_text("squishy stress ball shaped like a molar")
    assert d.entry == "stress_ball" and d.concept is not None and d.concept.shape_from == "plush_tooth"


@pytest.mark.parametrize(("text", "entry"), [("bike tire", "bike_tire"), ("bicycle tyre", "bike_tire"),
                                             ("mtb tire", "bike_tire"), ("folded bike tire", "folded_bike_tire"),
                                             ("bike seat cover", "saddle_cover"), ("gel saddle", "bike_saddle")])
def test_tyre_and_saddle_words(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
