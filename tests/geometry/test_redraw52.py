"""Session 52 redraw: six entries whose renders strangers misnamed (a sanding sponge named a granola bar, a beret an
upside-down bowl, cut comb honey a slab of fudge, a bag of mini marshmallows an egg carton, a rosin bag a favour
pouch, a corner tamping mat an L-shaped phone stand) are redrawn; each wording still builds its entry at its mass."""

from __future__ import annotations

import pytest

from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("sanding sponge, medium grit", "sanding_sponge", 0.03),
    ("beret", "beret", 0.08),
    ("chunk of comb honey", "cut_comb_honey", 0.35),
    ("bag of mini marshmallows", "marshmallow_bag", 0.31),
    ("grab the rosin bag off the bench", "rosin_bag", 0.03),
    ("silicone tamping mat", "tamping_mat", 0.15),
])
def test_redraw52_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)
