"""Session 37's audit of the ball group: sports balls carry their markings as parts in their own colours (a
basketball's black grooves, a padel ball's white seam curve, a baseball's red stitches, a pickleball's holes, an
American football's pointed ends and laces) raised or cut deep enough that the colour shows at draft meshing, and
food balls their cues (a cake pop's stick, an edam's cut wedge, a burrata's knot, a scoop's lip); a shuttlecock is a cork and a
hollow skirt. Each object is designed once (module-scoped)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import part_colors, program_bounds

TEXTS = {
    "basketball": "a basketball", "padel": "a padel ball", "baseball": "a foam baseball",
    "pickleball": "a pickleball", "football": "an american football", "medicine": "a medicine ball",
    "cake_pop": "a cake pop", "edam": "an edam", "burrata": "a burrata", "shuttlecock": "a shuttlecock",
    "massage": "a massage ball", "scoop": "a scoop of ice cream",
}


@pytest.fixture(scope="module")
def programs() -> dict:
    return {k: catalogue.design_from_text(t).program for k, t in TEXTS.items()}


def _parts(program, group: str) -> list:  # noqa: ANN001
    return [p for p in program.parts if part_group(p.name).split()[-1] == group]


def _luma(rgb) -> float:  # noqa: ANN001
    return float(np.dot(rgb, (0.2126, 0.7152, 0.0722)))


def _body(program):  # noqa: ANN001, ANN202
    return next(p for p in program.parts if p.name == "body")


def test_the_entries_are_their_own(programs: dict) -> None:
    assert catalogue.design_from_text("a basketball").concept.concept == "basketball"
    assert catalogue.design_from_text("a shuttlecock").concept.concept == "shuttlecock"


def test_a_basketball_has_its_four_dark_grooves_that_show(programs: dict) -> None:
    """The equator, a meridian and two curved lines, cut in, black on orange; the colour at a groove's floor is
    much darker than the body's (two parts' colour against the body's there)."""
    prog = programs["basketball"]
    seams = _parts(prog, "seam")
    assert len({part_group(p.name) for p in seams}) >= 4
    assert all(p.operation == "subtract" and _luma(p.color_rgb) < 0.1 for p in seams)
    body = _body(prog)
    c, r = np.asarray(body.transform.translation_m), body.primitive.radii_m[0]
    floor = (c + np.array([r - 0.02 * 2 * r, 0.0, 0.0]))[None]  # the equator groove's floor, in front
    size = float((program_bounds(prog)[1] - program_bounds(prog)[0]).max())
    rgb = part_colors(floor, prog, sharpness_m=1.5 * size / 64)[0]
    assert _luma(rgb) < 0.45 * _luma(body.color_rgb)


def test_a_padel_ball_has_a_white_seam_curve_and_a_baseball_red_stitches(programs: dict) -> None:
    padel = programs["padel"]
    seam = _parts(padel, "seam")
    assert len(seam) >= 24 and all(_luma(p.color_rgb) > 0.8 for p in seam)
    assert _luma(_body(padel).color_rgb) < 0.8
    pts = np.array([p.transform.translation_m for p in seam])
    assert np.ptp(pts[:, 2]) > 0.5 * _body(padel).primitive.radii_m[2]  # it winds over the ball, not a flat ring
    stitches = _parts(programs["baseball"], "stitch")
    assert len(stitches) >= 24 and all(p.color_rgb[0] > 2 * p.color_rgb[1] for p in stitches)


def test_raised_markings_stand_out_about_two_draft_cells(programs: dict) -> None:
    """A medicine ball's panel seams stand ~3 % of its diameter proud: their colour wins over the body's."""
    prog = programs["medicine"]
    body = _body(prog)
    d = 2 * body.primitive.radii_m[0]
    seams = _parts(prog, "seam")
    assert len(seams) >= 4
    assert all(p.primitive.radii_m[0] - body.primitive.radii_m[0] >= 0.025 * d for p in seams)


def test_a_pickleball_has_holes(programs: dict) -> None:
    holes = _parts(programs["pickleball"], "hole")
    assert len(holes) >= 20 and all(p.operation == "subtract" for p in holes)


def test_an_american_football_is_pointed_with_raised_laces(programs: dict) -> None:
    prog = programs["football"]
    lo, hi = program_bounds(prog)
    ext = hi - lo
    assert 1.4 < ext[0] / ext[1] < 1.9
    tips = _parts(prog, "tip")
    assert len(tips) == 2 and all(p.primitive.kind == "cone" for p in tips)
    body = _body(prog)
    top = body.transform.translation_m[2] + body.primitive.radii_m[2]
    laces = _parts(prog, "lace")
    assert len(laces) >= 7 and max(p.transform.translation_m[2] for p in laces) > top
    assert all(_luma(p.color_rgb) > 0.7 for p in laces)


def test_food_balls_carry_their_cues(programs: dict) -> None:
    pop = programs["cake_pop"]
    stick = _parts(pop, "stick")[0]
    body = _body(pop)
    assert stick.transform.translation_m[2] < body.transform.translation_m[2] - body.primitive.radii_m[2]
    assert sum(p.name.startswith("sprinkle") for p in pop.parts) >= 12
    edam = programs["edam"]
    inside = _parts(edam, "inside")[0]
    assert inside.operation == "subtract" and _luma(inside.color_rgb) > 2 * _luma(_body(edam).color_rgb)
    burrata = programs["burrata"]
    b = _body(burrata)
    knot = [p for p in burrata.parts if p.name.startswith("knot")]
    assert knot and max(p.transform.translation_m[2] for p in knot) > b.transform.translation_m[2] + b.primitive.radii_m[2]
    scoop = programs["scoop"]
    lip = [p for p in scoop.parts if p.name.startswith("lip")]
    s = _body(scoop)
    assert len(lip) >= 6 and all(p.transform.translation_m[2] < s.transform.translation_m[2] for p in lip)


def test_a_shuttlecock_is_a_cork_under_a_hollow_flaring_skirt(programs: dict) -> None:
    prog = programs["shuttlecock"]
    cork, skirt = _parts(prog, "cork")[0], _parts(prog, "skirt")[0]
    assert skirt.primitive.radius_top_m > 2 * skirt.primitive.radius_bottom_m
    assert cork.transform.translation_m[2] < skirt.transform.translation_m[2]
    assert any(p.operation == "subtract" and p.name.startswith("skirt") for p in prog.parts)


def test_a_massage_ball_is_spiky(programs: dict) -> None:
    assert len(_parts(programs["massage"], "spike")) >= 20
