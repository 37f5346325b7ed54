"""Development set 42 (helper dev42_d1: d42_01..20 of tests/geometry/dev42_prompts.jsonl), the prompts that read as
another object, were refused or weighed off: 'an octopus' was a 0.12 kg plush toy; 'mackerel, whole, not gutted' a
grey plush trout; 'salmon filet, half a side skin on' and 'neoprene dive hood' generic blocks; 'deflated size 5 footbal'
five American footballs ('deflated size' read as 'deflated-sized', 'footbal' as the gridiron ball); '5mm full wetsuit,
folded, size L' and 'dive booties pair 5mm' refused as 5 mm objects (the booties then a fleece slipper); 'soft weight
pouch with lead shot 2kg' a 40 cm drawstring sack. Each now reads as its entry and weighs within 2x of the real
object (masses: the lexicon entries' sources)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass

FIXED = [  # (text, entry, real mass [kg])
    ("an octopus", "whole_octopus", 1.5),  # fishmonger listings: whole raw common octopus 0.8-2 kg
    ("mackerel, whole, not gutted", "whole_mackerel", 0.35),  # whole Atlantic mackerel 30-35 cm, 300-450 g
    ("salmon filet, half a side skin on", "salmon_half_side", 0.8),  # half of a 1.2-2.0 kg skin-on side
    ("deflated size 5 footbal", "soccer_ball", 0.43),  # IFAB Law 2: size 5 ball 410-450 g
    ("5mm full wetsuit, folded, size L", "wetsuit", 1.8),  # full 5 mm suits 1.5-2.2 kg dry
    ("neoprene dive hood", "dive_hood", 0.22),  # bibbed 5-7 mm hoods 150-300 g
    ("dive booties pair 5mm", "dive_boots", 0.7),  # 5 mm zip dive boots 0.5-0.9 kg a pair
    ("soft weight pouch with lead shot 2kg", "lead_shot_weight_pouch", 2.0),  # sold by its nominal mass
]
BUILT_BY_DEFAULT = {"mackerel, whole, not gutted", "dive booties pair 5mm"}


@pytest.mark.parametrize(("text", "entry", "real_kg"), FIXED)
def test_a_development_prompt_reads_as_its_entry(text: str, entry: str, real_kg: float) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    assert design.concept is not None and 0.5 <= (design.concept.typical_mass_kg or 0.0) / real_kg <= 2.0


@pytest.mark.parametrize(("text", "entry", "real_kg"), [
    f if f[0] in BUILT_BY_DEFAULT else pytest.param(*f, marks=pytest.mark.slow) for f in FIXED])
def test_a_development_prompt_weighs_about_its_real_mass_as_built(text: str, entry: str, real_kg: float) -> None:
    assert 0.5 <= planned_mass(text) / real_kg <= 2.0


def test_the_states_and_counts_the_prompts_say_are_read() -> None:
    """'deflated size 5': one ball, deflated (not five 'deflated-sized' balls); 'pair': two boots; '5mm' the neoprene."""
    ball = catalogue.design_from_text("deflated size 5 footbal").concept
    assert ball is not None and "deflated" in ball.states and not any("of them" in s for s in ball.states)
    assert catalogue.design_from_text("a football").entry == "american_football"  # a bare 'football' is unchanged
    boots = catalogue.design_from_text("dive booties pair 5mm").concept
    assert boots is not None and "a pair" in boots.states
    assert catalogue.design_from_text("a squishy plush octopus").entry == "plush_octopus"
