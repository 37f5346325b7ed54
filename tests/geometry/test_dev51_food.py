"""Session 51 food list (dev51_food): a pack of instant ramen, a carton of oat milk, a bag of coffee beans, a juice box,
a jellied cranberry sauce log, a rack of ribs, a 3 gallon ice cream tub, a takeaway cup and a milkshake, a hash brown,
spanakopita, moussaka, loukoumades, mashed potatoes, whipped cream and tzatziki build as their own entries at their
real mass."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("one pack of instant ramen", "instant_ramen_pack", 0.085),
    ("instant noodles packet", "instant_ramen_pack", 0.085),
    ("1 litre carton of oat milk", "milk_carton", 1.05),
    ("a 1kg bag of espresso beans, valve side up", "coffee_bean_bag", 1.03),
    ("juice box squeezed half flat", "juice_box", 0.21),
    ("cranberry sauce log still showing the can ridges", "cranberry_sauce_log", 0.4),
    ("full rack of pork ribs", "baby_back_ribs", 1.1),
    ("3 gallon tub of vanilla from the dipping cabinet", "ice_cream_tub", 5.0),
    ("paper cup of hot cocoa with marshmallows", "takeaway_cup", 0.48),
    ("chocolate milkshake in a paper cup with a lid", "milkshake_cup", 0.5),
    ("pile of shredded hash browns", "hash_brown", 0.09),
    ("spanakopita triangle", "spanakopita", 0.12),
    ("slice of moussaka", "moussaka_slice", 0.35),
    ("honey-soaked loukoumades", "loukoumades", 0.25),
    ("mound of mashed potatoes with a gravy crater", "mashed_potatoes", 0.24),
    ("mound of whipped cream on a sundae", "whipped_cream", 0.02),
    ("dollop of tzatziki", "tzatziki", 0.1),
])
def test_dev51_food_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0
