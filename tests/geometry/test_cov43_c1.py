"""Development set 43's coverage gaps (helper cov43_c1): requests of tests/geometry/dev43_prompts.jsonl that read as no
named entry (a generic block, blob, ball, strip, garment or quadruped). Each now reads as its own entry
(contracts/lexicon/cov43_c1.yaml, shapes in tasks/geometry/shapes/cov43_c1.yaml) and weighs within 2x of the real
object (masses: the entries' sources)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass

FIXED = [  # (text, entry, real mass [kg])
    ("chunk of cut comb honey", "cut_comb_honey", 0.35),  # cut-comb sections 340-450 g
    ("link of mexican chorizo", "mexican_chorizo", 0.1),  # fresh links 85-115 g
    ("kaju katli with silver leaf", "kaju_katli", 0.012),  # 80-90 pieces a kg
    ("strip of raw pork belly", "pork_belly_strip", 0.15),  # ~20 x 5 x 1.2 cm of raw pork
    ("string of dried aubergines", "dried_aubergine_string", 0.09),  # ~30 shells at ~3 g
    ("lebkuchen heart on ribbon", "lebkuchen_heart", 0.25),  # ~20 x 18 x 1 cm iced gingerbread
    ("plush dragon zodiac toy", "plush_zodiac_dragon", 0.2),  # 30 cm plush toys 150-250 g
    ("felt witch hat", "witch_hat", 0.1),  # costume felt hats 80-120 g
    ("team warm-up jacket", "warmup_jacket", 0.5),  # tricot track jackets 400-550 g
    ("black skate wrist guards", "skate_wrist_guard", 0.2),  # ~100 g each, a pair
    ("paintball neck protector", "neck_protector", 0.06),  # listings 50-70 g
    ("grab an energy gel", "energy_gel", 0.035),  # 32 g gel in a ~3 g sachet
    ("black leather ballet flats", "ballet_flat", 0.35),  # ~175 g a shoe, a pair
    ("muslin backdrop, folded", "muslin_backdrop", 1.1),  # 10.8 m2 at ~100 g/m2
    ("rubber air blower", "air_blower", 0.04),  # rocket blowers 40-50 g
    ("rubber thumb tip", "thumb_tip", 0.005),  # soft vinyl 4-6 g
    ("plush slime mascot", "plush_slime", 0.15),  # 20 cm plush 120-180 g
    ("grape vine leaf", "vine_leaf", 0.005),  # mature leaves 3-6 g
    ("cloth nel drip filter", "nel_drip_filter", 0.03),  # ~20 g flannel, damp
]
BUILT_BY_DEFAULT = {"kaju katli with silver leaf", "grab an energy gel"}


@pytest.mark.parametrize(("text", "entry", "real_kg"), FIXED)
def test_a_coverage_request_reads_as_its_entry(text: str, entry: str, real_kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "real_kg"), [
    f if f[0] in BUILT_BY_DEFAULT else pytest.param(*f, marks=pytest.mark.slow) for f in FIXED])
def test_a_coverage_request_weighs_about_its_real_mass_as_built(text: str, entry: str, real_kg: float) -> None:
    assert 0.5 <= planned_mass(text) / real_kg <= 2.0
