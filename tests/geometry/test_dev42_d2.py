"""Development set 42 (helper dev42_d2): prompts that built a generic block or another object, each now read as its
own entry (contracts/lexicon/dev42_d2.yaml; hand-drawn shapes in tasks/geometry/shapes/dev42_d2.yaml) at its real
mass (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tests.geometry.test_mass_classes import planned_mass

CASES = [
    ("a flake of hay", "hay_flake", 2.0),
    ("lamb bottle nipple, red rubber", "lamb_teat", 0.01),
    ("wet muslin steamer cloth", "steamer_cloth", 0.04),
    ("israeli bandage", "israeli_bandage", 0.09),
    ("SAM splint rolled up", "sam_splint_rolled", 0.11),
    ("one har gow", "har_gow", 0.022),
    ("lo mai gai in the lotus leaf", "lo_mai_gai", 0.2),
    ("O2 mask w/ tubing", "oxygen_mask", 0.06),
    ("soggy sheet mask", "sheet_mask_unfolded", 0.025),
]
BUILT = {"a flake of hay", "one har gow"}  # built in the default run; the rest under -m slow


@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_prompt_reads_as_its_entry(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "kg"),
                         [c if c[0] in BUILT else pytest.param(*c, marks=pytest.mark.slow) for c in CASES])
def test_the_prompt_builds_at_its_real_mass(text: str, entry: str, kg: float) -> None:
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (text, planned_mass(text))


@pytest.mark.parametrize("entry", ["hay_flake", "lo_mai_gai", "lamb_teat", "har_gow", "oxygen_mask", "sheet_mask_unfolded"])
def test_each_shape_is_hand_drawn_within_the_part_budget(entry: str) -> None:
    assert 3 <= len(catalogue_program(entry).parts) <= 64


@pytest.mark.parametrize(("text", "entry"), [("konjac sponge wet", "konjac_sponge"), ("a korean sheet mask", "sheet_mask"),
                                             ("an oxygen mask", "oxygen_mask"), ("a burp cloth", "burp_cloth"),
                                             ("an elastic bandage", "elastic_bandage")])
def test_the_new_nouns_leave_the_old_readings(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
