"""Development set 20's misses (#35, session 34): what a reviewer who never saw the lexicon asked for and L0 built
wrong, fixed by class and tested here with other phrasings than the set's (the set itself: docs/blind/dev20/)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, grammar
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds, program_sdf
from tests.geometry.test_mass_classes import planned_mass


def _groups(text: str) -> list[str]:
    return [part_group(p.name) for p in catalogue.design_from_text(text).program.parts]


@pytest.mark.parametrize(("text", "entry"), [
    ("a red balloon", "balloon_party"),  # the bare 'balloon' was a 300 g water balloon
    ("a water balloon", "water_balloon"),
    ("a roll of purple vet wrap", "elastic_bandage"),  # 'wrap' was a 1.3 kg burrito
    ("a paper party hat", "party_hat"),  # was a generic garment of 90 g
    ("an inflatable recovery collar for a dog", "inflatable_collar"),  # was a 0.3 g generic ball
    ("a full black garbage bag, tied", "trash_bag"),
    ("a red biohazard waste bag", "biohazard_bag"),
    ("a packing cube full of clothes", "packing_cube"),  # 'stuffed w/ t-shirts' was a 19 g plush block of 'shirts'
    ("three red licorice twists", "licorice_twist"),  # 'twizzlers' was a generic block
    ("a lab wash bottle", "wash_bottle"),
    ("a churro dusted with sugar", "churro"),
    ("a soft breadstick", "breadstick"),
])
def test_dev20_nouns_build_their_own_object(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_words_between_a_container_and_its_goods_do_not_hide_the_noun() -> None:
    """'a tube of acrylic paint' is the lexicon's 'tube of paint' (it was a generic block); 'a slice of swiss cheese',
    a noun of its own, is left whole."""
    assert catalogue.design_from_text("a half used tube of oil paint").entry == "toothpaste_tube"
    assert catalogue._of_words_moved("a tube of acrylic paint") == "a acrylic tube of paint"
    assert catalogue._of_words_moved("a slice of swiss cheese") == "a slice of swiss cheese"
    assert catalogue._of_words_moved("a bag of the rice") == "a bag of the rice"  # a stop word stays


def test_a_request_opening_with_pls_is_not_the_goods_of_a_packed_sack() -> None:
    """'pls make a ... jacket stuffed into its own pocket' was the whole jacket as a 3.6 kg plush (the opening hid
    the packed-sack reading, and 'stuffed' made it plush)."""
    design = catalogue.design_from_text("plz make a puffer jacket stuffed into its own pocket")
    assert design.entry in ("packed_down_jacket", "packed_pouch")  # (its own pocket: the small packed pouch since
    # session 58, as 'its own pouch' was; a stuff sack before)
    assert 0.3 <= planned_mass("pls make a down puffer jacket stuffed into its own pocket") <= 1.0


def test_a_folded_sheet_with_its_flat_size_weighs_that_sheet() -> None:
    """'a fleece blanket folded in 4, 75 x 100 cm' weighed 0.81 kg, more than the 1.3 x 1.5 m throw (0.71 kg): the
    stated outline shrank the pile's footprint and the thin-goods scaling then raised its density ~3x. It weighs its
    area's share of the throw now (0.75 m^2 of 1.95 m^2 at ~0.33 kg/m^2)."""
    whole = planned_mass("a fleece blanket folded in 4")
    small = planned_mass("a fleece blanket folded in 4, 75 x 100 cm")
    assert 0.6 <= whole <= 0.8
    assert 0.18 <= small <= 0.35 and small < 0.5 * whole


@pytest.mark.parametrize(("text", "low", "high"), [
    ("a balloon", 0.002, 0.006),  # a 12 in latex party balloon, 3-4 g (was a 300 g water balloon)
    ("an inflatable donut collar for a cat", 0.06, 0.24),  # 100-150 g
    ("a paper cone party hat", 0.004, 0.016),  # ~8 g
    ("a twizzler", 0.006, 0.022),  # 11 g
    ("a lab wash bottle full of water", 0.3, 0.8),  # 500 ml of water in ~40 g of LDPE
])
def test_dev20_masses_within_2x_of_the_real_object(text: str, low: float, high: float) -> None:
    assert low <= planned_mass(text) <= high


def test_a_glove_blown_up_is_a_balloon_of_a_glove() -> None:
    """'a latex glove blown up like a balloon' was the flat glove: now a round palm (as thick as it is wide, nearly),
    fat fingers and a knotted cuff."""
    flat = catalogue.design_from_text("a latex glove")
    blown = catalogue.design_from_text("a latex glove blown up and tied off")
    assert "knot" in [p.name for p in blown.program.parts] and "knot" not in [p.name for p in flat.program.parts]
    ef, eb = grammar.program_extents(flat.program, 48), grammar.program_extents(blown.program, 48)
    assert eb[2] / eb[:2].max() > 2.0 * ef[2] / ef[:2].max()


def test_a_churro_has_star_ridges_and_a_breadstick_none() -> None:
    """A churro is piped through a star nozzle: grooves along it, a star seen end on (a smooth rod read as a
    breadstick)."""
    assert _groups("a churro").count("groove") == 6
    assert "groove" not in _groups("a breadstick")
    design = catalogue.design_from_text("a churro")
    lo, hi = (np.asarray(v) for v in program_bounds(design.program))
    centre, r = 0.5 * (lo + hi), 0.5 * float((hi - lo)[1])
    angles = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
    ring = np.stack([np.full_like(angles, centre[0]), centre[1] + 0.9 * r * np.cos(angles),
                     centre[2] + 0.9 * r * np.sin(angles)], axis=1)
    inside = program_sdf(ring, design.program) < 0
    assert 0 < inside.sum() < len(inside)  # at 90 % of the radius: ridges in, grooves out


def test_a_wash_bottle_has_its_bent_delivery_tube() -> None:
    groups = _groups("a wash bottle")
    assert "nozzle" in groups and "cap" in groups
    assert "nozzle" not in _groups("a shampoo bottle")


def test_goods_in_a_clear_bag_are_built_as_the_goods() -> None:
    """'a returned hoodie, folded up inside a clear plastic bag' was a full orange stuff sack (what a packed sack
    shows); through a clear bag what is seen is the folded hoodie. An opaque sack is still the sack."""
    design = catalogue.design_from_text("a sweatshirt folded inside a clear zip bag")
    assert design.entry != "stuff_sack" and any("clear bag" in w for w in design.warnings)
    assert catalogue.design_from_text("a sleeping bag stuffed in its compression sack").entry == "stuff_sack"


def test_a_sheet_bent_in_half_is_folded_in_half() -> None:
    """'a sheet of craft foam bent in half' was the flat sheet (the state 'bent' is not a sheet's)."""
    bent = catalogue.design_from_text("a sheet of craft foam, bent in half")
    flat = catalogue.design_from_text("a sheet of craft foam")
    eb, ef = grammar.program_extents(bent.program, 64), grammar.program_extents(flat.program, 64)
    assert eb[:2].min() == pytest.approx(0.5 * ef[:2].max(), rel=0.1)  # the long side halved
    assert eb[2] > 2.0 * ef[2]  # two layers and the fold


def test_goods_big_enough_to_tell_apart_show_through_a_bag_in_place_of_a_label() -> None:
    """'a bag of gummy bears' was a labelled pack read as a bag of flour (a generic 'candy' fill); 'a bag of 100
    cotton balls' a plain pillow (too many balls to draw: they are drawn fewer and larger now). Rice stays a fill."""
    for text in ("a bag of gummy bears", "a bag of cotton balls"):
        groups = _groups(text)
        assert groups.count("fill") >= 6 and "label" not in groups, text
    assert "fill" not in _groups("a 2 kg bag of rice")


@pytest.mark.parametrize(("text", "low", "high"), [
    ("a 6 x 9 ft canvas drop cloth, folded", 0.65, 2.6),  # 5 m2 of 8 oz canvas ~1.3 kg
    ("a small pouch of wet cat food", 0.04, 0.2),  # 85-100 g retail pouches
])
def test_more_dev20_masses(text: str, low: float, high: float) -> None:
    assert low <= planned_mass(text) <= high


def test_a_size_of_what_the_object_makes_is_not_its_size() -> None:
    """'a ball of pizza dough, enough for one 12 inch pizza' was a 30 cm ball (sealed set 19): the size belongs to
    the pizza. The amount clause is dropped; the object keeps its typical size."""
    plain = catalogue.design_from_text("a ball of bread dough")
    said = catalogue.design_from_text("a ball of bread dough, enough to make one 9 inch loaf, floured")
    assert said.entry == plain.entry and not said.size.explicit
    assert grammar.program_extents(said.program, 32).max() == pytest.approx(
        grammar.program_extents(plain.program, 32).max(), rel=0.05)


def test_a_loosely_rolled_sheet_is_a_wider_roll_round_an_open_core_of_the_same_mass() -> None:
    """'a silicone baking mat, rolled up loosely' was the tight 2.4 cm rod a blind reviewer named a thin rod (sealed
    set 19); the roll's core and packing now enter the state change, so its mass stays the mat's."""
    tight, loose = "a silicone baking mat, rolled up", "a silicone baking mat, rolled up loosely"
    et = grammar.program_extents(catalogue.design_from_text(tight).program, 48)
    el = grammar.program_extents(catalogue.design_from_text(loose).program, 48)
    assert sorted(el)[1] > 1.5 * sorted(et)[1]
    assert planned_mass(loose) == pytest.approx(planned_mass(tight), rel=0.1)


def test_a_stress_ball_wears_its_smiley_unless_said_plain() -> None:
    """A plain yellow foam ball was named a tennis ball (sealed sets 17, 19) and a lemon (set 20)."""
    assert {"eye", "mouth"} <= set(_groups("a yellow foam stress ball"))
    assert not {"eye", "mouth"} & set(_groups("a plain stress ball"))


def test_a_plush_keychain_weighs_a_small_plush_on_its_ring() -> None:
    """'tiny plush bunny keychain' was 3 g (sealed set 20; retail 25-35 g): the keychain size scaled the plush's mass
    as a solid's (L^3) and 'tiny' shrank it again; a plush keeps ~L^2 and a keychain is small by nature."""
    assert 0.015 <= planned_mass("a tiny plush teddy bear keychain") <= 0.06


def test_a_deflated_beach_ball_spreads_its_gores_from_the_cap() -> None:
    """A deflated striped beach ball lost its thin meridian stripes when squashed and was named a foil balloon
    (sealed sets 19 and 20): spread flat, its gores radiate from the cap in the stripes' colours."""
    design = catalogue.design_from_text("a deflated beach ball")
    gores = [p for p in design.program.parts if part_group(p.name) == "gore"]
    assert len({p.name.split()[1] for p in gores}) == 6 and len({p.color_rgb for p in gores}) >= 3
    assert "cap" in _groups("a deflated beach ball")
    ext = grammar.program_extents(design.program, 48)
    assert ext[2] < 0.25 * ext[:2].max()  # spread flat
