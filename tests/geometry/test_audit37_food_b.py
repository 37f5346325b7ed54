"""Session 37's food audit (group food_b: breads, pastries, cheeses, meats, sweets): the lexicon's own objects that
blind judges could not name, given the cues a person names them by (a croissant's ridged crescent, a loaf's scored
crust and pale cut crumb, a burger's stacked layers, bacon's fat stripes, a cheese block's
holes, a burrito's foil and filled cut end). Each object is designed once (programs only: no meshing)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _parts(text: str, group: str) -> list:
    return [p for p in _design(text).program.parts if part_group(p.name) == group or p.name.startswith(group)]


def _lum(rgb) -> float:  # noqa: ANN001
    r, g, b = rgb
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


@pytest.mark.parametrize(("text", "entry"), [
    ("a mini croissant", "croissant_mini"), ("a rye bread", "loaf_rye"),
    ("a cheeseburger", "sandwich"), ("a waffle", "waffle"), ("a strip of bacon", "bacon_strip"),
    ("a t bone steak", "steak"), ("a corn cob", "corn"), ("a gyoza", "dumpling"), ("a jelly donut", "donut_filled"),
    ("an eclair", "eclair"), ("a block of cheddar", "cheese_block"), ("a slice of cake", "cake_slice"),
    ("a burrito", "burrito"), ("a slice of ham", "ham_slice"), ("a salami slice", "salami_slice"),
    ("a pork chop", "pork_chop"), ("an empanada", "empanada"), ("a cornish pasty", "pasty"), ("a calzone", "calzone"),
    ("a challah", "challah"), ("a soda bread", "soda_bread"), ("a focaccia", "focaccia"),
    ("a poached egg", "poached_egg"), ("cotton candy", "candy_floss"), ("an uncut maki roll", "maki_roll"),
    ("a crab stick", "crab_stick"), ("asparagus", "asparagus"), ("a parmesan wedge", "parmesan"),
    ("a pain au chocolat", "pain_au_chocolat"), ("a saltwater taffy", "taffy"), ("a beignet", "beignet"),
    ("a xiaolongbao", "xiaolongbao"), ("a momo", "momo"), ("okra", "okra"), ("a grilled cheese sandwich", "grilled_cheese"),
    ("a piece of ginger root", "ginger_root"), ("a stollen", "stollen"), ("a babka", "babka"),
    ("a piece of lasagna", "lasagna_portion"), ("a weisswurst", "weisswurst"), ("a liverwurst", "liverwurst"),
    ("a merguez", "merguez"), ("a cannoli", "cannoli"),
])
def test_the_audited_foods_build_their_own_entry(text: str, entry: str) -> None:
    assert _design(text).entry == entry


def test_a_croissant_is_a_ridged_crescent_with_pointed_horns() -> None:
    parts = _design("a mini croissant").program.parts
    bands = [p for p in parts if p.name == "body" or p.name.startswith("segment")]
    creases = [p for p in parts if p.name.startswith("crease")]
    horns = [p for p in parts if p.name.endswith("horn")]
    assert len(bands) == 7 and len(creases) == 6 and len(horns) == 2
    body = next(p for p in parts if p.name == "body")
    # a crescent: the middle band stands out from the line joining the horns, and is the fattest
    mid_x = body.transform.translation_m[0]
    horn_x = np.mean([h.transform.translation_m[0] for h in horns])
    assert mid_x - horn_x > 0.5 * body.primitive.radii_m[2]
    assert body.primitive.radii_m[2] == max(b.primitive.radii_m[2] for b in bands)
    assert _lum(creases[0].color_rgb) > _lum(body.color_rgb)  # paler pastry in the creases


def test_a_rye_loaf_has_scores_and_a_pale_cut_crumb() -> None:
    parts = _design("a rye bread").program.parts
    assert sum(p.operation == "subtract" and p.name.startswith("score") for p in parts) == 3
    crust = next(p for p in parts if p.name == "crust")
    crumb = next(p for p in parts if p.name == "crumb")
    assert _lum(crumb.color_rgb) > 1.5 * _lum(crust.color_rgb)
    assert any(p.name == "cut" and p.operation == "subtract" for p in parts)


def test_a_burger_stacks_bun_patty_cheese_lettuce_tomato_bun() -> None:
    parts = {p.name: p for p in _design("a hamburger").program.parts}
    order = ["body", "patty", "cheese", "lettuce", "tomato", "top bun"]
    z = [parts[n].transform.translation_m[2] for n in order]
    assert z == sorted(z)
    assert _lum(parts["patty"].color_rgb) < 0.5 * _lum(parts["body"].color_rgb)
    assert parts["lettuce"].color_rgb[1] > parts["lettuce"].color_rgb[0]
    assert sum(n.startswith("seed") for n in parts) >= 8


def test_bacon_is_a_wavy_strip_of_meat_and_fat_bands() -> None:
    parts = _design("a rasher of bacon").program.parts
    fat = [p for p in parts if p.name.startswith("fat")]
    meat = [p for p in parts if p.name.startswith("meat") or p.name == "body"]
    assert fat and meat and _lum(fat[0].color_rgb) > 3 * _lum(meat[0].color_rgb)
    zs = [p.transform.translation_m[2] for p in meat]
    assert max(zs) - min(zs) > 0.1 * max(abs(p.transform.translation_m[0]) for p in meat)  # waves, not flat


def test_a_cheese_is_a_yellow_block_with_holes() -> None:
    parts = _design("a cheese").program.parts
    assert sum(p.name.startswith("hole") and p.operation == "subtract" for p in parts) >= 8
    assert parts[0].color_rgb[0] > 2 * parts[0].color_rgb[2]


def test_corn_has_kernel_rows_and_green_husks() -> None:
    kernels = _parts("a corn on the cob", "kernel")
    husks = _parts("a corn on the cob", "husk")
    assert len(kernels) >= 40 and len(husks) == 3
    assert all(h.color_rgb[1] > h.color_rgb[0] for h in husks)


def test_a_burrito_is_half_in_foil_with_a_filled_cut_end() -> None:
    parts = {p.name: p for p in _design("a burrito").program.parts}
    assert parts["cut"].operation == "subtract" and "foil" in parts
    fillings = [p for n, p in parts.items() if n.startswith("filling")]
    assert len({tuple(p.color_rgb) for p in fillings}) >= 4  # beans, lettuce, tomato, meat, cheese
    assert parts["foil"].transform.translation_m[0] < 0 < parts["rice"].transform.translation_m[0]


def test_meats_and_cheeses_show_fat_bone_and_rind() -> None:
    steak = {part_group(p.name) for p in _design("a steak").program.parts}
    assert {"bone", "fat rim"} <= steak
    salami = _parts("a salami slice", "fat")
    assert len(salami) >= 10
    parm = {p.name: p for p in _design("a parmesan").program.parts}
    assert _lum(parm["rind"].color_rgb) < 0.7 * _lum(parm["body"].color_rgb)


def test_a_challah_is_plaited_and_dumplings_are_pleated() -> None:
    assert len(_parts("a challah", "lobe")) >= 14
    assert len(_parts("a xiaolongbao", "pleat")) >= 10
    assert len(_parts("a gyoza", "pleat")) >= 5


def test_sausages_have_tied_ends_and_lasagna_rippled_sheets() -> None:
    for text in ("a weisswurst", "a liverwurst", "a merguez"):
        ties = [p for p in _design(text).program.parts if part_group(p.name) in ("tie", "tie end")]
        assert len(ties) == 4, text
    chub = next(p for p in _design("a liverwurst").program.parts if part_group(p.name) == "tie")
    body = next(p for p in _design("a liverwurst").program.parts if p.name == "body")
    assert not np.allclose(chub.color_rgb, body.color_rgb, atol=0.05)  # a metal clip
    assert len(_parts("a lasagna", "ruffle")) >= 28
