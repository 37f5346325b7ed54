"""Outdoor, sports and travel objects the lexicon did not know (session 36b): camping and hiking, beach and pool, gym,
team sports, cycling, winter, garden, car trunk, carry-on. Each entry is built from another phrasing than its first
noun, and weighs what the real object does (within 2x)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry"), [
    ("a pair of flippers", "swim_fins"),
    ("a bosu balance trainer", "bosu_ball"),
    ("a football shin pad", "shin_guard"),
    ("a leather baseball mitt", "baseball_glove"),
    ("a soccer goalie glove", "goalkeeper_glove"),
    ("an orange scrimmage vest", "training_pinnie"),
    ("a yellow saucer cone", "disc_cone"),
    ("a football tackle dummy", "tackling_dummy"),
    ("a gel bike seat", "bike_saddle"),
    ("a waterproof bicycle pannier", "bike_pannier"),
    ("a black ski mask", "balaclava"),
    ("mirrored snowboard goggles", "ski_goggles"),
    ("a pair of swimming goggles", "swim_goggles"),
    ("a sledding tube", "snow_tube"),
    ("a foam toboggan", "foam_sled"),
    ("a windshield sun shade", "car_sunshade"),
    ("a suit bag", "garment_bag"),
    ("a soft sided cooler", "soft_cooler"),
    ("a boxing focus pad", "focus_mitt"),
    ("a bum bag", "fanny_pack"),
    ("a heavy bag for boxing", "punching_bag"),
    ("a two person camping tent", "dome_tent"),
    ("a boogie board", "bodyboard"),
    ("an inflatable kiddie pool", "paddling_pool"),
])
def test_s36b_nouns_build_their_own_object(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "typical_kg"), [
    ("swim fins", 1.0),  # full-foot fins, a pair: 0.8-1.3 kg
    ("a bosu ball", 7.0),  # BOSU Home balance trainer ~7 kg
    ("a shin guard", 0.1),  # slip-in soccer shin guard 80-150 g
    ("a baseball glove", 0.6),  # 11.5-12.5 in leather glove 550-700 g
    ("a goalkeeper glove", 0.13),  # latex-palm goalkeeper glove 110-160 g
    ("a pinnie", 0.08),  # polyester mesh scrimmage vest 60-100 g
    ("a disc cone", 0.035),  # 19 cm PE disc cone 30-40 g
    ("a tackling dummy", 9.0),  # 48 in foam tackling dummy 7-11 kg
    ("a bike saddle", 0.3),  # padded saddle 220-400 g
    ("a pannier", 1.0),  # Ortlieb Back-Roller Classic 1.0 kg each
    ("a balaclava", 0.07),  # knit balaclava 50-100 g
    ("ski goggles", 0.2),  # 150-250 g
    ("swim goggles", 0.035),  # silicone swim goggles 25-45 g
    ("a snow tube", 2.0),  # 40-44 in nylon-covered snow tube 1.5-3 kg
    ("a foam sled", 1.8),  # 100-120 cm foam sled 1.3-2.5 kg
    ("a car sunshade", 0.35),  # 140 x 70 cm bubble-foil shade 0.25-0.45 kg
    ("a garment bag", 0.6),  # zip suit bag 0.4-0.9 kg
    ("a cooler bag", 0.9),  # 24-can soft cooler, empty 0.7-1.2 kg
    ("a focus mitt", 0.4),  # 350-500 g each
    ("a fanny pack", 0.2),  # 150-250 g
    ("a punching bag", 20.0),  # filled 3-4 ft heavy bag 18-25 kg
    ("a dome tent", 2.5),  # 2-person backpacking dome tent 1.8-3.2 kg
    ("a bodyboard", 1.1),  # 41-42 in bodyboard 0.9-1.4 kg
    ("a paddling pool", 3.0),  # 3-ring 147 cm PVC paddling pool 2.5-3.5 kg
])
def test_s36b_masses_within_2x(text: str, typical_kg: float) -> None:
    assert typical_kg / 2.0 <= planned_mass(text) <= typical_kg * 2.0
