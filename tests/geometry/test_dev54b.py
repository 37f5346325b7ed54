"""Session 54 dev list (post-hoc from sealed set 41's misses)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("one cricket batting pad, left leg, straps undone", "cricket_batting_pad", 0.65),
    ("Can you make a foam thigh guard like the ones we keep in the pavilion", "cricket_thigh_pad", 0.14),
    ("pair of sweaty batting gloves stuck together after an innings", "batting_gloves", 0.4),
    ("magnetic tank bag, half full, sitting on the fuel tank", "motorcycle_tank_bag", 2.0),
    ("textile riding jacket with the CE armour in, thrown over the seat", "motorcycle_jacket", 2.6),
    ("felt cowboy hat, cattleman crease, a little squashed on one side", "cowboy_hat", 0.16),
    ("batwing rodeo chaps with long fringe, draped over the fence", "rodeo_chaps", 2.5),
    ("Can you build one of those padded bull riding protective vests with the high collar", "bull_riding_vest", 1.6),
    ("bull riding glove, leather, sticky with rosin", "bull_riding_glove", 0.2),
    ("soft frap hat, the padded cloth helmet that tandem students wear", "frap_hat", 0.22),
    ("packed main canopy sitting in its deployment bag, lines stowed in the rubber bands", "parachute_dbag", 2.6),
    ("hackey pilot chute with the bridle, collapsed", "pilot_chute", 0.15),
    ("linen peasant chemise with big puffy sleeves", "peasant_chemise", 0.3),
    ("wool saddle blanket, navajo pattern, folded in half", "navajo_saddle_blanket", 1.8),
    ("sheepskin pad for the motorcycle seat, a bit matted from the rain", "sheepskin_seat_pad", 0.45),
    ("gamcha towel tied round my head, red and white check, thin cotton", "gamcha_head_wrap", 0.15),
])
def test_dev54b_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


def test_batting_and_saddle_readings_stay_apart() -> None:
    """'batting pad' and 'batting gloves' are cricket kit, plain batting is still the quilt roll; a plain saddle
    blanket is still the saddle pad, a wool or navajo one the folded blanket."""
    assert catalogue.design_from_text("a roll of quilt batting").entry == "batting_roll"
    assert catalogue.design_from_text("cricket batting pad").entry == "cricket_batting_pad"
    assert catalogue.design_from_text("a saddle pad").entry == "saddle_pad"
    assert catalogue.design_from_text("navajo saddle blanket").entry == "navajo_saddle_blanket"
    assert catalogue.design_from_text("a bath towel").entry == "bath_towel"
    assert catalogue.design_from_text("a sheepskin rug").entry == "sheepskin"
