"""Session 51 home list: a bag of charcoal (full, and half-used with its top folded over), a compact umbrella, a strip
of painter's tape, a block of beeswax, a foam paint brush, a wad of receipts, a foam tombstone, Easter grass, a fake
cobweb, a bedsheet ghost costume, a burlap treat bag and a plastic goody bag build as their own entries at their real
mass."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("bag of charcoal", "charcoal_bag", 7.0),
    ("half-used bag of charcoal folded over at the top", "charcoal_bag_folded", 3.5),
    ("folded umbrella", "compact_umbrella", 0.35),
    ("strip of blue painter's tape", "painters_tape_strip", 0.0025),
    ("block of raw beeswax", "beeswax_block", 0.45),
    ("foam paint brush", "foam_brush", 0.01),
    ("wad of crumpled receipts", "receipt_wad", 0.005),
    ("foam tombstone prop", "foam_tombstone", 0.4),
    ("nest of plastic easter grass", "easter_grass", 0.02),
    ("fake spider web", "fake_cobweb", 0.02),
    ("bedsheet ghost costume with eye holes", "ghost_costume", 0.6),
    ("burlap favor bag", "burlap_treat_bag", 0.02),
    ("plastic goody bag of party favours", "goody_bag", 0.1),
])
def test_dev51_home_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0
