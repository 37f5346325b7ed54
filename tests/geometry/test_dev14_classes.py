"""Classes development set 14 (120 prompts written in session 28 by two reviewers who never opened the repository)
found missing or misread (#35), fixed by class and checked here on other phrasings than the set's.

Real masses: typical retail figures (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.shape import Part, ShapeProgram
from tasks.geometry import catalogue, concepts, meshing
from tasks.geometry.concepts import concept_domain
from tests.geometry.test_mass_classes import planned_mass


def _parts(text: str) -> list[str]:
    return [p.name for p in catalogue.design_from_text(text).program.parts]


def test_a_pack_of_goods_shows_a_printed_label_and_a_clear_bag_its_goods() -> None:
    """A sack of rice or a bag of dog food was a plain pillow (judged 'a pillow' 8 times in set 14): its label tells
    it from one; a bag whose goods are drawn through its film keeps them instead."""
    design = catalogue.design_from_text("a 2 kg bag of brown rice")
    assert design.entry == "generic_pouch" and "label" in _parts("a 2 kg bag of brown rice")
    body = next(p.color_rgb for p in design.program.parts if p.name == "body")
    label = next(p.color_rgb for p in design.program.parts if p.name == "label")
    assert max(abs(a - b) for a, b in zip(body, label)) > 0.3  # it stands out from the film
    assert "label" not in _parts("a bag of gummy bears") and any(n.startswith("fill") for n in
                                                                   _parts("a bag of gummy bears"))  # (the bag of
    # marshmallows is a hand-drawn entry since session 43)


@pytest.mark.parametrize("text, real_kg", [
    ("a 180 cm closed cell foam camping mat, rolled up", 0.35),  # retail 180 x 55 x 1 cm mats 0.25-0.45 kg
    ("a 72 inch yoga mat, rolled", 1.2),  # 183 cm PVC / TPE mats 0.9-1.5 kg
])
def test_a_rolled_sheets_length_nearer_its_flat_length_is_the_sheets(text: str, real_kg: float) -> None:
    """'rolled closed-cell foam sleeping mat, 183 cm' was a roll 1.83 m long: 5 kg (the clamp)."""
    assert 0.5 <= planned_mass(text) / real_kg <= 2.0


@pytest.mark.parametrize("text, not_built", [
    ("a bag of bird seed for parrots", "parrot"),
    ("a fleece blanket for the dog", "dog"),
    ("a 1 m foam tube for 15 mm pipe", None),
    ("a neoprene sleeve for a 13 inch laptop", "laptop"),
])
def test_what_an_object_is_for_is_not_built(text: str, not_built: str | None) -> None:
    """'1 kg bag of timothy hay for rabbits' built a plush bunny; 'for 22mm pipe' sized the tube by the pipe; but
    'for a 13 inch laptop' still sizes the sleeve."""
    design = catalogue.design_from_text(text)
    if not_built == "laptop":
        assert design.size.explicit
    elif not_built is not None:
        assert not_built not in design.entry and concept_domain(design.entry) != "animal"
    else:
        assert design.size.longest_m == pytest.approx(1.0)


@pytest.mark.parametrize("text", ["a pound of ground lamb on a foam tray", "raw minced pork, 500 g"])
def test_meat_said_raw_or_ground_is_food_not_the_animal(text: str) -> None:
    """'1 lb ground beef on a foam tray' was a toy cow (WordNet's beef: cattle); words that say it is eaten choose the
    food sense."""
    design = catalogue.design_from_text(text)
    assert concept_domain(design.entry) != "animal", design.entry


@pytest.mark.parametrize("text, key, real_kg", [
    ("an all weather car mat", "car_floor_mat", 1.5),  # front rubber mats 1.2-2.0 kg
    ("a daycare rest mat", "nap_mat", 1.0),  # toddler nap mats 0.8-1.4 kg
    ("an EVA floor tile", "foam_floor_tile", 0.09),  # 30 cm EVA tiles 85-100 g
    ("an NG tube", "feeding_tube", 0.012),  # 120 cm 10-16 Fr tubes 8-15 g
    ("a rubber O-ring", "o_ring", 0.0015),  # 50 x 2.6 mm nitrile ~1.2 g
    ("a rocker cover gasket", "gasket", 0.1),  # moulded valve cover gaskets 80-150 g
    ("a period cup", "menstrual_cup", 0.008),  # 6-10 g
    ("a ketchup squeeze bottle", "squeeze_bottle", 0.44),  # 400 ml full, ~40 g empty
    ("a bunch of swiss chard", "kale", 0.34),  # a bunch of greens 300-400 g
    ("a space blanket", "emergency_blanket", 0.05),  # aluminised PET 45-60 g
    ("a reusable hand warmer", "hand_warmer", 0.09),  # click warmers 70-110 g
    ("foam pipe lagging", "pipe_insulation", 0.04),  # 1 m for 22 mm pipe 30-50 g
    ("a grilled octopus tentacle", "octopus_tentacle", 0.15),  # 120-250 g
    ("a cage hammock for rats", "pet_hammock", 0.15),  # fleece cage hammocks 100-200 g
    ("a parachute nylon hammock", "camping_hammock", 0.45),  # 0.4-0.6 kg
])
def test_set_14s_objects_are_named_and_weighed(text: str, key: str, real_kg: float) -> None:
    """Set 14's unknown nouns (generic blocks, balls and blobs, a toy cow for beef) are lexicon objects now."""
    assert catalogue.design_from_text(text).entry == key
    assert 0.5 <= planned_mass(text) / real_kg <= 2.0


def test_goods_packed_in_their_sack_are_the_full_sack_at_the_goods_mass() -> None:
    """'synthetic sleeping bag stuffed in a compression sack' was a flat quilted pad of 13.6 kg: the sack is seen,
    full, weighing what it holds (a fleece throw ~0.5-0.8 kg)."""
    design = catalogue.design_from_text("a fleece throw blanket packed into a stuff sack")
    assert design.entry == "stuff_sack" and any("packed in" in w for w in design.warnings)
    throw = catalogue.design_from_text("a fleece throw blanket").concept
    assert throw is not None and design.concept is not None
    assert design.concept.stated_mass_kg == pytest.approx(throw.typical_mass_kg, rel=0.01)


def test_a_count_of_pouch_goods_is_that_many_but_a_pack_stays_one_pack() -> None:
    """'three juggling beanbags' was one bean bag; 'a pack of 6 hand warmers' is one pack of them."""
    assert _parts("four bean bags").count("body") + sum(n.startswith("body ") for n in _parts("four bean bags")) == 4
    assert catalogue.design_from_text("a pack of 6 hand warmers").entry == "generic_pouch"


def test_a_body_thinner_than_the_envelope_grid_has_its_bounds_as_envelope(monkeypatch: pytest.MonkeyPatch) -> None:
    """A slump word on a film thinner than _body_envelope's grid cell found no inside sample and raised ValueError
    (a crash of L0 on a sealed set 14 prompt): the envelope falls back to the primitives' bounds, and the film is
    not slumped (it is not ball-like)."""
    film = ShapeProgram(name="film", category="textile", parts=[Part(
        name="body", primitive={"kind": "ellipsoid", "radii_m": (0.5, 0.3, 0.0004)})])
    monkeypatch.setattr(meshing, "sample_program", lambda program, resolution: (np.ones((8, 8, 8)), np.zeros(3),
                                                                                0.1))  # no sample inside the film
    centre, half = concepts._body_envelope(film)
    assert half == pytest.approx((0.5, 0.3, 0.0004), rel=0.05) and np.abs(centre).max() < 1e-6
    assert concepts.slumped(film, 0.7) is None


@pytest.mark.parametrize("text, key, real_kg", [
    ("a skin-on cod fillet", "white_fish_fillet", None),  # the cut's words are not the object
    ("a whole raw octopus", "whole_octopus", 1.0),  # whole raw octopus 0.8-1.5 kg
    ("a raw whole chicken", "whole_chicken", 1.6),  # size 14-18 chickens 1.4-1.8 kg
])
def test_sealed_set_14s_food_misreads(text: str, key: str, real_kg: float | None) -> None:
    """After sealed set 14's run (no longer blind): 'a 150 g skin-on salmon fillet' was a generic block ('skin' read
    as the object); 'a whole raw octopus, about 1 kg' became ground meat (the meat rule took the whole animal); 'a
    whole raw chicken, ready to roast' was 0.45 kg of ground meat."""
    design = catalogue.design_from_text(text)
    if key == "white_fish_fillet":
        assert design.concept is not None and not design.concept.by_analogy and "fillet" in design.entry
        return
    assert design.entry == key
    assert real_kg is not None and 0.5 <= planned_mass(text) / real_kg <= 2.0


@pytest.mark.parametrize("text, key", [
    ("a blue exercise band 1.8 m long", "therapy_band"),  # longer than any loop band laid flat
    ("a 6 ft latex band", "therapy_band"),
    ("a 41 inch pull up band loop", "resistance_band"),  # a loop said so
    ("a resistance band", "resistance_band"),
])
def test_a_band_longer_than_a_loop_is_a_flat_band(text: str, key: str) -> None:
    """'a green latex resistance band, 1.5 m long' (sealed set 14) and 'a 2 m flat latex band' (set 13) were built as
    pull-up loops at 6-7x their mass: a stated length over 1.3 m that no loop band has laid flat is a flat band."""
    assert catalogue.design_from_text(text).entry == key


@pytest.mark.parametrize("text, key, plan", [
    ("a 250 g block of modelling clay", "modelling_clay", "block"),  # 'a block of' shapes it; was a puck
    ("a pastry bag full of whipped cream", "piping_bag", None),  # a cone of frosting, not a labelled pillow
    ("an iceberg lettuce", "iceberg_lettuce", None),  # leaves, not a plain green ball
])
def test_sealed_set_14s_shapes(text: str, key: str, plan: str | None) -> None:
    """After sealed set 14's run (no longer blind): a block of clay, a piping bag, a head of iceberg lettuce."""
    design = catalogue.design_from_text(text)
    assert design.entry == key
    if plan is not None:
        assert design.concept is not None and design.concept.shape_from == plan
    if key == "iceberg_lettuce":
        assert sum(n.startswith("leaf") for n in _parts(text)) >= 6
