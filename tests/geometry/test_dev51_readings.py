"""Session 51 dev list readings: wordings of objects the lexicon already builds that fell to a generic guess (a
fried egg 'sunny side up' was a plush sun for 'side', a jack-o'-lantern a generic object, a whole grilled sea bream a
plush fish, a 'pat of butter', a 'crumpled paper water cup', a bolster pet bed, a plastic dust sheet)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry"), [
    ("two eggs sunny side up", "fried_egg"),
    ("a fried egg sunny side up", "fried_egg"),
    ("sunny-side-up eggs", "fried_egg"),
    ("eggs over easy", "fried_egg"),
    ("jack-o'-lantern that's starting to go soft", "pumpkin"),
    ("a Jack-O-Lantern", "pumpkin"),
    ("whole grilled sea bream", "whole_fish"),
    ("grilled sea bass", "whole_fish"),
    ("little pat of butter", "butter"),
    ("crumpled paper water cup", "crushed_paper_cup"),
    ("white disposable coverall suit", "disposable_coverall"),
    ("collapsible fabric tunnel", "play_tunnel"),
    ("little plush bolster bed", "pet_bed"),
    ("thin plastic sheet covering the sofa", "plastic_sheeting"),
    ("pouch of apple puree", "yogurt_pouch"),
    ("grilled portobello mushroom cap", "mushroom"),
    ("hamburger bun", "bread_roll"),
    ("one scoop of strawberry in a waffle cone", "ice_cream_cone"),
    ("a scoop of vanilla in a waffle cone", "ice_cream_cone"),
    ("ice cream cone", "ice_cream_cone"),
    ("two scoops of mint chocolate chip", "ice_cream_scoop"),
    ("scoop of chocolate", "ice_cream_scoop"),
])
def test_dev51_wording_reads_as_the_entry_it_names(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_sunny_side_up_is_not_read_outside_eggs() -> None:
    """The idiom rewrites only an egg: 'a sunny yellow plush sun' stays the plush sun."""
    assert catalogue.design_from_text("a sunny yellow plush sun").entry == "plush_sun"


def test_an_ice_cream_flavour_colours_the_scoop_not_the_wafer() -> None:
    """'scoop of strawberry in a waffle cone' is a pink scoop on a tan wafer, at a cone's mass (~0.1 kg)."""
    program = catalogue.design_from_text("one scoop of strawberry in a waffle cone").program
    scoop = next(p for p in program.parts if p.name == "scoop")
    wafer = next(p for p in program.parts if p.name == "wafer")
    assert scoop.color_rgb[0] > scoop.color_rgb[1] + 0.1  # pink: red well above green
    assert abs(wafer.color_rgb[0] - 0.8) < 0.05 and abs(wafer.color_rgb[2] - 0.22) < 0.05  # the wafer's own tan
    assert 0.05 <= planned_mass("ice cream cone") <= 0.2


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("ice cream cone", "ice_cream_cone", 0.1),
    ("foam pit cube", "foam_pit_cube", 0.06),
    ("cork sheet", "cork_sheet", 0.14),
    ("toilet wax ring", "toilet_wax_ring", 0.22),
])
def test_dev51_entry_builds_at_its_real_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


@pytest.mark.parametrize(("text", "entry", "state"), [
    ("roll up the foam sleeping mat from under the bunk", "sleeping_pad", "rolled"),
    ("roll up the yoga mat", "yoga_mat", "rolled"),
    ("fold up the blanket", "throw_blanket", "folded"),
])
def test_a_command_to_roll_or_fold_is_the_object_in_that_state(text: str, entry: str, state: str) -> None:
    """'roll up the foam sleeping mat' was a bread roll: the verb is the object's state, not a noun."""
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    assert design.concept is not None and state in design.concept.states


@pytest.mark.parametrize(("text", "entry"), [
    ("piping bag full of whipped cream", "piping_bag"),
    ("bag of mashed potatoes", "mashed_potatoes"),
])
def test_a_soft_food_in_a_bag_is_not_a_pouch_of_pieces(text: str, entry: str) -> None:
    """Once whipped cream was an entry, 'a piping bag full of whipped cream' became a pouch of 2 cream dollops: a
    spread takes its container's shape and is never pieces in a bag."""
    design = catalogue.design_from_text(text)
    assert design.entry == entry and design.concept is not None and not design.concept.by_analogy


def test_a_topping_is_not_the_material_of_a_drink() -> None:
    """'hot cocoa with marshmallows' weighed 0.22 kg as marshmallow foam; it is a 16 oz drink (~0.48 kg)."""
    assert 0.5 <= planned_mass("paper cup of hot cocoa with marshmallows") / 0.48 <= 2.0
