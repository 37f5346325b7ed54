"""Sealed set 30's reading misses, fixed after its one run: a note-taker's 'w' for 'with' made the string a
'rolled chashu pork belly log tied w string' is tied with its head noun; a 'log' of a known food is that food, not an
unknown noun; goods named before their bag ('saltwater taffy bag half full') are a bag of them, as full as said; a
measure word before 'of' names no material ('a roll of 10 paper target faces' built a 63 kg bread); a request's own
noun is checked against WordNet's classes before its kinds ('a phone case' is a case, 'a cardboard box' a box), its
object senses before a genus ('a rubber feed pan' is the vessel, not the chimpanzee)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.analogy import best_sense
from tasks.geometry.concepts import bindings, plain
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "said"), [("stuffed w straw", "stuffed with straw"),
                                            ("tied w/ string", "tied with string"),
                                            ("a box w/o a lid", "a box without a lid"),
                                            ("a 60 w bulb", "a 60 w bulb"),  # a wattage stays
                                            ("a shirt 24in w x 36in", "a shirt 24in w x 36in")])  # a width stays
def test_w_is_with_unless_it_is_a_unit(text: str, said: str) -> None:
    assert plain(text) == said


def test_a_log_of_a_known_food_is_that_food_and_w_string_is_no_head() -> None:
    assert bindings("rolled chashu pork belly log tied w string").head == "log"
    assert catalogue.design_from_text("rolled chashu pork belly log tied w string").entry == "chashu_roll"  # drawn since
    assert catalogue.design_from_text("pork belly log").entry == "pork_belly_strip"
    assert catalogue.design_from_text("a goat cheese log").entry == "goat_cheese"


def test_goods_named_before_their_bag_are_a_bag_of_them_as_full_as_said() -> None:
    for text in ("a gummy bear bag", "gummy bear bag half full"):
        d = catalogue.design_from_text(text)
        assert d.entry == "generic_pouch", (text, d.entry)
    full, half = planned_mass("a bag of gummy bears"), planned_mass("gummy bear bag half full")
    assert 0.4 * full <= half <= 0.75 * full  # half full: the pieces' mass halves (the bag's film stays)
    # the taffy bag of this set is drawn since (session 44, contracts/lexicon/redraw44_r3.yaml): a half-full bag
    assert catalogue.design_from_text("saltwater taffy bag half full").entry == "taffy_bag"
    # as 'a bag of gummy bears' weighs: a retail 5 oz (142 g) bag (sealed set 24's writer; 0.73 kg here until session 59,
    # a 1 l food bag of them, 5x the real bag)
    assert 0.5 * 0.142 <= planned_mass("a gummy bear bag") <= 2 * 0.142
    for own in ("a bean bag", "a tea bag", "a marshmallow bag"):  # the lexicon's own bags stay themselves
        assert catalogue.design_from_text(own).entry != "generic_pouch", own


def test_a_measure_word_before_of_names_no_material() -> None:
    assert bindings("roll of 10 paper target faces, 80cm").material is None  # a 63 kg bread before
    assert bindings("a bread roll").material == "bread"
    assert planned_mass("roll of 10 paper target faces, 80cm") < 10.0


@pytest.mark.parametrize(("text", "cls"), [("a felt gift box", "box"), ("a pink silicone case", "case")])
def test_the_requests_own_noun_is_a_class_before_its_kinds(text: str, cls: str) -> None:
    d = catalogue.design_from_text(text)  # a generic block of felt, a silicone blob before
    assert d.entry == "generic_bag" and d.concept is not None and d.concept.fallback_level == "category", text
    assert f"WordNet's '{cls}': the class '{cls}'" in d.concept.analogy


def test_an_object_sense_comes_before_a_genus() -> None:
    sense = best_sense("pan", {"flexible", "black", "rubber", "feed", "zebras"})
    assert sense is not None and "vessel" in sense.definition  # not 'chimpanzees' (the genus Pan)
    d = catalogue.design_from_text("a pan for the goats")
    assert d.concept is not None and d.concept.fallback_level == "hypernym", d.entry  # a pan, built as a vessel
    # the feed pan of this set has its own entry since (session 44): the flexible tub's mould made shallow
    assert catalogue.design_from_text("flexible black rubber feed pan for the zebras").entry == "feed_pan"
    assert 0.45 <= planned_mass("flexible black rubber feed pan for the zebras") <= 1.8  # ~0.9 kg; 55 g before
