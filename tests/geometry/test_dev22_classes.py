"""Development set 22's misses (#35, session 36): what a reviewer who never saw the lexicon asked for and L0 built
wrong, fixed by class and tested here with other phrasings than the set's (the set itself: docs/blind/dev22/); and
sealed set 21's leftovers (a striped rolled towel, a rubber band ball, a feather boa, a long rope's coil)."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.request import MAX_SIZE_M
from tasks.geometry import catalogue, fill_words, grammar
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds
from tests.geometry.test_mass_classes import planned_mass


def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _groups(text: str) -> list[str]:
    return [part_group(p.name) for p in _design(text).program.parts]


@pytest.mark.parametrize(("text", "entry"), [
    ("a chili dog", "hot_dog"),  # 'hot dog in a bun' was a 9 g sausage
    ("two street tacos", "taco"),  # 'soft corn taco' was a generic block
    ("a steamed pork bun", "bao_bun"),  # a 'bao bun' was a dumpling
    ("a bean burrito", "burrito"),  # 'burrito' was a naan bread's noun
    ("a burrito wrapped in foil", "foil_burrito"),
    ("an old sock puppet", "sock_puppet"),  # was a hand puppet
    ("a pink ballet tutu", "tutu"),  # a generic block (sealed set 21 and development set 22)
    ("a white tulle petticoat", "crinoline_petticoat"),
    ("a terry headband for washing your face", "spa_headband"),  # a generic strip
    ("a bridal garter", "lace_garter"),
    ("a scout neckerchief with its woggle", "rolled_neckerchief"),
    ("a scout sash with badges", "merit_badge_sash"),  # a generic block
    ("a climbing chalk bag", "chalk_bag"),
    ("a brown leather shoulder bag", "hobo_handbag"),  # 'leather handbag' was a 27 g generic block
    ("a hockey skate guard", "skate_guard"),  # a generic ball
    ("a climbing knee pad", "knee_bar_pad"),
    ("a bouldering pad", "crash_pad"),
    ("a hockey sock with stripes", "hockey_sock"),  # a crew sock
    ("a velour puff for loose powder", "powder_puff"),  # a 12 cm shower puff
    ("a muppet style puppet with a big mouth", "muppet_puppet"),  # a generic block
    ("a climbing chalk ball", "chalk_ball"),  # a red rubber ball
    ("a lavender neck wrap", "neck_wrap"),  # 'neck wrap' was a naan bread ('wrap')
    ("an organza favour bag", "favor_bag"),  # a 0.5 kg generic pouch
    ("a korean sheet mask", "sheet_mask"),
    ("a hockey gear bag", "hockey_bag"),  # a generic pouch of 25 cm
    ("a toiletry bag", "makeup_bag"),  # a 20 x 8 cm pencil case
    ("a square of butter muslin", "cheesecloth"),  # 'folded square of cheesecloth' was a 0.5 kg generic garment
    ("a spool of tulle", "tulle_roll"),  # 'roll of ivory tulle' was a generic garment
    ("a pack of deli cheese slices", "provolone_slices"),  # 'sliced provolone' a generic block
    ("a dyneema sling", "climbing_sling"),  # 'nylon sling' was a medical arm sling of 0.4 kg
    ("a grip sandbag", "stage_sandbag"),  # a flood sandbag with no handle
    ("a makeup brush cleaning mat", "brush_cleaning_mat"),  # a generic blob
    ("a stuff sack", "stuff_sack"),  # 'stuff' was a placeholder word ('some squishy stuff'): a generic block
])
def test_dev22_nouns_build_their_own_object(text: str, entry: str) -> None:
    assert _design(text).entry == entry


def test_a_thing_packed_in_its_stuff_sack_is_the_packed_sack() -> None:
    """'a mummy sleeping bag crammed into its stuff sack' was a 2 m sleeping bag scaled to 46 cm (0.11 kg): what is
    seen is the sack, with the sleeping bag's mass."""
    d = _design("a down sleeping bag stuffed into its compression sack")
    assert d.entry == "stuff_sack"
    assert 0.7 < planned_mass("a synthetic sleeping bag packed in its stuff sack") < 3.0  # 1.3-1.6 kg retail


@pytest.mark.parametrize(("text", "low", "high"), [
    ("a hot dog with ketchup", 0.05, 0.2),  # 0.1 kg (USDA: frank 45-57 g, bun 44 g)
    ("a burrito", 0.25, 0.9),  # 350-600 g
    ("a tutu", 0.06, 0.25),  # a 4.6 l drawn envelope of tulle: was 1 kg at textile's density
    ("a bouldering crash pad", 3.5, 13.0),  # 6-7 kg
    ("a lavender neck wrap", 0.45, 1.8),  # 0.8-1.1 kg of flaxseed
    ("a foam finger", 0.025, 0.12),  # 40-70 g
    ("a giant foam finger", 0.025, 0.12),  # 'giant' is the foam finger's own word, not a size (was 0.4 kg)
    ("an empty hockey bag", 1.0, 4.0),  # 1.5-2.5 kg (a generic pouch of 25 cm before)
    ("a makeup bag stuffed with makeup", 0.15, 1.1),  # ~0.55 kg (was the 60 g empty pencil case)
    ("a paper bag of popcorn", 0.015, 0.12),  # ~40 g: 'paper bag of seed' among the entry's nouns hid the fill
    ("a paper bag of churros", 0.08, 0.4),  # ~0.17 kg
    ("a sheet mask in its foil pouch", 0.012, 0.07),  # ~30 g (was 0.17 kg of gel)
    ("a 120 cm sewn sling", 0.03, 0.12),  # 55-65 g: a sling's stated length is its loop's (a closed band's was doubled)
])
def test_dev22_masses_within_2x(text: str, low: float, high: float) -> None:
    assert low <= planned_mass(text) <= high


def test_new_fills_have_sources_and_read_from_the_text() -> None:
    """Gear, gifts, cosmetics, chalk, baked goods and flaxseed: a bag 'stuffed with' them weighs its fill."""
    for words, key in (("a duffel stuffed with hockey gear", "gear"), ("a stocking full of little gifts", "gifts"),
                       ("a pouch stuffed with makeup", "cosmetics"), ("a bag half full of chalk", "chalk"),
                       ("a bag of churros", "baked"), ("a flaxseed-filled pillow", "flaxseed")):
        fill = fill_words.read_fill(words)
        assert fill is not None and fill.key == key, words
        assert fill.source and 10.0 < fill.bulk_density_kg_per_m3 < 2000.0


def test_a_colour_word_that_names_a_part_keeps_the_body_colour() -> None:
    """'a hot dog with mustard': 'mustard' is a colour word too; it painted the whole bun mustard yellow."""
    parts = _design("a hot dog with mustard").program.parts
    bun = next(p for p in parts if part_group(p.name) == "bun")
    mustard = next(p for p in parts if part_group(p.name) == "mustard")
    assert not np.allclose(bun.color_rgb, mustard.color_rgb, atol=0.05)


def test_two_bare_sizes_go_on_the_longer_sides_in_order() -> None:
    """'a stuff sack, about 9x18 inches' set x = 9 in and y = 18 in: a cylinder lying along x became a disc; the
    larger stated size goes on the object's longer side."""
    d = _design("a stuff sack, about 9x18 inches")
    current = np.asarray(grammar.program_extents(d.program, 64))
    ext = d.size.resolve(current)
    assert int(np.argmax(ext)) == int(np.argmax(current))
    assert float(ext.max()) == pytest.approx(18 * 0.0254, rel=0.02)
    assert sorted(ext)[1] == pytest.approx(9 * 0.0254, rel=0.1)


def test_a_long_rope_said_coiled_is_built_as_a_hank() -> None:
    """'coiled dynamic climbing rope, 60 m, 9.8 mm' was refused (a flat spiral of 8 turns 3.2 m across): a long
    rope coiled by hand is loops laid one on another, about an arm span across, its mass its length's."""
    d = _design("coiled climbing rope, 60 m, 9.8 mm")
    assert any(part_group(p.name) == "loop" for p in d.program.parts)
    mass = planned_mass("coiled climbing rope, 60 m, 9.8 mm")
    assert 1.8 < mass < 7.5  # 62 g/m x 60 m = 3.7 kg (retail specs)
    assert float(np.max(grammar.program_extents(d.program, 64))) <= MAX_SIZE_M


def test_stripes_are_drawn_on_a_rolled_and_a_flat_sheet() -> None:
    """'rolled up striped beach towel' had no stripes (a blind judge: a rolled yoga mat): bands round the roll; on a
    flat or folded sheet, bands across its longer side."""
    for text in ("a rolled up striped beach towel", "a striped yoga mat", "a folded striped beach towel"):
        assert "stripe" in _groups(text), text
    assert "stripe" not in _groups("a rolled up beach towel")


def test_a_rubber_band_ball_shows_its_bands() -> None:
    """A rubber band ball was a plain red sphere: bands wound round it, each a great circle of its own colour."""
    parts = _design("a rubber band ball").program.parts
    bands = [p for p in parts if part_group(p.name).startswith("band")]
    assert len(bands) >= 10
    assert len({tuple(np.round(p.color_rgb, 2)) for p in bands}) >= 4


def test_a_feather_boa_is_an_open_fluffy_length() -> None:
    """A feather boa was a closed ring (a blind judge: a big scrunchie): an open length in loose S-bends, clumps of
    fluff all along it, about its 1.8 m laid out."""
    d = _design("a pink feather boa")
    assert "fluff" in _groups("a pink feather boa")
    assert d.program.parts[0].name == "body"
    mass = planned_mass("a pink feather boa")
    assert 0.03 < mass < 0.16  # 40-80 g (party supply listings)


def test_a_hydration_bladder_has_its_drinking_tube() -> None:
    """A hydration bladder read as a hot water bottle: its drinking tube and bite valve, out of its bottom end."""
    groups = _groups("a hydration bladder")
    assert "hose" in groups and "bite valve" in groups


def test_a_stage_sandbag_has_its_handle_and_weight() -> None:
    """A stage sandbag read as a black cushion (sealed set 21 and development set 22): a webbing handle arching
    over its top, sewn down at both ends, and a 25 lb sandbag's mass."""
    groups = _groups("a stage sandbag")
    assert "handle" in groups and "handle tab" in groups
    assert 5.5 < planned_mass("a stage sandbag") < 23.0  # 11.3 kg (retail 25 lb)
    lo, _hi = program_bounds(_design("a stage sandbag").program)
    assert lo[2] > -1e-3  # the handle's arch does not poke out under the bag


def test_a_plastic_bag_of_known_goods_shows_them() -> None:
    """'a half-empty plastic bag of cotton rounds' was the empty 6 g carrier bag: a plastic bag 'of' goods the
    lexicon knows is a pouch of them seen through its film, their mass its fill's; a bare plastic bag stays one."""
    assert _design("a plastic bag of cotton pads").entry == "generic_pouch"
    assert "fill" in _groups("a plastic bag of cotton pads")
    assert _design("a plastic bag").entry == "carrier_bag"
    assert 0.015 < planned_mass("a plastic bag of cotton rounds") < 0.12  # ~40 pads at 0.6 g plus the bag
