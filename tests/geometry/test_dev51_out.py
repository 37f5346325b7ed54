"""Session 51's outdoor, playground, ceremony and small-pet list (dev51_out): a snowball and a snowman's rolled base, a
car tyre (a tire swing), a belt swing seat, a flower lei, a rolled diploma, program and poster, a set of cruiser
wheels, a sliding mitt, a bag of paper bedding and a rabbit harness with its lead build as their own entries at their
real mass."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a packed snowball", "snowball", 0.12),
    ("big rolled snowball for the snowman's base", "giant_snowball", 25.0),  # ~80 kg real; L1 plans at most 25 kg
    ("tire swing hanging on chains", "car_tire", 9.0),
    ("rubber belt swing seat", "belt_swing_seat", 2.0),
    ("fresh orchid lei", "flower_lei", 0.16),
    ("rolled diploma tied with a ribbon", "diploma_scroll", 0.02),
    ("ceremony program rolled up in my hand", "rolled_program", 0.025),
    ("rolled up poster", "rolled_poster", 0.1),
    ("set of soft cruiser wheels", "skateboard_wheels", 0.44),
    ("padded sliding mitt", "sliding_mitt", 0.12),
    ("bag of paper bedding", "paper_bedding_bag", 0.75),
    ("soft rabbit harness with lead", "rabbit_harness", 0.07),
])
def test_dev51_out_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


@pytest.mark.parametrize(("text", "entry"), [
    ("snowball", "snowball"), ("giant snowball", "giant_snowball"), ("tire swing", "car_tire"),
    ("old car tyre", "car_tire"), ("bike tire", "bike_tire"), ("belt swing", "belt_swing_seat"),
    ("swing seat", "belt_swing_seat"), ("hawaiian lei", "flower_lei"), ("lei", "flower_lei"),
    ("diploma scroll", "diploma_scroll"), ("skateboard wheels", "skateboard_wheels"), ("sliding mitt", "sliding_mitt"),
    ("bag of pet bedding", "paper_bedding_bag"), ("small animal bedding", "paper_bedding_bag"),
    ("rabbit harness", "rabbit_harness"), ("small pet harness", "rabbit_harness"),
])
def test_dev51_out_wordings_read_as_their_entry(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
