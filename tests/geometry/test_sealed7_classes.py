"""Classes of failure a blind judge found in the seventh sealed set, fixed by class (#35) and checked here on other
goods and phrasings than the set's: a size stated along one axis of a long or flat good sets that axis (or the
outline) and its mass follows, a bag or pack of goods is a bag holding them, flat and thin goods have their form (a
bib's neck, a nappy's hourglass, a mailer's flap, a crumpled film bag, a bed's floor), and words once misread (a
roll of bubble wrap, a heat pack) build what they name.

Real masses: typical retail or supplier figures (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, pipeline
from tasks.geometry.grammar.parts import part_group
from contracts.request import AssetRequest
from tests.geometry.test_mass_classes import planned_mass


def _groups(text: str) -> tuple[str, set[str]]:
    d = catalogue.design_from_text(text)
    return d.entry, {part_group(p.name) for p in d.program.parts}


def _extents(text: str) -> np.ndarray:
    """The built mesh's extents at draft, longest first [m]."""
    arrays, _info = pipeline.mesh_from_text(AssetRequest(text=text), pipeline.settings_from_contract("draft"))
    return np.sort(pipeline.arrays_to_mesh(arrays).extents)[::-1]


# ---------------------------------------------------------------------- 1. a size along one axis of a long or flat good
@pytest.mark.parametrize("text,entry,length,across,real", [
    # PE foam ~28 kg/m^3 x pi x (3.25 cm)^2 x 120 cm ~ 0.11 kg
    ("a 1.2 m pool noodle", "pool_noodle", 1.2, 0.08, 0.11),
    # retail 80-100 cm fibre-filled draught excluders 0.3-0.6 kg, ~10-12 cm across
    ("a 90 cm draught excluder", "draught_excluder", 0.9, 0.15, 0.45),
    # retail 100 cm bolster and body pillows 0.8-1.2 kg, ~17-20 cm across
    ("a bolster pillow 100 cm long", "bolster", 1.0, 0.25, 0.9),
])
def test_a_length_sets_a_long_goods_length_only(text: str, entry: str, length: float, across: float,
                                                real: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    ext = _extents(text)
    assert abs(ext[0] - length) < 0.02 * length and ext[1] < across, (text, ext)
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


@pytest.mark.parametrize("text", ["a 150 cm foam pool noodle", "a 60 x 90 cm bath mat"])
def test_a_long_or_flat_goods_proxy_hugs_it(text: str) -> None:
    """CoACD's coarse copy keeps cells across the thin side (a 6.5 cm noodle was lost between 4.8 cm cells)."""
    s = pipeline.settings_from_contract("draft")
    arrays, _info = pipeline.mesh_from_text(AssetRequest(text=text), s)
    proxy = pipeline.build_proxy(arrays, s.coacd)
    ratio = float(proxy["union_volume_m3"]) / float(pipeline.arrays_to_mesh(arrays).volume)
    assert 0.9 <= ratio <= 1.6, (text, ratio)


@pytest.mark.parametrize("text,outline,thick,real", [
    # 90 x 180 cm cotton beach towels 0.55-0.9 kg; folded twice it lies 45 x 90 cm
    ("a beach towel 90 x 180 cm, folded", (0.9, 0.45), 0.3, 0.7),
    # 45 x 30 cm woven placemats 45-80 g
    ("a placemat 45 x 30 cm", (0.45, 0.3), 0.02, 0.06),
    # tufted bath mats 1.2-2 kg/m^2 x 0.54 m^2
    ("a 60 x 90 cm bath mat", (0.9, 0.6), 0.03, 0.8),
    # 50 x 75 cm cotton pillowcases 0.1-0.15 kg (folded once: 37.5 x 50 cm)
    ("a pillowcase, 50 x 75 cm", (0.5, 0.375), 0.06, 0.12),
])
def test_two_sizes_set_a_flat_goods_outline_not_its_thickness(text: str, outline: tuple[float, float], thick: float,
                                                              real: float) -> None:
    ext = _extents(text)
    assert np.allclose(ext[:2], outline, rtol=0.06) and ext[2] < thick, (text, ext)
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


def test_a_folded_sheet_stated_at_its_folded_size_stays_that_size() -> None:
    ext = _extents("a folded tea towel, 25 x 35 cm")
    assert np.allclose(ext[:2], (0.35, 0.25), rtol=0.06), ext


@pytest.mark.parametrize("text,real", [("a 5 litre bag of potting compost", 2.0),  # moist compost ~0.4-0.5 kg/l
                                       ("a 20 l bag of multipurpose compost", 8.5),
                                       # bagged "potting soil" is a peat or bark mix, not earth: ~0.45 kg/l
                                       ("a 10 litre bag of potting soil", 4.5)])
def test_a_litre_bag_of_compost_weighs_its_volume_of_compost(text: str, real: float) -> None:
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


# ------------------------------------------------------------------------------------- 2. a bag or a pack of goods
@pytest.mark.parametrize("text,pieces,real", [
    ("a bag of pink and white marshmallows", 6, 0.2),  # retail 150-300 g bags
    ("a 100 g bag of cotton balls", 6, 0.1),  # stated
    ("a pack of kitchen sponges", 3, 0.075),  # four 10 x 7 x 3 cm sponges of 12-25 g in a film pack
])
def test_a_bag_of_goods_is_a_bag_showing_them(text: str, pieces: int, real: float) -> None:
    d = catalogue.design_from_text(text)
    assert d.entry == "generic_pouch", (text, d.entry)
    assert sum(part_group(p.name) == "fill" for p in d.program.parts) >= pieces, text
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


def test_a_bag_of_two_coloured_goods_shows_both_colours() -> None:
    d = catalogue.design_from_text("a bag of pink and white marshmallows")
    colours = {tuple(np.round(p.color_rgb, 2)) for p in d.program.parts if part_group(p.name) == "fill"}
    assert len(colours) == 2


def test_a_pair_of_mitts_is_two_mitts() -> None:
    d = catalogue.design_from_text("a pair of oven mitts")
    assert d.entry == "oven_mitt" and any(p.name.startswith("other ") for p in d.program.parts)
    assert 0.5 <= planned_mass("a pair of oven mitts") / 0.24 <= 2.0  # two quilted mitts of 80-150 g


# ------------------------------------------------------------------------------- 3. flat and thin goods in their form
@pytest.mark.parametrize("text,entry,groups,real", [
    ("a cotton feeding bib", "baby_bib", {"neck", "neck opening", "snap"}, 0.03),  # retail bibs 20-40 g
    ("a disposable nappy", "diaper", {"leg opening", "tab", "core", "waistband"}, 0.035),  # dry nappies 30-40 g
    ("a padded bubble envelope", "padded_envelope", {"flap", "seal", "peel strip"}, 0.03),  # A4 mailers 25-35 g
    ("a plastic carrier bag, crumpled up", "carrier_bag", {"crease", "mouth", "handle"}, 0.006),  # HDPE bags 4-10 g
    ("a kitten bed", "cat_bed", {"floor"}, 0.7),  # 50 cm donut cat beds 0.5-0.9 kg
    ("a round dog bed", "pet_bed", {"floor"}, 1.2),  # 60 cm donut dog beds 0.9-1.6 kg
])
def test_flat_and_thin_goods_have_their_form(text: str, entry: str, groups: set[str], real: float) -> None:
    got, have = _groups(text)
    assert got == entry, (text, got)
    assert groups <= have, (text, groups - have)
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


def test_a_mailer_is_flat_not_a_block() -> None:
    ext = _extents("a jiffy bag")
    assert ext[2] < 0.05 * ext[0], ext


def test_a_cat_bed_is_read_as_a_bed_not_a_cat() -> None:
    assert catalogue.design_from_text("a cat bed").entry == "cat_bed"


# ------------------------------------------------------------------------------------------------- 4. wrong readings
@pytest.mark.parametrize("text,real", [
    ("a roll of bubble wrap", 0.075),  # 45-55 g/m^2 small-cell wrap, 50 cm x 3 m
    ("a roll of bubble wrap 30 cm wide and 5 m long", 0.075),  # the same wrap, 1.5 m^2
])
def test_a_roll_of_bubble_wrap_is_a_light_roll(text: str, real: float) -> None:
    entry, groups = _groups(text)
    assert entry == "bubble_wrap_roll" and {"ring", "bubble"} <= groups, (text, entry)
    assert 0.5 <= planned_mass(text) / real <= 2.0, text


def test_a_rolled_sheets_width_is_the_rolls_length() -> None:
    ext = _extents("a roll of bubble wrap 30 cm wide and 5 m long")
    assert abs(ext[0] - 0.3) < 0.01 and ext[1] < 0.3, ext


@pytest.mark.parametrize("text", ["a lavender heat pack", "a microwave heat bag", "a rice heat pack shaped like a tube"])
def test_a_heat_pack_is_a_filled_fabric_pack_not_a_hot_water_bottle(text: str) -> None:
    assert catalogue.design_from_text(text).entry == "heat_pad", text
    assert 0.5 <= planned_mass(text) / 0.8 <= 2.0, text  # 0.6-1.0 kg of wheat, rice or lavender and grain


def test_a_heat_pack_shaped_like_a_tube_is_a_long_stitched_tube() -> None:
    entry, groups = _groups("a grain heat pack shaped like a long tube")
    assert entry == "heat_pad" and "stitch" in groups
    ext = _extents("a grain heat pack shaped like a long tube")
    assert ext[0] > 4 * ext[1], ext
