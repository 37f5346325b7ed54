"""Post-hoc from sealed set 40 (after its one run at 6fd6e05): a rigid word in what the object is for is not the
object, and a material said after its noun is not the head noun."""

from __future__ import annotations

from tasks.agents.intent import rigid_object
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


def test_what_an_object_is_for_is_not_the_object() -> None:
    """'a plastic tablecloth ... for a long table' was refused as a rigid table; a table itself still is."""
    text = "I need a plastic tablecloth 54 x 108 for a long table, crumpled up after the party"
    assert rigid_object(text) is None
    assert catalogue.design_from_text(text).entry == "plastic_tablecloth"
    assert rigid_object("a table for a dollhouse") == "table" and rigid_object("a teacup for my daughter") == "teacup"


def test_a_material_after_its_noun_is_not_the_head() -> None:
    """'adult BP cuff nylon w/ bladder and bulb' was a generic garment read from 'nylon'; a material that is the goods
    ('an aerial silk', 'a sheet of crepe rubber', 'sheep fleece, rolled up') stays the head."""
    assert catalogue.design_from_text("adult BP cuff nylon w/ bladder and bulb (no gauge)").entry == \
        "blood_pressure_cuff"
    assert catalogue.design_from_text("a tote bag canvas").entry == "tote_bag"
    assert catalogue.design_from_text("an aerial silk").entry == "aerial_silk"
    assert catalogue.design_from_text("freshly sheared sheep fleece, rolled up").entry == "sheep_fleece"


def test_up_to_half_an_inch_after_a_foam_good_or_on_a_sheet_is_its_stock() -> None:
    """'EVA foam chestplate 10mm' was a 1 cm generic block of 8 mg, and '10mm eva foam sheet' a 1 cm sheet: 10 mm is
    the EVA's thickness (the chestplate is a foam armour plate, ~0.2 kg); before its stock a centimetre is still the
    object's ('a 12mm foam ball')."""
    chest = catalogue.design_from_text("EVA foam chestplate 10mm, painted, for a Mandalorian build")
    assert chest.entry == "foam_armor_plate" and chest.size.longest_m is None
    assert 0.1 <= planned_mass("EVA foam chestplate 10mm, painted, for a Mandalorian build") <= 0.4
    assert catalogue.design_from_text("10mm eva foam sheet").size.longest_m is None
    assert catalogue.design_from_text("a 12mm foam ball").size.longest_m == 0.012


def test_a_long_wig_said_by_its_length_weighs_a_wig() -> None:
    """'36 inch silver lace front wig' scaled the curly costume wig to 0.91 m: 9.75 kg (32x); a long straight wig is
    drawn lying with its hair laid out, 0.92 m from cap to tips, ~0.3 kg."""
    text = "36 inch silver lace front wig for my Geralt cosplay lol"
    assert catalogue.design_from_text(text).entry == "long_wig"
    assert 0.15 <= planned_mass(text) <= 0.6


def test_a_tempur_neck_pillow_is_the_contoured_bed_pillow_not_a_travel_one() -> None:
    """Set 40's 'tempur neck pillow, medium' built the 0.13 kg U-shaped travel pillow (the TEMPUR-Neck is a 50 cm
    contoured memory foam bed pillow, ~1.15 kg); a memory foam travel neck pillow stays the travel pillow."""
    assert catalogue.design_from_text("tempur neck pillow, medium").entry == "memory_foam_pillow"
    assert catalogue.design_from_text("memory foam travel neck pillow").entry == "neck_pillow"


def test_a_canvas_training_dummy_is_a_dog_bumper_not_a_babys_dummy() -> None:
    """Set 40's 'canvas training dummy 3" x 12"' built a 7 g pacifier; a baby's dummy still is one."""
    assert catalogue.design_from_text('canvas training dummy 3" x 12", kinda chewed up').entry == "retrieving_bumper"
    assert 0.125 <= planned_mass('canvas training dummy 3" x 12", kinda chewed up') <= 0.5
    assert catalogue.design_from_text("a baby dummy").entry == "pacifier"
