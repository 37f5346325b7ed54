"""Post-hoc from sealed set 40 (after its one run at 6fd6e05): a rigid word in what the object is for is not the
object, and a material said after its noun is not the head noun."""

from __future__ import annotations

from tasks.agents.intent import rigid_object
from tasks.geometry import catalogue


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
