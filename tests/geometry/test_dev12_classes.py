"""Classes a development set of 120 prompts (written in session 26 by a reviewer who never opened the repository,
judged blind: 79 / 120 named, 90 / 120 within 2x of the mass) found missing or misread (#35), fixed by class and
checked here on other phrasings than the set's: a bag of goods the lexicon does not know is a pouch (was a generic
block), goods bulge a bag's film (read as a tray), a compound head the lexicon knows as one object ('volleyball knee
pads' were a volleyball), garment size labels ('size M' read as metres), 'w/', a pair said after the goods, a folded
or rolled sheet's stated size is its flat size, a piece's size in a pack of a number of them, and new entries.

Real masses: typical retail or rule figures (the source in each line)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize("text", ["a bag of arugula", "a 1 lb bag of kapok fiber", "a packet of shredded coconut"])
def test_a_bag_of_unknown_goods_is_a_pouch_said_as_a_guess(text: str) -> None:
    d = catalogue.design_from_text(text)
    assert d.entry == "generic_pouch" and d.concept.fallback_level == "category"
    assert "sealed pouch" in (d.concept.fallback_note or "")


def test_a_bare_bag_is_a_fabric_bag_not_a_block() -> None:
    assert catalogue.design_from_text("a bag").entry == "generic_bag"


def test_goods_in_a_bag_sit_in_its_depth_and_tint_its_body() -> None:
    d = catalogue.design_from_text("a bag of pink marshmallows")
    body = next(p for p in d.program.parts if p.name == "body")
    fills = [p for p in d.program.parts if part_group(p.name) == "fill"]
    assert fills
    top = body.transform.translation_m[2] + body.primitive.radii_m[2]
    # each piece's top stays within a fifth of its thickness of the bag's top (bumps, not goods standing on a tray);
    # a piece is drawn with the marshmallow's own parts (tasks.geometry.pack_pieces)
    for f in fills:
        lo, hi = program_bounds(d.program.model_copy(update={"parts": [f.model_copy(update={"blend_m": 0.0})]}))
        assert hi[2] <= top + 0.2 * (hi[2] - lo[2])
    assert body.color_rgb[0] > body.color_rgb[2] + 0.05  # pink shows through the clear film


@pytest.mark.parametrize("text,entry", [("basketball knee pads", "work_knee_pads"), ("a duck bath toy", "rubber_duck"),
                                        ("a mouse cat toy", "cat_toy_mouse")])
def test_a_compound_the_lexicon_knows_is_the_object_unless_an_animal_shapes_it(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize("text,entry", [("work gloves, size L", "work_glove"),
                                        ("a fleece hoodie, adult XL", "hoodie"),
                                        ("women's size 7 house slipper", "slipper")])
def test_a_garment_size_label_is_no_length(text: str, entry: str) -> None:
    d = catalogue.design_from_text(text)
    assert d.entry == entry and d.size.longest_m is None and d.size.extents_m == (None, None, None)


def test_a_size_5_ball_keeps_its_size_number() -> None:
    assert catalogue.normalise_sizes("a size 5 soccer ball") == "a size 5 soccer ball"


def test_w_slash_reads_as_with() -> None:
    assert catalogue.design_from_text("a plush jellyfish w/ long ribbon tentacles").entry == "plush_jellyfish"


@pytest.mark.parametrize("text", ["wool mittens, pair", "swim armbands (pair)"])
def test_a_pair_said_after_the_goods_is_a_pair(text: str) -> None:
    assert "a pair" in catalogue.design_from_text(text).concept.states


def test_a_folded_blankets_stated_size_is_its_flat_size() -> None:
    d = catalogue.design_from_text("a fleece throw folded up, 127 x 152 cm")
    folded = catalogue.final_scale(d.size, d.program, d.concept.typical_size_m or 1.0)[0]
    assert folded < 0.9  # folded twice or more: not a 1.5 m block
    # retail 130 x 150 cm polyester fleece throws: 0.55-0.8 kg
    assert 0.5 <= planned_mass("a fleece throw folded up, 127 x 152 cm") / 0.7 <= 2.0


def test_a_rolled_towels_stated_size_rolls_along_its_length() -> None:
    d = catalogue.design_from_text("a beach towel rolled up, 75 x 150 cm")
    assert d.size.extents_m[0] == pytest.approx(0.75, rel=0.02)  # the roll is the towel's width long


def test_a_piece_size_in_a_pack_of_a_number_of_them_sizes_the_pieces() -> None:
    # craft listings: 100 acrylic pom poms of 1-2.5 cm weigh 30-60 g
    assert 0.5 <= planned_mass("a bag of 100 craft pom poms, 2 cm") / 0.045 <= 2.0


@pytest.mark.parametrize("text,entry,kg", [
    ("a raw squid", "whole_squid", 0.15),  # fishmongers: whole squid 20-25 cm, 100-200 g
    ("a silicone stretch lid", "stretch_lid", 0.015),  # retail: a 10 cm lid 10-20 g
    ("a silk sleep mask", "sleep_mask", 0.02),  # retail: 15-30 g
    ("an inflatable swim ring", "swim_ring", 0.2),  # retail: 60-90 cm PVC rings 0.15-0.35 kg
    ("a soft foam neck collar", "cervical_collar", 0.06),  # medical supply: 40-90 g
    ("a microfibre hair turban", "hair_towel", 0.1),  # retail: 80-130 g
    ("a sheer voile curtain", "sheer_curtain", 0.2),  # retail: 140 x 230 cm voile panels 0.15-0.35 kg
    ("a round braided rug", "braided_rug", 0.6),  # retail: 60 cm round braided rugs 0.4-0.9 kg
    ("a baby food squeeze pouch", "yogurt_pouch", 0.11),  # retail: 90-113 g pouches
    ("a spray mop pad", "mop_pad", 0.06),  # retail: 40-80 g
    ("a silicone pocket bib", "silicone_bib", 0.075),  # retail: 60-90 g
    ("a cotton bbq apron", "apron", 0.3),  # retail: canvas bib aprons 0.2-0.4 kg
    ("a tube of hand cream", "toothpaste_tube", 0.13),  # retail: 75-100 ml tubes 0.1-0.17 kg full
])
def test_new_everyday_entries_are_named_and_weighed(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_nursing_pillow_is_an_open_c() -> None:
    d = catalogue.design_from_text("a breastfeeding pillow")
    assert d.entry == "nursing_pillow" and any(p.name == "opening" and p.operation == "subtract"
                                               for p in d.program.parts)


def test_an_animal_hand_puppet_takes_the_animals_shape() -> None:
    d = catalogue.design_from_text("a bear hand puppet")
    assert d.entry == "hand_puppet" and d.concept.shape_from is not None


def test_a_foam_shape_cutout_is_the_shape_named() -> None:
    assert catalogue.design_from_text("a glitter foam heart cutout").program.parts
    assert catalogue.design_from_text("a foam star cutout").entry != "generic_block"
