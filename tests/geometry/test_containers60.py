"""Session 60's supermarket containers (containers60): a tub, a carton box, a gallon jug and an egg box build as their
own entries at their real mass with the goods' name on the label, and a container of goods the lexicon does not name
reads as the lexicon's container of that kind (development set 60: a tub of greek yogurt was a black plant pot, a box
of cornflakes a tote bag, a tube of tomato puree a block, a bottle of shower gel a pillar candle)."""

from __future__ import annotations

import pytest

from contracts.request import AssetRequest
from tasks.geometry import catalogue, container_words, pipeline
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg", "printed"), [
    ("a 500g tub of greek yogurt", "food_tub", 0.52, "GREEK YOGURT"),
    ("a box of cornflakes, the 500g one, bit dented on one corner", "retail_box", 0.56, "CORNFLAKES"),
    ("a gallon of milk in a plastic jug", "milk_jug", 3.96, "MILK"),
    ("cardboard egg box for 6 eggs, empty", "egg_box", 0.03, None),
    ("a 16 oz tub of sour cream", "food_tub", 0.47, "SOUR CREAM"),
    ("a tub of coleslaw", "food_tub", 0.3, "COLESLAW"),
])
def test_a_container_builds_at_its_mass_with_its_goods_on_the_label(text: str, entry: str, kg: float,
                                                                     printed: str | None) -> None:
    assert_builds_at_its_mass(text, entry, kg)
    prints = catalogue.design_from_text(text).program.prints
    assert [p.text for p in prints] == ([printed] if printed else [])


@pytest.mark.parametrize(("text", "entry", "printed"), [
    ("a tube of tomato puree", "toothpaste_tube", "TOMATO PUREE"),
    ("500ml bottle of shower gel, the squeezy coconut one", "squeeze_bottle", "SHOWER GEL"),
    ("honey in one of those squeezy bear bottles", "squeeze_bottle", "HONEY"),
    ("a crushed 2 litre fizzy drink bottle", "plastic_water_bottle", "FIZZY DRINK"),
    ("a box of 6 chewy cereal bars, oat and raisin", "retail_box", "CHEWY CEREAL BARS"),
    ("a pot of hummus", "food_tub", "HUMMUS"),
    ("squeezy ketchup bottle, the upside down kind", "squeeze_bottle", "KETCHUP"),
])
def test_an_unnamed_container_of_goods_is_the_lexicons_container_printed_with_them(text: str, entry: str,
                                                                                    printed: str) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry and [p.text for p in design.program.prints] == [printed]


@pytest.mark.parametrize(("text", "head", "before", "found"), [
    ("a tube of tomato puree", "tube", [], ("squeeze tube", "tomato puree")),
    ("a squeezy honey bottle", "bottle", ["squeezy", "honey"], ("squeeze bottle", "honey")),
    ("a bottle of lemonade", "bottle", [], ("plastic bottle", "lemonade")),
    ("a carton of orange juice", "carton", [], ("milk carton", "orange juice")),
    ("honey in one of those squeezy bear bottles", "honey", [], ("squeeze bottle", "honey")),
    ("a bottle", "bottle", [], None),
    ("a spray bottle", "bottle", ["spray"], None),
    ("a box", "box", [], None),
    ("a blue plastic bottle", "bottle", ["blue", "plastic"], None),
    ("a felt gift box", "box", ["felt", "gift"], None),
    ("socks in a drawer", "socks", [], None),
])
def test_container_of_goods_words(text: str, head: str, before: list[str], found: tuple[str, str] | None) -> None:
    assert container_words.container_of_goods(text, head, before) == found


def test_an_empty_walled_container_keeps_its_shape() -> None:
    full, _ = pipeline.mesh_from_text(AssetRequest(text="an egg box"), pipeline.settings_from_contract("draft"))
    empty, _ = pipeline.mesh_from_text(AssetRequest(text="an empty egg box"), pipeline.settings_from_contract("draft"))
    h_full = pipeline.arrays_to_mesh(full).extents[2]
    assert pipeline.arrays_to_mesh(empty).extents[2] == pytest.approx(h_full, rel=0.05)
