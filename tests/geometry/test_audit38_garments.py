"""Session 38's audit, garments group: garments and worn soft goods the blind judges could not name as built. Folded
tops and jeans read as a padded laptop sleeve, a foam tile or a hardcover book (a plain slab): they now show their
collar with a neck label, sleeves folded across, a ribbed hem, and the front's motif (a chest print, a jersey's number,
cable knit, a gown's scattered print; the jeans' button, fly, pocket scoops and turned-up hems). Shirts laid flat read
as trousers (their sleeves reached the hem like legs). A bra, a knee brace, a foam neck collar and a rain poncho are
hand-written shapes (tasks/geometry/shapes/audit38_garments.yaml). Checked on the programs, built once each."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds, program_sdf


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _program(text: str):  # noqa: ANN202
    return _design(text).program


def _groups(text: str) -> set[str]:
    return {part_group(p.name) for p in _program(text).parts if p.operation == "union"}


def _count(text: str, group: str) -> int:
    return sum(1 for p in _program(text).parts if part_group(p.name) == group and p.operation == "union")


def _extent(text: str) -> np.ndarray:
    lo, hi = program_bounds(_program(text))
    return hi - lo


def _inside(text: str, frac: tuple[float, float, float]) -> bool:
    lo, hi = program_bounds(_program(text))
    p = lo + np.asarray(frac) * (hi - lo)
    return bool(program_sdf(p[None, :], _program(text))[0] < 0)


def _colours(text: str, group: str) -> set[tuple[float, ...]]:
    return {tuple(round(c, 2) for c in p.color_rgb) for p in _program(text).parts
            if part_group(p.name) == group and p.operation == "union"}


@pytest.mark.parametrize(("text", "entry", "groups"), [
    ("folded grey t-shirt", "t_shirt", {"body", "collar band", "neck label", "left sleeve", "left sleeve hem", "print"}),
    ("wool sweater, folded", "sweater", {"collar band", "neck label", "left sleeve", "left cuff", "hem", "hem rib",
                                         "cable"}),
    ("folded football jersey", "sports_jersey", {"collar band", "left sleeve", "left sleeve stripe", "number"}),
    ("folded hospital gown", "hospital_gown", {"collar band", "left sleeve", "dot", "tie"}),
    ("pair of blue jeans, folded", "jeans", {"waistband", "belt loop", "button", "fly stitch", "left pocket edge",
                                            "right pocket stitch", "coin pocket stitch", "left hem cuff"}),
    ("black bra", "bra", {"left cup", "right cup", "centre gore", "bow", "underband", "left wing", "hook tab",
                          "left strap", "left strap slider"}),
    ("knee brace", "knee_brace", {"sleeve", "patella ring", "left hinge", "left stay", "strap", "velcro",
                                  "binding"}),
    ("foam neck collar", "cervical_collar", {"band", "cover seam", "velcro strap", "velcro hooks"}),
    ("rain poncho", "rain_poncho", {"body", "hood", "hood rim", "hood lining", "left drawcord", "left cord toggle",
                                    "left press stud", "pocket"}),
])
def test_named_parts(text: str, entry: str, groups: set[str]) -> None:
    assert _design(text).concept.concept == entry
    groups = {g.removeprefix("left ").removeprefix("right ") for g in groups}  # (a part's group drops its side)
    assert groups <= _groups(text), groups - _groups(text)


@pytest.mark.parametrize("text", ["folded grey t-shirt", "wool sweater, folded", "folded football jersey",
                                  "pair of blue jeans, folded"])
def test_folded_garment_is_a_low_stack_a_little_longer_than_wide(text: str) -> None:
    ext = _extent(text)
    assert ext[2] < 0.35 * min(ext[0], ext[1])  # (a folded sweater ~8 cm high on ~30 cm)
    assert 0.6 < ext[0] / ext[1] < 1.6


def test_folded_sweater_sleeves_cross_the_front_to_ribbed_cuffs() -> None:
    parts = {p.name: p for p in _program("wool sweater, folded").parts}
    assert _count("wool sweater, folded", "cable") >= 9 and _count("wool sweater, folded", "hem rib") >= 8
    assert _count("wool sweater, folded", "cuff rib") == 6
    left, right = parts["left sleeve"], parts["right sleeve"]  # both cross the middle: their centres near y = 0
    w = _extent("wool sweater, folded")[1]
    assert abs(left.transform.translation_m[1]) < 0.1 * w and abs(right.transform.translation_m[1]) < 0.1 * w
    assert left.transform.rotation_deg[2] * right.transform.rotation_deg[2] < 0  # mirrored diagonals: an X


def test_folded_tops_markings_have_their_own_colours() -> None:
    body = _colours("folded grey t-shirt", "body")
    assert _colours("folded grey t-shirt", "print").isdisjoint(body)
    assert _colours("folded football jersey", "number").isdisjoint(_colours("folded football jersey", "body"))
    assert _count("folded football jersey", "number") >= 3
    assert _colours("folded hospital gown", "dot").isdisjoint(_colours("folded hospital gown", "body"))
    assert _count("folded hospital gown", "dot") >= 10


def test_folded_jeans_details_stay_on_the_front() -> None:
    prog = _program("pair of blue jeans, folded")
    body = next(p for p in prog.parts if p.name == "body")
    half_w = body.primitive.size_m[1] / 2 if hasattr(body.primitive, "size_m") else None
    ext = _extent("pair of blue jeans, folded")
    if half_w is not None:  # the pocket scoops and stitching do not stick out past the sides
        assert ext[1] <= 2 * half_w * 1.05
    jeans = _colours("pair of blue jeans, folded", "body")
    assert _colours("pair of blue jeans, folded", "hem cuff").isdisjoint(jeans)
    assert _colours("pair of blue jeans, folded", "fly stitch").isdisjoint(jeans)


@pytest.mark.parametrize("text", ["silk blouse", "red flannel shirt"])
def test_flat_shirt_sleeves_end_above_the_hem(text: str) -> None:
    """The collar at +x: no sleeve reaches the hem's corners (sleeves beside the body down to the hem read as
    trouser legs), and the sleeves still spread wider than the body."""
    assert _design(text).concept.concept == "long_sleeve_shirt"
    for fx in (0.02, 0.1, 0.18):
        for fy in (0.04, 0.12, 0.88, 0.96):
            assert not _inside(text, (fx, fy, 0.5)), (fx, fy)
    assert _inside(text, (0.4, 0.2, 0.5)) and _inside(text, (0.4, 0.8, 0.5))


def test_bra_is_two_cups_between_wide_wings() -> None:
    ext = _extent("black bra")
    top = program_bounds(_program("black bra"))[1][2]
    assert ext[1] > 1.7 * ext[0] and top < 0.25 * ext[0]
    assert not _inside("black bra", (0.02, 0.02, 0.3))  # the straps loop, not a plate


def test_knee_brace_stands_open_with_the_kneecap_hole() -> None:
    ext = _extent("knee brace")
    assert ext[2] > 1.5 * max(ext[0], ext[1])
    assert not _inside("knee brace", (0.5, 0.5, 0.9)) and not _inside("knee brace", (0.5, 0.5, 0.1))
    assert _colours("knee brace", "patella ring").isdisjoint(_colours("knee brace", "upper sleeve"))


def test_neck_collar_is_a_short_thick_ring_with_a_velcro_back() -> None:
    ext = _extent("foam neck collar")
    assert ext[2] < 0.6 * min(ext[0], ext[1])
    assert not _inside("foam neck collar", (0.5, 0.5, 0.5))
    assert _colours("foam neck collar", "velcro strap").isdisjoint(_colours("foam neck collar", "band"))


def test_poncho_is_a_wide_panel_with_the_hood_on_top() -> None:
    ext = _extent("rain poncho")
    assert ext[2] < 0.1 * min(ext[0], ext[1])
    prog = _program("rain poncho")
    hood = next(p for p in prog.parts if p.name == "hood")
    assert hood.transform.translation_m[0] > 0.35 * ext[0]


def test_onesie_has_trimmed_sleeves_a_chest_heart_and_crotch_snaps() -> None:
    text = "baby onesie"
    assert _design(text).concept.concept == "baby_bodysuit"
    assert {"sleeve", "cuff trim", "leg trim", "neck trim", "heart", "snap", "crotch"} <= _groups(text)
    assert _colours(text, "heart").isdisjoint(_colours(text, "body"))
    assert _colours(text, "cuff trim").isdisjoint(_colours(text, "body"))
    assert not _inside(text, (0.97, 0.5, 0.5))  # the neck opening at the top edge's middle


def test_sleep_sack_is_a_sleeveless_sack_with_zip_and_a_starry_print() -> None:
    text = "baby sleeping bag"
    assert _design(text).concept.concept == "baby_sleep_sack"
    assert {"chest", "neck binding", "zip", "zip pull", "shoulder snap", "star", "moon"} <= _groups(text)
    assert _count(text, "star") >= 4
    assert _colours(text, "star").isdisjoint(_colours(text, "body"))


def test_arm_sling_is_an_open_trough_with_a_looped_strap_and_pad() -> None:
    text = "arm sling"
    assert _design(text).concept.concept == "arm_sling"
    assert {"pouch", "edge binding", "strap", "shoulder pad", "buckle", "d ring", "thumb loop"} <= _groups(text)
    assert not _inside(text, (0.6, 0.93, 0.7))  # the pouch is open on top (the forearm lies in it)
    ext = _extent(text)
    assert ext[2] < 0.3 * min(ext[0], ext[1])  # the strap lies in a wide loop beside it


def test_blood_pressure_cuff_is_wrapped_round_with_its_hose_and_plug() -> None:
    text = "a blood pressure cuff"
    assert _design(text).concept.concept == "blood_pressure_cuff"
    assert {"band", "wrapped flap", "fastener patch", "d ring", "index label", "artery arrow", "hose",
            "plug"} <= _groups(text)
    assert _colours(text, "artery arrow").isdisjoint(_colours(text, "band"))
