"""Session 52 new list: a beekeeping suit, a disposable coverall, a pair of work knee pads, a bus hand strap and a beeswax foundation sheet build as their own entries at their real mass."""

from __future__ import annotations

import pytest

from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("grab the bee suit hanging by the door", "bee_suit", 1.2),
    ("tyvek suit", "disposable_coverall", 0.2),
    ("my foam knee pads", "work_knee_pads", 0.5),
    ("the rubber hand strap loop hanging off the rail", "bus_hand_strap", 0.15),
    ("beeswax foundaton sheet for a deep frame", "beeswax_foundation", 0.045),
])
def test_dev52_new_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)
