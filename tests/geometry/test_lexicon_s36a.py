"""Soft things found at home (session 36a: bedroom, bathroom, kitchen, living room, toy box, laundry, closet and
nursery) that L0 built as something else: each is its own entry now (contracts/lexicon/everyday_s36a.yaml, drawn by
tasks/geometry/shapes/everyday_s36a.yaml), found from other phrasings than its first noun, and weighs about what the
real object weighs."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry"), [
    ("a navy silk tie", "necktie"),  # a generic block
    ("a black bowtie", "bow_tie"),  # a generic block
    ("an old fashioned sleeping cap", "nightcap"),  # a baseball cap
    ("a pink satin hanger", "padded_hanger"),  # a generic block
    ("a compression storage bag", "vacuum_storage_bag"),  # a generic bag ("vacuum ..." reads as a vacuum pack)
    ("a blue cot bumper", "crib_bumper"),  # a generic block
    ("a bunny lovey", "lovey"),  # a generic block
    ("a baby sleeping bag", "baby_sleep_sack"),  # an adult sleeping bag
    ("a kids crawl tunnel", "play_tunnel"),  # a generic block
    ("a crinkle tunnel for the cat", "cat_tunnel"),  # a generic block
    ("a kids teepee", "play_teepee"),  # a generic block
    ("a toilet rug", "contour_rug"),  # a plain bath mat
    ("a plunger", "toilet_plunger"),  # a generic ball
    ("an ostrich duster", "feather_duster"),  # a generic garment
    ("a bumbo seat", "baby_floor_seat"),  # a generic block
    ("a rainbow ring stacker", "stacking_rings"),  # a generic block
    ("a clothes hamper", "laundry_hamper"),  # a generic block
    ("a hanging shoe organizer", "shoe_organizer"),  # a generic block
    ("a tassel tieback", "curtain_tassel"),  # a generic block
    ("a red kids cape", "kids_cape"),  # a generic garment
    ("an activity gym for a baby", "baby_play_gym"),  # a generic block
    ("a foam ball pit", "ball_pit"),  # a generic ball
    ("a linen table runner", "table_runner"),  # a generic garment
    ("a felted wool ball for the dryer", "wool_dryer_ball"),  # a 'dryer ball' was a rubber ball
    ("a nappy bag", "diaper_bag"),  # a disposable diaper
])
def test_home_objects_build_their_own_entry(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "low", "high"), [
    ("a necktie", 0.0275, 0.11),  # 45-70 g (silk and polyester ties)
    ("a bow tie", 0.01, 0.04),  # 15-30 g
    ("a nightcap", 0.03, 0.12),  # 40-80 g (flannel, with a pompom)
    ("a padded hanger", 0.03, 0.12),  # 45-75 g
    ("a space saver bag", 1.0, 4.0),  # ~2 kg: the bag (~150 g) squeezed round a duvet or clothes
    ("a crib bumper", 0.45, 1.8),  # 0.7-1.2 kg
    ("a lovey", 0.04, 0.16),  # 60-110 g
    ("a wearable blanket", 0.14, 0.56),  # 0.22-0.35 kg (2.5 tog, 0-6 months)
    ("a play tunnel", 0.6, 2.4),  # 0.9-1.5 kg (180 x 46 cm)
    ("a cat tunnel", 0.175, 0.7),  # 0.3-0.5 kg
    ("a play teepee", 2.25, 9.0),  # 3.5-6 kg with its five pine poles
    ("a contour rug", 0.3, 1.2),  # 0.45-0.8 kg
    ("a toilet plunger", 0.15, 0.6),  # 0.25-0.4 kg
    ("a feather duster", 0.06, 0.24),  # 0.09-0.18 kg
    ("a baby floor seat", 0.675, 2.7),  # 1.2-1.5 kg
    ("a ring stacker", 0.15, 0.6),  # 0.2-0.4 kg
    ("a laundry hamper", 0.5, 2.0),  # ~1 kg: the hamper (0.4-0.8 kg) and a few garments
    ("an over the door shoe organizer", 0.35, 1.4),  # 0.5-0.9 kg
    ("a curtain tassel", 0.04, 0.16),  # 50-120 g
    ("a superhero cape", 0.035, 0.14),  # 50-100 g
    ("a baby play gym", 0.75, 3.0),  # 1.1-2 kg
    ("a ball pit", 3.5, 14.0),  # ~7 kg: the foam pool (3-4 kg) and ~200 balls
    ("a table runner", 0.1, 0.4),  # 0.15-0.3 kg (33 x 180 cm)
    ("a wool dryer ball", 0.0225, 0.09),  # 40-50 g
    ("a diaper bag", 0.375, 1.5),  # 0.6-0.9 kg empty
])
def test_home_objects_weigh_within_2x(text: str, low: float, high: float) -> None:
    assert low <= planned_mass(text) <= high
