"""A WordNet compound whose modifier is a noun the lexicon's entry does not list ('a sweat suit', 'a bowler hat') is
read by analogy and said so, not as the entry its last word names; a qualifier ('a wool hat', 'a black kite') and a
compound with no physical sense ('a small cap') leave the entry as it was; a hard ball is refused as rigid."""

from __future__ import annotations

import pytest

from contracts.errors import InputError
from tasks.agents.intent import check_rigid_object
from tasks.geometry import catalogue
from tasks.geometry.sources import _is_named


@pytest.mark.parametrize(("text", "entry", "said"), [
    ("a bowler hat", "felt_hat", "a kind of 'hat'"),  # a kind of the head noun: the entry's shape, by analogy
    ("a golf glove", "knit_glove", "a kind of 'glove'"),
    ("an electric blanket", "throw_blanket", "a kind of 'blanket'"),
    ("a sweat suit", "business_suit", "sweat pants and a sweatshirt"),  # another garment: WordNet's gloss said
    ("a milk float", "pool_float", "a van"),  # another thing altogether: a guess, and the line says so
])
def test_an_unlisted_compound_is_built_by_analogy_with_its_reason(text: str, entry: str, said: str) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    assert design.concept is not None and design.concept.fallback_level == "hypernym"
    assert not _is_named(design)  # the 'built by analogy' line, and --strict-concept's refusal
    note = design.concept.fallback_note or ""
    assert f"'{text.split(' ', 1)[1]}' is not in the lexicon" in note and said in note
    assert len(design.concept.analogy) == 2  # the chain recorded in geometry.json and shown on the card


@pytest.mark.parametrize(("text", "entry"), [
    ("a wool hat", "beanie_hat"),  # a material qualifies the hat
    ("a black kite", "diamond_kite"),  # a colour, though WordNet's black kite is a bird
    ("a small cap", "baseball_cap"),  # WordNet's small cap is a stock, nothing physical
    ("a beach towel", "beach_towel"),  # the lexicon lists the compound
    ("mandarin orange with leaves", "mandarin"),  # WordNet's synonym of a lexicon noun: that object, named
])
def test_qualifiers_listed_compounds_and_synonyms_keep_a_named_reading(text: str, entry: str) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry and _is_named(design)


@pytest.mark.parametrize("text", ["a bowling ball", "a billiard ball", "a cannonball", "a croquet ball"])
def test_a_hard_ball_is_refused_as_rigid(text: str) -> None:
    with pytest.raises(InputError, match="rigid object"):
        check_rigid_object(text)


@pytest.mark.parametrize("text", ["a plush bowling ball", "a foam billiard ball", "a rubber ball", "a pool ball",
                                  "a soft bowling ball toy"])
def test_a_soft_word_outside_the_rigid_noun_still_makes_it_soft(text: str) -> None:
    check_rigid_object(text)  # 'pool ball' is the lexicon's water polo ball
