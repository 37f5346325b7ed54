"""Session 54: basic-level nouns (garments and accessories) build a typical member of their kind.

A bare basic noun ('a hat', 'a helmet', 'a wallet') built by analogy (a generic garment, bag, block or object); each
now builds a typical member of its kind (contracts/lexicon/basic54a.yaml) at a typical mass, or the existing entry that
is its prototype (the noun added to that entry). Compounds with entries of their own
still read them."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a hat", "felt_hat", 0.11),
    ("a suit", "business_suit", 1.3),
    ("a wallet", "bifold_wallet", 0.08),
    ("a helmet", "bike_helmet", 0.3),
    ("a collar", "dog_collar", 0.05),
    ("a harness", "dog_harness", 0.2),
    ("a saddle", "western_saddle", 12.0),
    ("a gown", "evening_gown", 0.7),
    ("a tunic", "tunic", 0.35),
    ("underwear", "briefs", 0.05),
    ("a pair of overalls", "bib_overalls", 1.0),
    ("a turban", "wrapped_turban", 0.4),
    ("a pair of earmuffs", "earmuffs", 0.1),
    ("a muff", "hand_muff", 0.25),
    ("a patch", "embroidered_patch", 0.003),
    ("a holster", "leather_holster", 0.2),
    ("a sheath", "knife_sheath", 0.08),
    ("a canteen", "water_canteen", 1.1),
    # nouns an existing entry already reads as its prototype
    ("a pair of tights", "leggings", 0.2),
    ("a raincoat", "jacket", 0.6),
    ("a satchel", "hobo_handbag", 0.7),
    ("a jumpsuit", "coveralls", 0.9),
    ("a shawl", "scarf", 0.2),
    # the bare noun added to the existing entry that is its prototype
    ("a sandal", "flip_flop", 0.12),
    ("a purse", "hobo_handbag", 0.7),
    ("a mask", "face_mask", 0.003),
    ("a cloak", "velvet_cloak", 1.3),
    ("a bonnet", "newborn_bonnet", 0.02),
    ("a bandage", "gauze_roll", 0.02),
    ("a duffel", "duffel_bag", 0.6),
    ("a waterskin", "bota_bag", 0.65),
])
def test_basic_noun_builds_a_typical_member_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


@pytest.mark.parametrize(("text", "entry"), [
    ("a ski hat", "ski_hat"),
    ("a bucket hat", "bucket_hat"),
    ("a cowboy hat", "cowboy_hat"),
    ("a bee suit", "bee_suit"),
    ("a bike saddle", "bike_saddle"),
    ("a rabbit harness", "rabbit_harness"),
    ("an eye patch", "adhesive_eye_patch"),
    ("a hospital gown", "hospital_gown"),
    ("a dog leash", "dog_leash"),
])
def test_compounds_with_their_own_entries_still_read_them(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_rain_suit_is_the_rain_jacket_not_the_business_suit() -> None:
    """Set 41's 'two piece motorcycle rain suit': with 'suit' the business suit, a rain suit is the jacket (a shell)."""
    assert catalogue.design_from_text("a rain suit").entry == "jacket"
    assert catalogue.design_from_text("a suit").entry == "business_suit"
    # set 42's 'padded bite suit jacket' (a K9 decoy's jacket) read 'suit jacket' as the business suit
    assert catalogue.design_from_text("the padded bite suit jacket").entry != "business_suit"
    assert catalogue.design_from_text("a suit jacket").entry == "blazer"  # (session 58: the tailored jacket with
    # lapels; before there was none, the plain jacket)
