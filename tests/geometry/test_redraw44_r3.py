"""Session 44's redraw (helper r3): sealed set 30's objects the blind judges could not name as built, each now its own
drawing (tasks/geometry/shapes/redraw44_r3.yaml; the feed pan a shallow mould) read from the prompt as typed, at its
real mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("stack of old newspapers tied with string", "newspaper_bundle", 2.5),
    ("rolled chashu pork belly log tied w string", "chashu_roll", 1.0),
    ("navy noren curtain 85 x 150 cm", "noren_curtain", 0.3),
    ("200g bag of bean sprouts", "bean_sprouts_bag", 0.2),
    ("small hay net stuffed full of hay", "hay_net_small", 2.0),
    ("burlap sack enrichment toy stuffed w straw", "burlap_enrichment_sack", 1.5),
    ("2 kg chunk of raw meat in a plastic bag", "raw_meat_bag", 2.0),
    ("flexible black rubber feed pan for the zebras", "feed_pan", 0.9),
    ("saltwater taffy bag half full", "taffy_bag", 0.25),
    ("zip bag of soil sample, about a litre", "soil_sample_bag", 1.2),
]
@pytest.mark.parametrize(("text", "entry", "_kg"), CASES)
def test_the_prompt_reads_as_its_entry(text: str, entry: str, _kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_built_mass_is_the_real_mass(text: str, entry: str, kg: float) -> None:
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("entry", sorted({e for _t, e, _kg in CASES} - {"feed_pan"}))
def test_each_shape_is_hand_drawn_within_the_part_budget(entry: str) -> None:
    assert 3 <= len(catalogue_program(entry).parts) <= 64


@pytest.mark.parametrize(("text", "entry"), [("a hay net", "hay_net"), ("a small hay net", "hay_net_small"),
                                             ("a burlap sack", "cloth_sack"), ("a bag of bean sprouts", "bean_sprouts_bag"),
                                             ("a noren", "noren_curtain"), ("chashu", "chashu_roll"),
                                             ("raw pork belly", "pork_belly_strip"), ("a rubber feed pan", "feed_pan"),
                                             ("a flexible tub", "flexible_tub"), ("a piece of saltwater taffy", "taffy"),
                                             ("a bag of saltwater taffy", "taffy_bag"), ("a newspaper", "newspaper"),
                                             ("a bundle of newspapers", "newspaper_bundle"), ("a zip bag", "zip_bag"),
                                             ("a soil sample bag", "soil_sample_bag")])
def test_the_new_nouns_and_their_neighbours(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
