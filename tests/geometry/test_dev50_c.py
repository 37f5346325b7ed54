"""Session 50 dev list c: a foam balance beam, a fleece hutch liner, a bar of skate wax and a rubber safety tile build as their own entries at their real mass."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("foam balance beam", "foam_balance_beam", 3.0),
    ("fleece hutch liner", "hutch_liner", 0.4),
    ("bar of skate wax", "skate_wax", 0.1),
    ("rubber safety surface tile", "rubber_safety_tile", 6.0),
])
def test_dev50_c_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0
