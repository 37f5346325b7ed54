"""Session 37 audit (second round), animals2: figures and food-shaped plush blind judges could not name from their
plans (a plush avocado read as a pear, a sock monkey as a teddy bear, a Santa and a robot as plain dolls, a moon as a
squash, a cloud as bread dough, a plush egg as a bean bag, plush sushi as a sponge) are drawn by hand with the parts
people name them by; a roast chicken and turkey are brown, not pink (read as a seal; a whole raw chicken is drawn raw, session 42), a plush croissant has its
rolled ridges."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.shape import ShapeProgram
from tasks.geometry.grammar.parts import part_group
from tests.geometry.helpers import designs

TEXTS = {"avocado": "a plush avocado", "monkey": "a sock monkey", "santa": "a santa", "robot": "a plush robot",
         "moon": "a crescent moon", "cloud": "a cloud", "egg": "a plush egg", "sushi": "a plush sushi",
         "puppet": "a hand puppet", "chicken": "a roast chicken", "turkey": "a whole turkey",
         "croissant": "a plush croissant", "gummy snake": "a gummy snake",
         "sperm whale": "a sperm whale", "grey whale": "a grey whale",
         "yeti": "a yeti"}
ENTRIES = {"avocado": "plush_avocado", "monkey": "sock_monkey", "santa": "plush_santa", "robot": "plush_robot",
           "moon": "plush_moon", "cloud": "plush_cloud", "egg": "plush_egg", "sushi": "plush_sushi",
           "puppet": "hand_puppet", "chicken": "roast_chicken", "turkey": "whole_turkey",
           "croissant": "plush_croissant", "gummy snake": "gummy_snake",
           "sperm whale": "plush_sperm_whale", "grey whale": "plush_baleen_whale",
           "yeti": "plush_yeti"}


@pytest.fixture(scope="module")
def built() -> dict[str, tuple[str, ShapeProgram]]:
    return designs(TEXTS)


def _parts(program: ShapeProgram) -> dict[str, object]:
    return {p.name: p for p in program.parts}


def _groups(program: ShapeProgram) -> set[str]:
    return {part_group(p.name) for p in program.parts}


def _at(part) -> np.ndarray:  # noqa: ANN001
    return np.asarray(part.transform.translation_m)


def _dark(rgb) -> bool:  # noqa: ANN001
    return max(rgb) < 0.1


def _red(rgb) -> bool:  # noqa: ANN001
    return rgb[0] > 0.7 and rgb[1] < 0.2 and rgb[2] < 0.2


def _white(rgb) -> bool:  # noqa: ANN001
    return min(rgb) > 0.85


def test_the_texts_build_their_entries(built: dict) -> None:
    assert {k: v[0] for k, v in built.items()} == ENTRIES


def test_a_plush_avocado_is_a_dark_skinned_half_with_pale_flesh_and_a_brown_pit_in_front(built: dict) -> None:
    p = _parts(built["avocado"][1])
    skin, flesh, pit = p["skin lower"], p["flesh lower"], p["pit"]
    assert max(skin.color_rgb) < 0.35 and flesh.color_rgb[0] > 0.8  # dark green skin, pale yellow-green flesh
    assert pit.color_rgb[0] > pit.color_rgb[1] > pit.color_rgb[2]  # brown
    assert _at(pit)[0] > _at(flesh)[0] > _at(skin)[0]  # the pit stands proud of the cut face
    assert p["skin upper"].primitive.radii_m[1] < skin.primitive.radii_m[1]  # a narrower neck


def test_a_sock_monkey_has_a_white_muzzle_red_lips_and_heel_and_white_hands_and_feet(built: dict) -> None:
    p = _parts(built["monkey"][1])
    assert _white(p["muzzle"].color_rgb) and _red(p["lips"].color_rgb) and _red(p["heel seat"].color_rgb)
    assert all(_white(p[f"{s} {limb}"].color_rgb) for s in ("left", "right") for limb in ("hand", "foot"))
    assert _at(p["lips"])[0] > _at(p["muzzle"])[0] > _at(p["head"])[0]  # the mouth in front of the face
    assert p["body"].color_rgb != p["muzzle"].color_rgb and "tail" in _groups(built["monkey"][1])


def test_a_santa_has_a_red_suit_white_beard_and_trim_black_belt_and_boots_and_a_red_hat(built: dict) -> None:
    p = _parts(built["santa"][1])
    assert _red(p["coat"].color_rgb) and _red(p["hat"].color_rgb)
    assert all(_white(p[n].color_rgb) for n in ("beard", "hat brim", "hat pompom", "coat hem"))
    assert all(_dark(p[n].color_rgb) for n in ("belt", "left boot", "right boot"))
    assert _at(p["beard"])[0] > _at(p["head"])[0] and _at(p["hat pompom"])[2] > _at(p["head"])[2]


def test_a_robot_is_boxy_with_an_antenna_round_eyes_and_a_chest_panel(built: dict) -> None:
    p = _parts(built["robot"][1])
    assert p["head"].primitive.kind == "rounded_box" and p["body"].primitive.kind == "rounded_box"
    top = max(_at(q)[2] for q in p.values())
    assert _at(p["antenna ball"])[2] == top
    assert p["left eye"].color_rgb != p["head"].color_rgb and _at(p["chest panel"])[0] > _at(p["body"])[0]
    assert len({tuple(p[f"button {c}"].color_rgb) for c in ("red", "yellow", "green")}) == 3


def test_a_moon_is_a_crescent_standing_with_a_sleepy_face(built: dict) -> None:
    prog = built["moon"][1]
    p = _parts(prog)
    assert p["bite"].operation == "subtract"  # the crescent is a disc with a disc cut away
    assert np.linalg.norm(_at(p["bite"]) - _at(p["body"])) < p["body"].primitive.radius_m
    assert _at(p["bite"])[2] > _at(p["body"])[2]  # the horns point up; it rests on its back
    assert {"eye", "cheek"} <= _groups(prog)


def test_a_cloud_is_puffs_on_a_flat_base_and_a_fried_egg_a_yolk_on_a_flat_white(built: dict) -> None:
    cloud = _parts(built["cloud"][1])
    puffs = [q for n, q in cloud.items() if n.startswith("puff")]
    assert len(puffs) >= 5 and all(_white(q.color_rgb) for q in puffs)
    assert np.ptp([_at(q)[1] for q in puffs]) > 2 * cloud["base"].primitive.radii_m[0]  # wider than deep
    egg = _parts(built["egg"][1])
    assert egg["yolk"].color_rgb[0] > 0.9 and egg["yolk"].color_rgb[2] < 0.2 and _white(egg["white"].color_rgb)
    assert egg["white"].primitive.radii_m[0] > 3 * egg["white"].primitive.radii_m[2]  # flat


def test_plush_sushi_is_a_salmon_slice_with_fat_stripes_on_white_rice(built: dict) -> None:
    p = _parts(built["sushi"][1])
    assert _white(p["rice"].color_rgb) and p["fish"].color_rgb[0] > 0.9 and p["fish"].color_rgb[2] < 0.4
    assert _at(p["fish"])[2] > _at(p["rice"])[2]
    assert sum(n.startswith("fat stripe") for n in p) >= 4


def test_a_hand_puppet_is_a_head_on_a_flared_gown_with_no_legs(built: dict) -> None:
    prog = built["puppet"][1]
    p = _parts(prog)
    assert p["gown"].primitive.radius_bottom_m > p["gown"].primitive.radius_top_m
    assert "leg" not in _groups(prog) and _at(p["head"])[2] > _at(p["gown"])[2]


def test_roast_birds_are_brown_and_a_plush_croissant_has_ridges(built: dict) -> None:
    for k in ("chicken", "turkey"):
        body = next(q for q in built[k][1].parts if q.name == "body")
        assert body.color_rgb[0] > body.color_rgb[1] > body.color_rgb[2] + 0.15  # golden brown, not pink
    assert "crease" in _groups(built["croissant"][1])


def test_a_gummy_snake_is_two_tone_in_bands(built: dict) -> None:
    prog = built["gummy snake"][1]
    bands = [p for p in prog.parts if part_group(p.name) == "band"]
    others = [p for p in prog.parts if part_group(p.name) == "segment"]
    assert len(bands) >= 4 and others and bands[0].color_rgb != others[0].color_rgb


def test_a_sperm_whale_has_a_huge_boxy_head_and_other_whales_keep_their_plan(built: dict) -> None:
    p = _parts(built["sperm whale"][1])
    head, body = p["head"], p["body"]
    assert head.primitive.kind == "superellipsoid" and head.primitive.exponent_ns < 0.5  # square-fronted
    assert head.primitive.radii_m[0] >= body.primitive.radii_m[0] and _at(head)[0] > _at(body)[0]
    assert "fluke" in _groups(built["sperm whale"][1])
    assert "head" not in _parts(built["grey whale"][1])  # a grey whale keeps its plan, not the sperm whale's head


def test_a_yeti_is_white_and_shaggy_with_a_blue_face_hands_and_feet_and_horns(built: dict) -> None:
    prog = built["yeti"][1]
    p = _parts(prog)
    assert _white(p["body"].color_rgb) and _white(p["head"].color_rgb)
    blue = p["face"].color_rgb
    assert blue[2] > blue[0] + 0.3 and all(p[n].color_rgb == blue for n in ("left hand", "right foot"))
    assert _at(p["face"])[0] > _at(p["head"])[0] and {"horn", "tuft"} <= _groups(prog)
