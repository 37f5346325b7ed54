"""Session 52 dev list b: a dry maple leaf, a clump of wet leaves, a strapped stack of banknotes, a bank deposit bag and a full canvas coin bag build as their own entries at their real mass."""

from __future__ import annotations

import pytest

from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("single dry maple leaf, curled up at the edges", "dry_maple_leaf", 0.001),
    ("soggy clump of wet oak leaves, like two handfuls", "wet_leaf_clump", 0.3),
    ("strapped stack of 100 twenty dollar bills w/ the paper band", "banknote_stack", 0.1),
    ("navy canvas zip deposit bag, empty, about 11x9 in", "bank_deposit_bag", 0.12),
    ("full fed coin bag of quarters ($1000), canvas, tied shut", "coin_bag", 22.7),
])
def test_dev52_b_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)
