"""Session 50's readings and entries (issue #35): a 'pls' mid-request is no noun; a cluster, clump or nest of a thing
is the thing; a bare rug is an area rug (it was the 0.8 m bath mat), carpet and its samples, tiles and pads are
their own goods; a rug's bare 'A by B' is in feet; a rug too wide to roll is folded lengthwise first; a gi is a
folded martial-arts uniform tied with its belt; a Kevlar sleeve is an arm sleeve."""

from __future__ import annotations

import pytest

from contracts.errors import InputError
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


def test_a_please_mid_request_is_no_noun() -> None:
    design = catalogue.design_from_text("yuba sheet pls, one, off the drying rod")
    assert design.concept is not None and design.concept.noun != "pls"
    assert catalogue.design_from_text("a sponge pls, the yellow one").entry == "kitchen_sponge"
    assert catalogue.design_from_text("the towel please, the blue one").entry == "bath_towel"


@pytest.mark.parametrize(("text", "entry"), [
    ("a cluster of oyster mushrooms", "oyster_mushroom"),
    ("a nest of tagliatelle", "pasta_nest"),
    ("hand me a clump of the oyster mushrooms, a whole one", "oyster_mushroom"),
])
def test_a_cluster_clump_or_nest_of_a_thing_is_the_thing(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a rug", "area_rug", 4.5),  # 4 x 6 ft pile rug, 1.5-3 kg/m2
    ("a persian rug, rolled up", "area_rug", 4.5),
    ("carpet", "area_rug", 4.5),
    ("a felt rug pad", "rug_pad", 2.0),  # 4 x 6 ft, 1/4 in felt, 0.8-1.1 kg/m2
    ("a carpet tile", "carpet_tile", 1.0),  # 50 x 50 cm, 3.5-5 kg/m2
    ("Hand me one of the carpet samples, the grey shag square.", "carpet_sample", 0.25),
    ("a white judo gi, folded", "gi_folded", 1.5),  # judo / BJJ gi 1.2-2.2 kg
    ("the Kevlar sleeve, the left one", "arm_sleeve", 0.06),  # 18 in cut-resistant sleeve 40-90 g
])
def test_rugs_carpet_a_gi_and_a_sleeve_are_their_own_goods_at_their_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.67 <= planned_mass(text) / kg <= 1.5


def test_a_bath_rug_is_still_the_bath_mat() -> None:
    assert catalogue.design_from_text("a bath rug").entry == "bath_mat"


@pytest.mark.parametrize(("text", "sides_m"), [
    ("a 2 by 3 rug", (0.914, 0.610)),  # rug sizes are said in feet
    ("a 4x6 rug", (1.829, 1.219)),
    ("a bath mat 50 x 80", (0.8, 0.5)),  # ... a bath mat's in centimetres: the unit nearer its typical size
    ("a 24 by 24 by 4 foam slab", (0.24, 0.24)),  # 'by' as 'x'
    ("silk scarf 90x90", (0.9, 0.9)),  # 90 cm, not 90 inches (2.3 m, over what L0 builds), though nearer 1.6 m
])
def test_bare_sides_are_read_in_the_unit_nearer_the_typical_size(text: str, sides_m: tuple[float, float]) -> None:
    extents = catalogue.design_from_text(text).size.extents_m
    assert extents[0] == pytest.approx(sides_m[0], abs=0.002) and extents[1] == pytest.approx(sides_m[1], abs=0.002)


def test_a_rug_too_wide_to_roll_is_folded_lengthwise_then_rolled() -> None:
    """An 8 x 10 ft rug rolled is 2.44 m long, over the 2 m L0 builds: folded in half along its length first (as a big
    rug is carried), a 1.22 m roll whose cross-section holds both layers (wider than the 5 x 8 ft rug's roll)."""
    big = catalogue.design_from_text("the 8x10 jute rug, rolled up")
    small = catalogue.design_from_text("a 5x8 rug, rolled up")
    assert big.entry == "area_rug" and big.size.extents_m[0] == pytest.approx(1.219, abs=0.002)
    assert "folded lengthwise" in (big.size.stated or "")
    assert big.size.extents_m[1] > small.size.extents_m[1]
    with pytest.raises(InputError, match="outside the supported range"):  # flat, it is bigger than L0 builds
        catalogue.design_from_text("an 8x10 rug")


@pytest.mark.parametrize(("text", "kg"), [
    ("a bag of clay", None),
    ("Can you get me a bag of the stoneware clay? The 12.5 kilo one, unopened.", 12.5),
])
def test_a_bag_of_clay_is_a_sack_of_pugged_clay(text: str, kg: float | None) -> None:
    """A pottery's bag of clay is pugged clay sealed in its plastic sack (set 36: 'a bag of the stoneware clay, the
    12.5 kilo one' was a 10 cm ball of clay, named 'an orange playground ball'); a ball of clay is still the ball."""
    design = catalogue.design_from_text(text)
    assert design.entry == "generic_pouch" and design.concept is not None
    assert "pouch of clay" in (design.concept.fallback_note or "")
    if kg is not None:
        assert design.concept.stated_mass_kg == pytest.approx(kg)
    assert catalogue.design_from_text("a ball of clay").entry == "potters_clay"


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("grab a bunch of fresh coriander from the walk in", "herb_bunch", 0.08),  # a grocer's bunch 50-100 g
    ("a bunch of flat leaf parsley", "herb_bunch", 0.08),
    ("a roti", "roti", 0.04),  # 18 cm whole-wheat roti 30-45 g
    ("a christmas tree skirt", "tree_skirt", 0.5),  # 48 in velvet tree skirt 0.35-0.7 kg
    ("grey 40 pin ribbon cable about 30 cm long", "ribbon_cable", 0.025),  # was a 1.5 kg generic brick
    ("14 inch rubber squeegee blade, spare", "squeegee_blade", 0.02),  # was a 1.1 kg rubber ball
    ("kids tug of war rope, 10 m", "tug_of_war_rope", 3.7),  # 10 m of 25 mm manila; was refused as a 10 m object
    ("silicone repair mat 45x30cm", "floor_mat", 0.5),  # was a 15 kg blob of silicone
])
def test_set_36_and_37_goods_are_their_own_entries_at_their_mass(text: str, entry: str, kg: float) -> None:
    """Post-hoc (sealed sets 36 and 37, after their runs): goods built as generic objects, blocks or balls, or
    refused."""
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_count_of_cloth_goods_is_a_pile_weighing_all_of_them() -> None:
    """'5 yellow mesh bibs/pinnies' were five flat vests laid apart, four dropped as separate bodies: a 3.7 g sliver.
    Cloth goods drawn by hand are piled, one on another, weighing five."""
    one, five = planned_mass("a yellow mesh pinnie"), planned_mass("5 yellow mesh bibs/pinnies")
    assert 3.5 <= five / one <= 6.5
    assert "a stack of 5" in catalogue.design_from_text("5 yellow mesh pinnies").concept.states


def test_a_plain_foam_ball_is_not_drawn_the_colour_of_an_orange() -> None:
    """'a squishy foam ball, size of an orange' was an orange ball of 7 cm, named 'an orange'."""
    plain = catalogue.design_from_text("a squishy foam ball, size of an orange").program.parts[0].color_rgb
    orange = catalogue.design_from_text("an orange foam ball").program.parts[0].color_rgb
    assert plain[2] > plain[0] and orange[0] > orange[2]


@pytest.mark.parametrize("text", ["packet of salt and vinegar crisps", "a bag of sour cream & onion chips",
                                  "a packet of ready salted crisps"])
def test_a_snacks_flavour_is_not_its_fill(text: str) -> None:
    """'packet of salt and vinegar crisps' was a 0.73 kg pouch of sugar ('salt')."""
    assert catalogue.design_from_text(text).entry == "bag_of_chips"


def test_a_bag_with_unnamed_things_in_it_is_the_bag_named() -> None:
    assert catalogue.design_from_text("quilted makeup bag with a few things in it").entry == "makeup_bag"
    assert catalogue.design_from_text("a grocery bag with six oranges inside").entry == "generic_pouch"


def test_a_poncho_still_in_its_packet_is_the_packed_poncho() -> None:
    """Set 37: 'cheap plastic rain ponchos still in the packet' was the 0.4 kg poncho laid out flat."""
    design = catalogue.design_from_text("one of those cheap plastic rain ponchos still in the packet")
    assert design.entry == "poncho_pouch"
    assert planned_mass("a rain poncho in its packet") < 0.15


def test_a_sheet_folded_but_still_too_long_says_what_fits() -> None:
    """'folded bird netting, like 4m by 10m' (set 37) is 2.5 m long folded three times: the error says to roll it
    (rolled, it is folded lengthwise and built) rather than 'folded in quarters' (5 m)."""
    with pytest.raises(InputError, match="say it rolled"):
        catalogue.design_from_text("folded bird netting, like 4m by 10m")
    rolled = catalogue.design_from_text("bird netting, 4m by 10m, rolled")
    assert max(v for v in rolled.size.extents_m if v is not None) <= 2.0
