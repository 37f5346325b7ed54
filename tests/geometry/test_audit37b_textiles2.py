"""Session 37 audit, second round (textiles2): cloth goods blind judges could not name now carry the cues a person
names them by: a slipper (was an egg) is a sole under a closed toe with a foot opening and a fleece collar; a tomato
pincushion (read as a tomato) has coloured pin heads in it; a makeup brush (read as a paintbrush) has a domed
bristle head wider than its ferrule; a superhero cape (read as a kite) has a neck band wider than its top and drape
folds; a bathrobe has its crossing shawl collar, a tie belt with long hanging ends and two side pockets; a paper towel
roll (read as a rolled towel) stands tall on a brown cardboard core; a lab coat (read as a shirt) has lapels, a row of
buttons and three patch pockets; a terry wristband (read as a toilet roll) is a short ring with two coloured stripes
round it and rolled rims."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.shape import ShapeProgram
from tests.geometry.helpers import designs, parts_by_group as _groups

TEXTS = {"slipper": "a slipper", "pincushion": "a pincushion", "makeup_brush": "a makeup brush",
         "kids_cape": "a superhero cape", "bathrobe": "a bathrobe", "paper_towel_roll": "a paper towel roll",
         "lab_coat": "a lab coat", "wristband": "a sweatband"}


@pytest.fixture(scope="module")
def built() -> dict[str, tuple[str, ShapeProgram]]:
    return designs(TEXTS)




def _at(part) -> np.ndarray:  # noqa: ANN001
    return np.asarray(part.transform.translation_m)


def test_the_texts_build_their_entries(built: dict) -> None:
    assert {k: v[0] for k, v in built.items()} == {k: k for k in TEXTS}


def test_a_slipper_is_a_sole_under_a_closed_toe_with_a_foot_opening(built: dict) -> None:
    g = _groups(built["slipper"][1])
    assert {"sole", "upper", "foot opening", "foot cavity", "fleece collar"} <= set(g)
    assert g["sole"][0].color_rgb != g["upper"][0].color_rgb  # a darker sole
    assert g["fleece collar"][0].color_rgb != g["upper"][0].color_rgb
    assert _at(g["foot opening"][0])[0] < _at(g["upper"][0])[0]  # the opening at the heel, the toe closed
    sole = g["sole"][0].primitive.radii_m
    assert sole[0] > 2 * sole[1]  # long and narrow


def test_a_pincushion_is_a_segmented_tomato_stuck_with_coloured_pins(built: dict) -> None:
    g = _groups(built["pincushion"][1])
    assert len(g["groove"]) >= 8 and len(g["leaf"]) >= 4 and "stem" in g
    heads = g["pin head"]
    assert len(heads) >= 6 and len({p.color_rgb for p in heads}) >= 4
    assert all(p.color_rgb != g["body"][0].color_rgb for p in heads)


def test_a_makeup_brush_has_a_bristle_dome_wider_than_its_ferrule(built: dict) -> None:
    g = _groups(built["makeup_brush"][1])
    assert {"handle", "ferrule", "bristles"} <= set(g)
    assert g["bristles"][0].primitive.radii_m[1] > 1.8 * g["ferrule"][0].primitive.radius_m
    assert _at(g["bristles"][0])[0] > _at(g["ferrule"][0])[0] > _at(g["handle"][0])[0]
    assert len({g[k][0].color_rgb for k in ("handle", "ferrule", "bristles")}) == 3


def test_a_cape_has_a_neck_band_wider_than_its_top_and_drape_folds(built: dict) -> None:
    g = _groups(built["kids_cape"][1])
    assert len(g["fold"]) == 4 and "emblem" in g
    length = g["body"][0].primitive.size_m[0]  # the cape's length; its top is ~0.4 of it wide
    assert g["collar"][0].primitive.length_m > 0.6 * length  # a neck band past the cape's narrow top
    assert g["emblem"][0].color_rgb != g["body"][0].color_rgb


def test_a_bathrobe_has_a_shawl_collar_a_tie_belt_and_two_side_pockets(built: dict) -> None:
    g = _groups(built["bathrobe"][1])
    assert len(g["lapel"]) == 2 and len(g["pocket"]) == 2 and len(g["belt end"]) == 2 and "belt knot" in g
    ys = sorted(float(_at(p)[1]) for p in g["pocket"])
    assert ys[0] < 0 < ys[1]
    assert min(float(_at(p)[0]) for p in g["pocket"]) < _at(g["belt"][0])[0]  # below the waist


def test_a_paper_towel_roll_stands_tall_on_a_cardboard_core(built: dict) -> None:
    g = _groups(built["paper_towel_roll"][1])
    roll, core = g["roll"][0].primitive, g["core"][0].primitive
    assert roll.height_m > 2 * roll.radius_m  # taller than wide, standing
    assert core.radius_m < 0.5 * roll.radius_m and g["core"][0].color_rgb != g["roll"][0].color_rgb
    assert "core bore" in g  # a hole down its middle


def test_a_lab_coat_has_lapels_buttons_and_patch_pockets(built: dict) -> None:
    g = _groups(built["lab_coat"][1])
    assert len(g["lapel"]) == 2 and len(g["button"]) == 4 and len(g["pocket"]) == 2 and "breast pocket" in g
    xs = [float(_at(p)[0]) for p in g["button"]]
    assert max(xs) - min(xs) > 0.2  # a row down the front of a ~1 m coat [m]
    assert all(abs(float(_at(p)[1])) < 0.01 for p in g["button"])  # on the centre line


def test_a_wristband_is_a_short_striped_ring(built: dict) -> None:
    g = _groups(built["wristband"][1])
    stripes = g["stripe"]
    assert len(stripes) == 2 and all(p.color_rgb != g["middle"][0].color_rgb for p in stripes)
    assert "bore" in g and len(g["rim"]) == 2
    outer = g["middle"][0].primitive.radius_m
    assert g["bore"][0].primitive.radius_m > 0.6 * outer  # a band, not a roll
