"""Session 37 audit, group food_a: fruit, vegetables and round foods the blind judges could not name from a round
blob (round_fruit/egg/pear/disc/cone/ring plans) are hand-written shapes (tasks/geometry/shapes/audit37_food_a.yaml)
with the cues a person names them by: a pineapple's crown and eyes, a pomegranate's crown, an onion's neck and root
tuft, a garlic bulb's cloves, a cut face where the food is usually seen cut, candy corn's three bands."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.lexicon import load_lexicon
from tasks.geometry import catalogue
from tasks.geometry.catalogue_programs import catalogue_program
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds
from tests.geometry.helpers import parts_by_group as _groups

CHANGED = ("onion", "garlic", "pineapple", "pomegranate", "beet", "apricot", "raspberry", "melon", "grapefruit",
           "papaya", "passion_fruit", "cabbage", "candy_corn", "rice_ball", "sponge_cake", "burger_patty",
           "bundt_cake", "maki", "dragon_fruit", "acorn_squash", "artichoke", "chicken_nugget", "star_fruit", "kiwano",
           "coconut_flesh", "scotch_egg", "quail_egg", "temaki", "mooncake", "physalis", "mangosteen",
           "beefsteak_tomato", "angel_food_cake", "shumai", "pattypan", "tortellini", "scallop", "prune", "fennel",
           "gooseberry", "habanero")
REUSED = {"rambutan": "kiwano", "radicchio": "cabbage", "pearl_onion": "onion", "arancini": "scotch_egg",
          "tomatillo": "physalis", "kohlrabi": "beet", "uramaki": "maki"}  # another entry's shape, recoloured


@pytest.fixture(scope="module")
def programs() -> dict:
    return {k: catalogue_program(k) for k in CHANGED}




def _rgb(part) -> np.ndarray:  # noqa: ANN001
    return np.asarray(part.color_rgb)


def test_lexicon_entries_name_their_hand_written_shapes() -> None:
    lex = load_lexicon().entries
    for key in CHANGED:
        assert lex[key].catalogue == key and lex[key].plan is None, key
        assert lex[key].density_kg_per_m3 is not None, key  # density follows the drawn volume
    for key, shape in REUSED.items():
        assert lex[key].catalogue == shape and lex[key].colors, key


def test_reused_shapes_take_their_own_colours() -> None:
    from tasks.geometry.concepts import concept_program

    radicchio = {part_group(p.name): p.color_rgb for p in concept_program("radicchio").parts}
    cabbage = {part_group(p.name): p.color_rgb for p in concept_program("cabbage").parts}
    assert radicchio["head"][0] > radicchio["head"][1] and cabbage["head"][1] > cabbage["head"][0]  # red vs green
    husk = {part_group(p.name): p.color_rgb for p in concept_program("tomatillo").parts}
    assert husk["berry"][1] > husk["berry"][2]  # a green berry in its husk, not physalis' orange


@pytest.mark.parametrize(("text", "entry"), [
    ("a red onion", "onion"), ("a bulb of garlic", "garlic"), ("a ripe pineapple", "pineapple"),
    ("a pomegranate", "pomegranate"), ("a cantaloupe", "melon"), ("a pink grapefruit", "grapefruit"),
    ("a handful of candy corn", "candy_corn"), ("an onigiri", "rice_ball"), ("a jackfruit", "coconut_flesh"),
])
def test_nouns_still_find_their_entries(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_pineapple_has_a_tall_crown_of_leaves_over_a_body_of_eyes(programs: dict) -> None:
    g = _groups(programs["pineapple"])
    assert len(g["eye"]) >= 30 and len(g["leaf"]) >= 10
    body_top = max(p.transform.translation_m[2] for p in g["eye"])
    assert max(p.transform.translation_m[2] for p in g["leaf"]) > body_top * 1.2
    assert _rgb(g["leaf"][0])[1] > _rgb(g["leaf"][0])[0]  # green crown on a golden body


def test_pomegranate_onion_and_garlic_have_their_tops(programs: dict) -> None:
    pom = _groups(programs["pomegranate"])
    assert len(pom["sepal"]) == 6 and "crown cup" in pom
    onion = _groups(programs["onion"])
    assert {"neck", "root", "skin line"} <= set(onion) and len(onion["root"]) >= 5
    garlic = _groups(programs["garlic"])
    assert len(garlic["clove"]) >= 6 and "neck" in garlic


@pytest.mark.parametrize(("key", "face"), [
    ("grapefruit", "flesh"), ("passion_fruit", "pulp"), ("papaya", "seed cavity"), ("melon", "wedge"),
    ("scotch_egg", "yolk"), ("sponge_cake", "cut"),
])
def test_foods_usually_seen_cut_show_a_cut_face(programs: dict, key: str, face: str) -> None:
    names = [part_group(p.name) for p in programs[key].parts]
    assert face in names
    assert any(p.operation == "subtract" for p in programs[key].parts)


def test_candy_corn_has_three_bands_white_at_the_tip(programs: dict) -> None:
    parts = {p.name: p for p in programs["candy_corn"].parts}
    zs = [parts[n].transform.translation_m[2] for n in ("base", "middle", "tip")]
    assert zs == sorted(zs)
    assert _rgb(parts["tip"]).min() > 0.9 and _rgb(parts["middle"])[2] < 0.2  # white tip, orange middle


def test_spiky_and_scaly_fruit(programs: dict) -> None:
    assert len(_groups(programs["kiwano"])["spike"]) >= 25
    assert len(_groups(programs["coconut_flesh"])["spike"]) >= 25
    dragon = _groups(programs["dragon_fruit"])
    assert len(dragon["scale"]) >= 12 and _rgb(dragon["green"][0])[1] > _rgb(dragon["green"][0])[0]
    assert len(_groups(programs["raspberry"])["drupelet"]) >= 40


def test_star_fruit_is_long_with_five_ribs(programs: dict) -> None:
    g = _groups(programs["star_fruit"])
    assert len(g["rib"]) == 5
    lo, hi = program_bounds(programs["star_fruit"])
    ext = hi - lo
    assert ext[0] > 1.3 * ext[1]


def test_acorn_squash_is_ribbed_and_pointed_below(programs: dict) -> None:
    g = _groups(programs["acorn_squash"])
    assert len(g["rib"]) >= 8 and "tip" in g and "stem" in g
    assert np.asarray(g["rib"][0].color_rgb).max() < 0.3  # dark green


def test_rice_ball_is_a_triangle_with_a_nori_band(programs: dict) -> None:
    g = _groups(programs["rice_ball"])
    assert len(g["side"]) == 2 and "nori" in g
    assert _rgb(g["nori"][0]).max() < 0.1


def test_maki_and_temaki_have_rice_and_filling_in_nori(programs: dict) -> None:
    for key in ("maki", "temaki"):
        names = {part_group(p.name) for p in programs[key].parts}
        assert {"rice"} <= names and ("nori" in names or "nori cone" in names)


def test_mangosteen_and_tomato_have_green_calyxes(programs: dict) -> None:
    for key, n in (("mangosteen", 4), ("beefsteak_tomato", 6)):
        g = _groups(programs[key])
        assert len(g["sepal"]) == n and _rgb(g["sepal"][0])[1] > _rgb(g["sepal"][0])[0]
    assert len(_groups(programs["beefsteak_tomato"])["lobe"]) >= 6


def test_small_cues_of_scallop_prune_fennel_and_gooseberry(programs: dict) -> None:
    scallop = {p.name: p for p in programs["scallop"].parts}
    assert _rgb(scallop["seared top"]).sum() < 0.75 * _rgb(scallop["meat"]).sum()  # a browned face on pale meat
    assert sum(p.operation == "subtract" for p in programs["prune"].parts) >= 5  # wrinkles
    fennel = _groups(programs["fennel"])
    assert len(fennel["stalk"]) >= 3 and len(fennel["frond"]) >= 9 and _rgb(fennel["bulb"][0]).min() > 0.8
    assert len(_groups(programs["gooseberry"])["vein"]) >= 5


def test_patty_has_grill_marks_and_cakes_their_layers(programs: dict) -> None:
    assert len(_groups(programs["burger_patty"])["grill mark"]) >= 4
    cake = {p.name for p in programs["sponge_cake"].parts}
    assert {"bottom layer", "jam", "cream", "top layer"} <= cake
    bundt = _groups(programs["bundt_cake"])
    assert len(bundt["flute"]) >= 12 and "icing" in bundt
    angel = {p.name: p for p in programs["angel_food_cake"].parts}
    assert angel["tube"].operation == "subtract" and angel["slice cut"].operation == "subtract"
