"""Readings fixed post-hoc from sealed set 45 (session 59): British 'round' after a participle is a preposition; a
weighed pack before its goods without 'of' is a pack of them."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry"), [
    ("Clump of bladderwrack tangled round the longline", "bladderwrack_clump"),  # ('longline' was the object)
    ("a scarf wrapped round the neck", "scarf"),  # ('neck' was: a generic blob)
    ("a round cushion", "round_cushion"),  # (the shape word stays a shape word)
])
def test_round_after_a_participle_is_around(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_weighed_pack_before_its_goods_is_a_pack_of_them() -> None:
    d = catalogue.design_from_text("200g bag dried shiitake mushrooms, resealable")  # (was one 200 g mushroom)
    assert d.entry == "generic_pouch" and [p.text for p in d.program.prints] == ["DRIED SHIITAKE MUSHROOMS"]
    assert planned_mass("200g bag dried shiitake mushrooms, resealable") == pytest.approx(0.2, rel=0.02)
    assert catalogue.design_from_text("1kg bag rice").entry == "generic_pouch"
    assert catalogue.design_from_text("a 200g bag").entry != "generic_pouch"  # (no goods: the bag)
