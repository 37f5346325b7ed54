"""Session 43's redraw (r4): sealed set 29's objects the blind judges could not name as built. Each prompt now reads as
an entry with a hand-written shape (tasks/geometry/shapes/redraw43_r4.yaml) drawn with the cues a person names it by,
and its built mass is within 2x of the real object's: a 25 kg bag of Portland cement (a generic white pouch, 'a sack
of rice') as a kraft multiwall paper sack with block ends, a valve, print and a grey spill; a 300 g bag of
marshmallows (the same pouch, 'wet wipes') as a clear bag of white marshmallows with a blue printed header; a mesh bag
of 12 foam practice golf balls (the net-bag pouch, 'a tray of baseballs') as dimpled white balls in a dark net with a
drawstring and cord lock; a goldfish in a bag of water from the ring toss (the plush fish) as a tied water bag with an
orange goldfish; an inflatable striped hammer from the fair (a generic 0.3 g ball) as a 1 m hammer in coloured bands;
a plush tiger head cover for a golf driver (a generic quadruped, 'a polar bear') as a tiger's head on a striped sock
with a ribbed cuff. Checked on the programs: the readings in the default run, the built masses under -m slow."""

from __future__ import annotations

import functools

import pytest

from contracts.lexicon import load_lexicon
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import drawn_mass_kg, planned_mass

# prompt as typed, entry, the real object's mass [kg]
CASES = [
    ("25kg bag of portland cement", "cement_bag", 25.0),
    ("bag of marshmallows 300g", "marshmallow_bag", 0.31),
    ("mesh bag of 12 foam practice golf balls", "golf_ball_mesh_bag", 0.08),
    ("goldfish in a plastic bag of water from the ring toss", "goldfish_bag", 0.5),
    ("inflatable striped hammer from the fair", "inflatable_hammer", 0.12),
    ("plush tiger head cover for a golf driver", "tiger_headcover", 0.15),
]


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


@pytest.mark.parametrize(("text", "entry", "_kg"), CASES)
def test_the_prompt_reads_as_the_entry(text: str, entry: str, _kg: float) -> None:
    d = _design(text)
    assert d.entry == entry
    assert len(d.program.parts) <= 64


def test_the_bag_of_twelve_balls_is_one_bag_and_other_bags_keep_their_readings() -> None:
    """'a mesh bag of 12 balls' counts the balls inside the one bag, not twelve bags; a goldfish alone is the plush."""
    assert [p.name for p in _design("mesh bag of 12 foam practice golf balls").program.parts].count("net body") == 1
    assert _design("a goldfish").entry == "plush_fish"
    assert _design("a bag of frozen peas").entry == "frozen_peas"
    assert _design("a marshmallow").entry == "marshmallow"


@pytest.mark.slow
@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_built_mass_is_within_2x_of_the_real_mass(text: str, entry: str, kg: float) -> None:
    """L1's mass as the blind bench weighs it (tests.geometry.test_mass_classes.planned_mass): the density over the
    volume built at the final size, or the mass the request states ('25kg', '300g')."""
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (entry, planned_mass(text), kg)


@pytest.mark.slow
@pytest.mark.parametrize("entry", [e for _t, e, _k in CASES])
def test_the_density_is_the_sourced_mass_over_the_built_volume(entry: str) -> None:
    """Density is the sourced mass over the built shape's volume at size_m (L0's draft mesh, 48 cells)."""
    e, mass = load_lexicon().entries[entry], drawn_mass_kg(entry)
    assert 0.85 * e.mass_kg <= mass <= 1.15 * e.mass_kg, (entry, mass, e.mass_kg)
