"""Session 42's redraw (r3): objects the blind judges could not name as built. Each prompt now reads as an entry with a
hand-written shape (tasks/geometry/shapes/redraw42_r3.yaml) or a strap plan drawn with the cues a person names it by,
and its built mass is within 2x of the real object's: ribeyes wrapped in butcher paper (were two bare steaks, 'mini
pizzas') as pink paper parcels with folded ends, tape, marker writing and a steak edge showing; a beef tongue (was a
generic blob) as a long tapered tongue with a rough top, a groove and a cut root; a ground beef chub (read as a salami)
with mince showing through the film, a label on top and metal clips; a rain poncho folded in its little pouch (was
the full stuff sack at 4x its mass) as the flat retail packet; a folded band T-shirt (was a white garment, 'a quilted
placemat') black with a collar and a printed logo; a 2.5 m yoga strap (was black webbing, 'a coiled rope') purple
with its metal rings; rental bowling shoes (were red sneakers, 'Santa slippers') tan, red and blue with laces, a thin
sole and the size on the heel; a rosin bag (a flat pillow, 'a tea bag') as a tied cloth pouch in its dust; a bowling
wrist brace (was a generic block) as a black neoprene brace with a thumb hole, stiffener and velcro strap. Checked on
the programs: the readings in the default run, the built masses under -m slow."""

from __future__ import annotations

import functools

import pytest

from contracts.lexicon import load_lexicon
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import drawn_mass_kg, planned_mass

# prompt as typed, entry, the real object's mass [kg]
CASES = [
    ("2 ribeyes wrapped in butcher paper", "butcher_paper_ribeye", 0.7),
    ("beef tongue", "beef_tongue", 1.2),
    ("1lb chub of ground beef", "ground_beef_chub", 0.454),
    ("rain poncho folded in its little pouch", "poncho_pouch", 0.07),
    ("band tshirt XL, folded", "band_tshirt_folded", 0.22),
    ("yoga strap 2.5m", "yoga_strap", 0.12),
    ("pair of rental bowling shoes sz 10", "bowling_shoe", 0.95),
    ("rosin bag", "rosin_bag", 0.04),
    ("neoprene wrist brace for bowling", "bowling_wrist_brace", 0.12),
]


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


@pytest.mark.parametrize(("text", "entry", "_kg"), CASES)
def test_the_prompt_reads_as_the_entry(text: str, entry: str, _kg: float) -> None:
    d = _design(text)
    assert d.entry == entry
    assert len(d.program.parts) <= 64


@pytest.mark.slow
@pytest.mark.parametrize(("text", "entry", "kg"), CASES)
def test_the_built_mass_is_within_2x_of_the_real_mass(text: str, entry: str, kg: float) -> None:
    """L1's mass as the blind bench weighs it (tests.geometry.test_mass_classes.planned_mass): the density over the
    volume built at the final size, or the mass the request states ('1lb')."""
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (entry, planned_mass(text), kg)


@pytest.mark.slow
@pytest.mark.parametrize("entry", [e for _t, e, _k in CASES if e != "yoga_strap"])
def test_the_density_is_the_sourced_mass_over_the_built_volume(entry: str) -> None:
    """Density is the sourced mass over the built shape's volume at size_m (L0's draft mesh, 48 cells)."""
    e, mass = load_lexicon().entries[entry], drawn_mass_kg(entry)
    assert 0.85 * e.mass_kg <= mass <= 1.15 * e.mass_kg, (entry, mass, e.mass_kg)


def test_a_poncho_in_its_pouch_is_the_packet_and_other_goods_keep_the_stuff_sack() -> None:
    """'X folded in its pouch' is an entry of its own where the lexicon has 'X in its pouch'; else the stuff sack."""
    assert _design("rain poncho folded in its little pouch").concept.stated_mass_kg is None
    assert _design("a sleeping bag stuffed in its sack").entry == "stuff_sack"
    assert _design("a rain poncho").entry == "rain_poncho"
