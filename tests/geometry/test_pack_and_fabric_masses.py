"""Masses the words set: a bag of goods sold in small packs weighs a retail pack, a size word scales a bag's fill, a
light fabric said of a heavy-fabric garment weighs it by the fabrics' areal masses (development set 58, sealed 44)."""

from __future__ import annotations

import pytest

from tasks.geometry import concepts
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "lo", "hi"), [
    ("a bag of gummy sweets", 0.12, 0.2),  # retail 140-175 g (not 0.58 kg: a 1 l food bag of them)
    ("a bag of almonds", 0.15, 0.26),  # 150-400 g, most 200 g
    ("a bag of fudge", 0.12, 0.2),
    ("a pouch of dried mango slices", 0.1, 0.2),  # 80-250 g
    ("a bag of rice", 0.5, 1.2),  # staples keep their food bag
])
def test_an_unsized_bag_of_goods_weighs_their_retail_pack(text: str, lo: float, hi: float) -> None:
    assert lo <= planned_mass(text) <= hi


def test_a_stated_mass_or_size_still_sets_the_bag() -> None:
    assert planned_mass("a bag of almonds 500 g") == pytest.approx(0.5, rel=0.02)
    assert planned_mass("a 30 cm bag of almonds") > 2.5 * planned_mass("a bag of almonds")


def test_a_size_word_scales_a_bags_fill() -> None:
    small, plain, big = (planned_mass(f"a {w}bag of fudge") for w in ("small ", "", "big "))
    assert small < 0.5 * plain and big > 2.0 * plain
    assert planned_mass("small bag of rice") < 0.5 * planned_mass("bag of rice")


def test_a_light_fabric_weighs_a_heavy_fabric_garment_by_its_areal_mass() -> None:
    satin, terry = planned_mass("a satin robe"), planned_mass("a bathrobe")
    assert 0.15 < satin / terry < 0.35  # satin ~110 g/m^2 against terry ~450 (retail satin robes 0.2-0.35 kg)
    assert planned_mass("a chunky knit blanket") > 1.6 * planned_mass("a knit blanket")


def test_a_fabric_named_for_something_else_leaves_the_object_alone() -> None:
    text = "the bathrobe on the hook by the silk scarf"
    reading = concepts.read_text(text)
    assert reading.match.concept == "bathrobe"
    assert planned_mass(text) == pytest.approx(planned_mass("a bathrobe"), rel=0.02)
    assert planned_mass("a chunky knit beanie") < 2.0 * planned_mass("a knit beanie")  # (a chunky beanie's mass)
