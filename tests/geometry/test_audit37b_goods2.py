"""Session 37's second audit round on the goods group: an American football (and a foam one) is a pointed spindle
with raised laces and two stripes; 'a bunch of grapes' is a tapered cluster of purple grapes with a stem and a leaf
(its own entry, not one grape's flat rows); a lick mat carries raised rings and a smear of paste; 'a pair of ballet
slippers' is two low pink slippers with an open top and a bow; a catnip kicker is a slim light fish with orange fins;
a floor pouf is a round seat of panels, its dark seams meeting at a top button.
Each object is designed once (module-scoped)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, concepts
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds

TEXTS = {  # (the pouf is designed in its own test)
    "football": "an american football", "foam_football": "a foam football", "grapes": "a bunch of grapes",
    "lick": "a silicone lick mat with paste", "ballet": "a pair of ballet slippers",
    "kicker": "a catnip kicker fish toy",
}


@pytest.fixture(scope="module")
def designs() -> dict:
    return {k: catalogue.design_from_text(t) for k, t in TEXTS.items()}


def _named(program, word: str) -> list:  # noqa: ANN001
    return [p for p in program.parts if word in part_group(p.name).split()]


def _ext(program) -> np.ndarray:  # noqa: ANN001
    lo, hi = program_bounds(program)
    return np.asarray(hi) - np.asarray(lo)


def test_footballs_are_pointed_with_laces_and_stripes(designs: dict) -> None:
    for key, lace_luma in (("football", 0.7), ("foam_football", 0.6)):
        prog = designs[key].program
        ext = _ext(prog)
        assert 1.4 < ext[0] / ext[1] < 1.9, key
        assert len(_named(prog, "tip")) == 2 and len(_named(prog, "stripe")) == 2, key
        laces = _named(prog, "lace")
        assert len(laces) >= 7, key
        assert min(float(np.dot(p.color_rgb, (0.2126, 0.7152, 0.0722))) for p in laces) > lace_luma, key
    assert designs["football"].program.parts[0].color_rgb[0] > 2 * designs["football"].program.parts[0].color_rgb[2]


def test_a_bunch_of_grapes_is_its_own_purple_cluster_with_a_stem(designs: dict) -> None:
    design = designs["grapes"]
    assert concepts.read_text("a bunch of grapes").match.concept == "grape_bunch"
    grapes = _named(design.program, "grape")
    assert len(grapes) >= 30
    assert all(p.color_rgb[2] > p.color_rgb[1] + 0.1 for p in grapes)  # purple
    assert _named(design.program, "stem") and _named(design.program, "leaf")
    ext = _ext(design.program)
    assert ext[0] > 1.5 * ext[1] > 2.0 * ext[2]  # longer than wide, lying low
    assert concepts.read_text("a grape").match.concept == "grape"


def test_a_lick_mat_has_rings_and_paste(designs: dict) -> None:
    prog = designs["lick"].program
    assert len(_named(prog, "ring")) >= 3
    paste = _named(prog, "paste")
    assert paste and all(p.color_rgb[0] > p.color_rgb[2] + 0.2 for p in paste)  # a brown spread on a green mat
    ext = _ext(prog)
    assert ext[2] < 0.15 * ext[0]


def test_a_pair_of_ballet_slippers_is_two_low_pink_open_slippers(designs: dict) -> None:
    prog = designs["ballet"].program
    assert concepts.read_text("a pair of ballet slippers").match.concept == "ballet_slipper"
    assert len(_named(prog, "sole")) == 2 and len(_named(prog, "binding")) == 2 and len(_named(prog, "bow")) >= 4
    sole = _named(prog, "sole")[0]
    assert sole.color_rgb[0] > 0.85 and sole.color_rgb[0] > sole.color_rgb[1] + 0.15  # pink
    one = designs["ballet"].program.parts[0]
    assert one.primitive.radii_m[0] > 2.5 * one.primitive.radii_m[1]  # long and narrow


def test_a_catnip_kicker_is_a_slim_fish_with_orange_fins(designs: dict) -> None:
    design = designs["kicker"]
    assert concepts.read_text("a catnip kicker fish toy").match.concept == "cat_kicker"
    prog = design.program
    body = _named(prog, "body")[0]
    assert body.color_rgb[2] > body.color_rgb[0]  # light blue
    fins = _named(prog, "fin") + _named(prog, "tail")
    assert fins and all(p.color_rgb[0] > p.color_rgb[2] + 0.3 for p in fins)  # orange
    ext = _ext(prog)
    assert ext[0] > 2.0 * ext[2]


def test_a_pouf_is_a_round_seat_of_panels_with_dark_seams_and_a_button() -> None:
    prog = catalogue.design_from_text("a pouf").program
    seams = _named(prog, "seam")
    assert len(seams) >= 16 and _named(prog, "button")
    body = prog.parts[0]
    assert all(sum(p.color_rgb) < 0.6 * sum(body.color_rgb) for p in seams)  # dark piping on a light cover
    ext = _ext(prog)
    assert 1.1 < ext[0] / ext[2] < 1.6 and abs(ext[0] - ext[1]) < 0.05 * ext[0]
