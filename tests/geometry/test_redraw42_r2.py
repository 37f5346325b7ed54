"""Session 42's redraw (helper r2): objects the blind judges could not name as built, each now its own hand-drawn
shape (tasks/geometry/shapes/redraw42_r2.yaml) read from the prompt as typed, at its real mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("small 1% agarose gel, ~10x7cm", "gel_slab", 0.035),
    ("folded blue bench pad", "bench_pad", 0.025),
    ("whirlpak bag w/ water sample, about 100 ml", "whirl_pak", 0.105),
    ("rolled white hand towel", "rolled_hand_towel", 0.12),
    ("insulated paraffin mitts (pair)", "paraffin_mitts", 0.25),
    ("4 way nail buffer block", "nail_buffer", 0.015),
    ("bag of cotton rounds, mostly used up", "cotton_rounds_bag", 0.03),
    ("whole raw chicken, medium size", "whole_chicken", 1.6),
    ("string of pork sausages, six links", "sausage_links", 0.45),
]
BUILT = {"bench_pad", "whirl_pak", "sausage_links"}  # built in the default run (the rest under -m slow)


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


@pytest.mark.parametrize(("text", "entry"), [
    ("roast chicken", "roast_chicken"), ("a rotisserie chicken", "roast_chicken"), ("a raw whole chicken", "whole_chicken"),
    ("a bench cushion", "bench_cushion"), ("lab bench pad", "bench_pad"), ("a plastic bag of cotton pads", "generic_pouch"),
    ("a bag of bait squid", "bait_squid_pack"), ("whirl pak sample bag", "whirl_pak"), ("rolled towel", "rolled_towel")])
def test_neighbouring_words(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
