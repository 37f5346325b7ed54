"""Session 54: basic-level nouns (things, plants, food) build a typical member of their kind (a kite, a nest, a flag),
and compound nouns with entries of their own still read them."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a kite", "diamond_kite", 0.1),
    ("a rainbow kite", "diamond_kite", 0.1),
    ("a nest", "bird_nest", 0.06),
    ("a flag", "flag", 0.12),
    ("a banner", "banner", 0.5),
    ("a pennant", "felt_pennant", 0.03),
    ("a wreath", "christmas_wreath", 1.2),
    ("a flower", "daisy_flower", 0.015),
    ("a leaf", "green_leaf", 0.002),
    ("a plant", "potted_plant", 1.5),
    ("a feather", "feather", 0.0006),
    ("a ham", "whole_ham", 4.0),
    ("a candy", "wrapped_candy", 0.005),
    ("a sweet", "wrapped_candy", 0.005),
    ("a buoy", "mooring_buoy", 1.4),
    ("an ottoman", "ottoman", 7.0),
    ("a futon", "futon_mattress", 15.0),
    # the bare noun added to the existing entry that is the typical member of its kind
    ("a pastry", "croissant", 0.057),
    ("a chocolate", "chocolate_truffle", 0.014),
    ("a rattle", "plush_rattle", 0.04),
    ("a float", "pool_float", 1.2),
    ("a mop", "string_mop", 0.25),
    ("a garland", "tinsel_garland", 0.04),
    ("a hide", "rolled_leather_hide", 2.6),
])
def test_basic54b_noun_builds_a_typical_member_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


@pytest.mark.parametrize(("text", "entry"), [
    ("a parafoil kite", "parafoil_kite"), ("a knitted nest", "knitted_nest"), ("a pasta nest", "pasta_nest"),
    ("a ham slice", "ham_slice"), ("a tailors ham", "tailors_ham"), ("a feather boa", "feather_boa"),
    ("a feather duster", "feather_duster"), ("a dry leaf", "dry_maple_leaf"), ("a vine leaf", "vine_leaf"),
    ("a pull buoy", "pull_buoy"), ("a sweet potato", "sweet_potato"), ("cotton candy", "candy_floss"),
    ("a candy bar", "wrapped_snack_bar"), ("a rolled felt banner", "felt_banner_rolled"),
    ("a plant in a grow bag", "planted_grow_bag"), ("a pouf", "pouf"), ("a sheet of paper", "paper_sheet"),
])
def test_compounds_with_their_own_entries_still_read_them(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
