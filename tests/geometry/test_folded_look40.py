"""Session 40's folded textiles: blind judges read folded towels, an apron, a bib and a bathrobe as foam mats, seat
cushions and packaging inserts (a thick flat-topped slab with crisp edges), and a rolled sleeping bag as a yoga mat.
Folded cloth now has a round crease, its layers' edges seen apart, a soft top; a towel its woven border bands; a
folded garment its own cues on top (a robe's shawl collar and belt, an apron's neck strap, ties and pocket); a bib
its outline with the bottom folded up; a rolled sleeping bag two straps with buckles round the roll."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from contracts.shape import MAX_PARTS, ShapeProgram
from tasks.geometry import grammar
from tasks.geometry.catalogue import design_from_text
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_sdf

PROMPTS = ("black salon towel, folded", "child's paint apron, folded", "a cloth baby bib, folded",
           "a white terry cloth bathrobe, folded", "bath mat folded in half", "a rolled sleeping bag",
           "a folded bath towel", "a towel folded in thirds", "a folded striped beach towel")
BATH_TOWEL = {"width": 0.5, "thickness": 0.00357, "folds": 2}  # the lexicon's 70 x 140 cm bath towel
SLEEPING_BAG = {"width": 0.375, "thickness": 0.025, "quilt": 10, "zip": True, "hood": True}  # 200 x 75 cm
CORNER_IN = 0.1  # a probe this share of the folded stack's height in from its end's corner [-]


@functools.lru_cache(maxsize=16)
def _program(text: str) -> ShapeProgram:
    return design_from_text(text).program


def _groups(text: str) -> list[str]:
    """The part groups of a text's program, one per part."""
    return [part_group(p.name) for p in _program(text).parts]


def _colour(text: str, group: str) -> np.ndarray:
    """The colour of a text's first part of a group."""
    return np.asarray(next(p.color_rgb for p in _program(text).parts if part_group(p.name) == group))


@pytest.mark.parametrize("text", PROMPTS)
def test_folded_textiles_stay_within_the_part_budget_with_unique_names(text: str) -> None:
    names = [p.name for p in _program(text).parts]
    assert len(names) <= MAX_PARTS and len(set(names)) == len(names)


def test_a_folded_towel_has_a_round_crease_layer_lines_and_two_border_bands() -> None:
    groups = _groups("a folded bath towel")
    assert groups.count("border") == 2
    assert {"crease", "layer", "loft"} <= set(groups)  # (session 45: its layers own soft slabs, not grooves cut)


def test_the_crease_side_is_round_and_the_open_side_shows_its_layers() -> None:
    """Probes into the folded towel: just inside its crease end's top corner is outside the solid (the crease is
    round, not a slab's square edge) while the middle of that end is cloth; at the open end, between the first two
    layers' rounded edges, is outside."""
    prog = _program("a folded bath towel")
    part = {p.name: p for p in prog.parts}
    body, crease, second = part["body"], part["crease"], part["layer 2"]
    top = max(float(p.transform.translation_m[2] + p.primitive.size_m[2] / 2) for p in prog.parts
              if p.name == "body" or p.name.startswith("layer "))
    lo = float(body.transform.translation_m[0] - body.primitive.size_m[0] / 2)
    hi = min(float(q.transform.translation_m[0] + q.primitive.size_m[0] / 2) for q in (body, second))
    s = float(np.sign(crease.transform.translation_m[0] - 0.5 * (lo + hi)))  # the crease's end
    crease_end, open_end = (lo, hi) if s < 0 else (hi, lo)
    d = CORNER_IN * top
    seam = float(body.transform.translation_m[2] + body.primitive.size_m[2] / 2)  # between the first two layers
    probes = np.array([[crease_end - s * d, 0.0, top - d],  # the crease end's top corner
                       [crease_end - s * d, 0.0, 0.5 * top],  # its middle
                       [open_end + s * 0.02 * abs(hi - lo), 0.0, seam]])  # the open end, between two layers
    inside = program_sdf(probes, prog) < 0
    assert inside.tolist() == [False, True, False]


def test_a_patterned_folded_towel_shows_its_stripes_not_bands() -> None:
    """A woven pattern over the top (a tea towel's stripes) is the towel's cue: no plain bands drawn over it."""
    striped = grammar.build_program("sheet", {**BATH_TOWEL, "state": "folded", "border": True, "stripes": 3}, {},
                                    "towel", "textile", 0.7)
    groups = {part_group(p.name) for p in striped.parts}
    assert "stripe" in groups and "border" not in groups
    assert "border" not in _groups("a folded striped beach towel")  # (a beach towel has no woven band)


def test_a_towels_bands_keep_the_towels_mass() -> None:
    """Small details only: the bands change the folded towel's built volume little (its mass is the flat towel's
    through the density factor; session 45 drew folded cloth lower, so the factor is no longer ~1)."""
    change = grammar.state_change("sheet", {**BATH_TOWEL, "border": True}, 1.4, "folded")
    plain = grammar.state_change("sheet", BATH_TOWEL, 1.4, "folded")
    assert change.density_factor == pytest.approx(plain.density_factor, rel=0.1)
    assert change.mass_factor == 1.0 and 1.0 <= change.density_factor < 2.0


def test_a_rolled_sleeping_bag_is_strapped_and_a_rolled_mat_is_not() -> None:
    groups = _groups("a rolled sleeping bag")
    assert groups.count("strap") == 2 and groups.count("buckle") == 2 and "baffle" in groups
    assert not {"strap", "buckle"} & set(_groups("a rolled yoga mat"))
    assert np.abs(_colour("a rolled sleeping bag", "strap") - _colour("a rolled sleeping bag", "body")).max() > 0.1
    with_straps = grammar.state_change("sheet", {**SLEEPING_BAG, "straps": True}, 1.98, "rolled")
    without = grammar.state_change("sheet", SLEEPING_BAG, 1.98, "rolled")
    assert with_straps.density_factor == pytest.approx(without.density_factor, rel=0.1)
    assert with_straps.size_m == pytest.approx(without.size_m, rel=0.05)


def test_a_folded_apron_shows_its_neck_strap_ties_and_pocket() -> None:
    text = "child's paint apron, folded"
    assert {"neck strap", "tie", "pocket"} <= set(_groups(text))
    assert _groups(text).count("tie") >= 4  # each tie out of a side and lying in bends on the table
    assert np.abs(_colour(text, "neck strap") - _colour(text, "body")).max() > 0.3


def test_a_folded_robe_shows_its_shawl_collar_and_belt_not_a_sweaters_ribbing() -> None:
    groups = set(_groups("a white terry cloth bathrobe, folded"))
    assert {"lapel", "belt", "belt knot", "belt end", "pocket"} <= groups
    assert not {"hem rib", "cuff rib", "collar band", "sleeve"} & groups


def test_a_folded_bib_keeps_its_neck_opening_and_snaps_with_its_bottom_folded_up() -> None:
    prog = _program("a cloth baby bib, folded")
    groups = {part_group(p.name) for p in prog.parts}
    assert {"neck", "snap", "flap", "flap piping", "crease"} <= groups
    neck = next(p for p in prog.parts if p.name == "neck")
    assert program_sdf(np.array([neck.transform.translation_m]), prog)[0] > 0  # the neck is a hole
