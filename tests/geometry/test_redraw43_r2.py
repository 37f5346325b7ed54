"""Session 43's redraw (helper r2): objects the blind judges could not name as built, each now its own hand-drawn
shape (tasks/geometry/shapes/redraw43_r2.yaml) read from the prompt as typed, at its real mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tasks.render.finish import LOOKS, finish_for
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("folded black choir robe", "choir_robe", 0.7),
    ("orange hi-vis safety vest", "hivis_vest", 0.15),
    ("embroidered green priest stole", "priest_stole", 0.25),
    ("natural chamois leather cloth, dry and stiff", "chamois", 0.1),
    ("brown leather shoulder handbag, empty", "hobo_handbag", 0.7),
    ("blue chenille wash mitt, soaking wet", "chenille_wash_mitt", 0.4),
]
BUILT = {"hivis_vest", "chenille_wash_mitt"}  # built in the default run (the rest under -m slow)


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_prompt_reads_as_its_entry(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "kg"), [
    c if c[1] in BUILT else pytest.param(*c, marks=pytest.mark.slow) for c in CASES])
def test_the_prompt_builds_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("entry", sorted({e for _t, e, _kg in CASES}))
def test_each_shape_is_hand_drawn_within_the_part_budget(entry: str) -> None:
    assert 3 <= len(catalogue_program(entry).parts) <= 64


def test_the_soaked_mitt_holds_its_water_and_the_handbag_looks_like_leather() -> None:
    mitt = catalogue.design_from_text("blue chenille wash mitt, soaking wet").concept
    assert mitt is not None and "wet" in mitt.states
    bag = catalogue.design_from_text("brown leather shoulder handbag, empty").concept
    assert bag is not None and finish_for(bag.default_material, bag.category, bag.finish) is LOOKS["leather"]


@pytest.mark.parametrize(("text", "entry"), [
    ("a stole", "scarf"), ("silk stole", "silk_scarf"), ("liturgical stole", "priest_stole"),
    ("wash mitt", "bath_mitt"), ("bath mitt", "bath_mitt"), ("car wash mitt", "chenille_wash_mitt"),
    ("safety vest", "hivis_vest"), ("a puffer vest", "gilet"), ("graduation gown", "choir_robe"),
    ("a bathrobe", "bathrobe"), ("hobo bag", "hobo_handbag"), ("chamois leather", "chamois")])
def test_neighbouring_words(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
