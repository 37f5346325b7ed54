"""Session 54 dev list (post-hoc from sealed set 41's misses)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a gujiya, the crescent shaped fried sweet with the crimped edge", "gujiya", 0.04),
    ("a cucumber sandwich triangle from the tea interval", "cucumber_sandwich", 0.045),
    ("a thawed day old chick for feeding the owls", "feeder_chick", 0.04),
    ("small knitted bird nest, woolly, about the size of a cereal bowl", "knitted_nest", 0.035),
    ("fleece pouch we hang up for the orphaned joeys", "joey_pouch", 0.15),
    ("leather bota bag wineskin, half full, sloshing", "bota_bag", 0.65),
    ("drawstring leather coin purse with some coins in it", "leather_coin_purse", 0.15),
    ("cloth sandbag anchor for the kite line, about half full of sand", "kite_sandbag", 5.5),
    ("make the orange landing area windsock, around 1.5m long, hanging limp", "dropzone_windsock", 0.4),
    ("rainbow ripstop spinner windsock, about a metre long with streamers", "spinner_windsock", 0.1),
    ("a frameless parafoil kite stuffed into its little carry bag", "stuff_sack", 0.25),
    ("a parafoil kite", "parafoil_kite", 0.25),
    ("Floppy cloth marionette, a jester with a stuffed body and little wooden hands", "jester_marionette", 0.4),
    ("microwave wheat heat bag for the baby birds box, flannel cover", "heat_pad", 0.8),
])
def test_dev54a_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


def test_the_new_goods_do_not_take_their_neighbours() -> None:
    """A plain chick is still the plush chicken, a plain sandbag the flood sandbag, a coin bag the coin bag, a plain
    puppet the hand puppet."""
    assert catalogue.design_from_text("a chick").entry == "plush_chicken"
    assert catalogue.design_from_text("a sandbag").entry == "sandbag"
    assert catalogue.design_from_text("a bag of coins").entry == "coin_bag"
    assert catalogue.design_from_text("a hand puppet").entry == "hand_puppet"
