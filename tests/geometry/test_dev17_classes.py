"""Development set 17 and sealed set 16's misses (#35, session 31): what reviewers who never saw the lexicon asked
for and L0 built wrong, fixed by class and tested here with other phrasings than the sets' (the set itself:
docs/blind/dev17/)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from contracts.request import AssetRequest
from tasks.geometry import catalogue, grammar, pipeline
from tasks.geometry.grammar.goods import PouchParams, SheetParams, pouch, sheet
from tasks.render.finish import finish_for, shade_pixels
from tasks.render.views import telling_views
from tests.geometry.test_mass_classes import planned_mass


def _built(text: str):  # noqa: ANN202
    arrays, info = pipeline.mesh_from_text(AssetRequest(text=text), pipeline.settings_from_contract("draft"))
    return pipeline.arrays_to_mesh(arrays), info


def test_a_towel_folded_then_rolled_is_a_roll_a_third_as_long_of_the_same_mass() -> None:
    """'a bath towel folded in thirds and rolled up' was built folded (the first state said won): it is rolled, the
    roll as long as the folded strip is wide, the towel's mass kept."""
    design = catalogue.design_from_text("a beach towel folded in thirds and rolled up")
    plain = catalogue.design_from_text("a beach towel rolled up")
    assert design.program.parts[0].name == plain.program.parts[0].name  # the same roll plan
    lo, hi = grammar.program_extents(design.program, 48), grammar.program_extents(plain.program, 48)
    assert lo[0] == pytest.approx(hi[0] / 3, rel=0.15)  # the roll along x: a third of the plain roll's length
    assert planned_mass("a beach towel folded in thirds and rolled up") == pytest.approx(
        planned_mass("a beach towel rolled up"), rel=0.15)


def test_a_stack_of_bread_slices_keeps_each_slices_outline_and_crust() -> None:
    """Three slices of sandwich bread were three rounded rectangles (read as washcloths): each keeps its rounded
    top and its crust."""
    p = SheetParams(width=0.92, thickness=0.1, shape="bread", state="stacked", layers=3)
    parts = sheet(p)
    assert sum(q.name.split()[0] == "crust" for q in parts if "joint" not in q.name) >= 3  # a crust per slice
    assert len(parts) <= 64
    z = [q.transform.translation_m[2] for q in parts if q.name.startswith("body")]
    assert len(z) == 3 and z[0] < z[1] < z[2]  # stacked
    assert 0.07 <= planned_mass("a stack of three slices of white bread") <= 0.13  # 3 x 25-29 g


@pytest.mark.parametrize("text", ["a silk scarf draped over a bar", "a tea towel hanging over the oven door"])
def test_a_cloth_draped_over_a_bar_hangs_in_two_panels(text: str) -> None:
    """'a 90 cm square silk scarf, loosely draped over a bar' was a flat folded rectangle: the cloth hangs over a
    bar at its middle, two panels falling from the fold; standing about half its length high."""
    design = catalogue.design_from_text(text)
    assert any(p.name.startswith("left panel") for p in design.program.parts)
    assert any(p.name.startswith("right panel") for p in design.program.parts)
    ext = grammar.program_extents(design.program, 64)
    assert ext[2] > 2 * ext[0] * 0.5 and ext[2] > 0.25 * ext.max()  # it stands, its panels splayed a little


def test_a_draped_sheets_stated_size_is_the_flat_sheets() -> None:
    """'a 90 cm square scarf draped over a bar': 90 cm along the bar, about 45 cm high; 'square' makes a long
    scarf as wide as long."""
    mesh, info = _built("a 90 cm square silk scarf draped over a bar")
    assert info.entry == "silk_scarf"
    ext = np.sort(mesh.extents)[::-1]
    assert ext[0] == pytest.approx(0.9, rel=0.05) and 0.33 <= ext[1] <= 0.5


def test_a_towel_hanging_on_a_rail_is_draped_not_a_garment_on_a_hanger() -> None:
    design = catalogue.design_from_text("a bath towel hanging on a towel rail")
    assert any(p.name.startswith("left panel") for p in design.program.parts)
    assert not any("hanger" in p.name for p in design.program.parts)


@pytest.mark.parametrize("text", ["a 200 g bag of potato chips", "a 1 kg bag of long grain rice",
                                  "a 5 kg bag of cat litter"])
def test_a_bag_of_goods_is_a_pillow_pack_with_crimped_ends(text: str) -> None:
    """Seven 'bag of X' prompts of dev set 17 were one pillow with a label: a pillow pack's two ends are flat
    heat-sealed fins with crimp ridges, the body gathering into them."""
    design = catalogue.design_from_text(text)
    names = [p.name for p in design.program.parts]
    assert "left end seal" in names and "right end seal" in names
    assert sum("crimp" in n for n in names) >= 6


def test_a_pillow_packs_fins_are_thin_and_its_body_full() -> None:
    parts = {p.name: p for p in pouch(PouchParams(fill=0.8, width=0.65, crimp=True, label=True))}
    fin = parts["left end seal"].primitive.size_m  # (x, y, z) of the box
    body = parts["body"].primitive.radii_m
    assert fin[2] < 0.25 * 2 * body[2] and fin[1] == pytest.approx(0.65)  # as wide as the bag, far thinner
    assert parts["left end seal"].transform.translation_m[0] < -0.4 < 0.4 < parts["right end seal"].transform.translation_m[0]


@pytest.mark.parametrize("text, entry, lo, hi", [
    ("a red nylon dog leash, coiled", "dog_leash", 0.06, 0.24), ("a metre of satin ribbon", "ribbon", 0.003, 0.012),
    ("a folded plastic tarp", "tarp", 0.4, 1.5), ("a cotton sweatband for the wrist", "wristband", 0.009, 0.036),
    ("a crochet granny square", "granny_square", 0.01, 0.04),
    ("an interlocking foam puzzle mat", "foam_floor_tile", 0.04, 0.18)])
def test_dev17_objects_that_were_generic_have_an_entry_and_their_mass(text: str, entry: str, lo: float,
                                                                      hi: float) -> None:
    """A coiled dog leash was a generic red block, a metre of ribbon a strip of 16 times its mass, a folded tarp a
    garment, a terry wristband a scrunchie, a foam puzzle mat tile a sponge."""
    assert catalogue.design_from_text(text).entry == entry
    assert lo <= planned_mass(text) <= hi


def test_a_foam_puzzle_tile_has_tabs_on_two_sides_and_sockets_on_the_others() -> None:
    parts = sheet(SheetParams(width=1.0, thickness=0.04, shape="puzzle"))
    tabs = [p for p in parts if p.name.startswith("tab")]
    sockets = [p for p in parts if p.name.startswith("socket")]
    assert len(tabs) == len(sockets) == 8 and all(p.operation == "subtract" for p in sockets)
    assert all(max(p.transform.translation_m[:2]) > 0.4 for p in tabs)  # on the +x and +y sides
    assert all(min(p.transform.translation_m[:2]) < -0.3 for p in sockets)


def test_a_known_two_word_noun_before_of_is_no_portion() -> None:
    """'a folded fat quarter of floral cotton fabric' read 'quarter of' as a portion of fabric and 'fat' as a
    modifier: a 0.7 kg fabric piece, 19 times a fat quarter's mass."""
    assert catalogue.design_from_text("a folded fat quarter of floral cotton fabric").entry == "fat_quarter"
    assert planned_mass("a folded fat quarter of floral cotton fabric") < 0.1
    assert catalogue.design_from_text("a slice of swiss cheese").entry == "swiss_cheese_slice"  # a portion still


def test_a_parts_material_is_not_the_objects() -> None:
    """'an adult blood pressure cuff with its rubber tube' was a solid rubber cuff of 1 kg (9 times its mass)."""
    assert planned_mass("an adult blood pressure cuff with its rubber tube") == pytest.approx(
        planned_mass("an adult blood pressure cuff"), rel=0.1)


@pytest.mark.parametrize("extents, views", [
    ((0.5, 0.7, 0.03), ("iso", "top", "front")), ((0.12, 0.11, 0.012), ("iso", "top", "front")),
    ((0.3, 0.1, 0.1), ("iso", "front", "side")), ((0.2, 0.2, 0.3), ("iso", "front", "side"))])
def test_a_flat_object_is_judged_from_above(extents: tuple[float, float, float], views: tuple[str, ...]) -> None:
    """A T-shirt laid flat seen edge-on from the front and the side is two lines: the judge's third picture of a
    flat object is from above."""
    assert telling_views(np.array(extents)) == views


def test_a_pair_of_rolls_lies_side_by_side_both_ends_seen() -> None:
    """'a pair of rolled boxing hand wraps' was one roll (a roll's core is a cut, and a pair refused cuts): two rolls
    side by side, not end to end (read as one long roll)."""
    design = catalogue.design_from_text("a pair of rolled boxing hand wraps")
    one = catalogue.design_from_text("a rolled boxing hand wrap")
    assert len(design.program.parts) == 2 * len(one.program.parts)
    two, single = grammar.program_extents(design.program, 48), grammar.program_extents(one.program, 48)
    assert two[0] == pytest.approx(single[0], rel=0.1) and two[1] > 1.8 * single[1]  # across the rolls' axis (x)


def test_a_cinnamon_roll_shows_its_spiral_on_top() -> None:
    """A cinnamon roll was a plain caramel disc (read as a cheese wheel): the rolled dough's spiral runs over its
    top, darker."""
    parts = catalogue.design_from_text("a cinnamon roll").program.parts
    swirl = [p for p in parts if p.name.startswith("swirl")]
    assert len(swirl) > 10 and swirl[0].color_rgb != parts[0].color_rgb
    radii = [float(np.hypot(*p.transform.translation_m[:2])) for p in swirl]
    assert max(radii) > 3 * min(radii)  # from the centre out


def test_a_half_deflated_balls_dent_is_off_its_top() -> None:
    """A half-deflated playground ball's dent sat on its top, centred: read as an apple's stalk cavity."""
    parts = catalogue.design_from_text("a half-deflated rubber playground ball").program.parts
    dent = next(p for p in parts if p.name == "dent")
    body = grammar.program_extents(catalogue.design_from_text("a half-deflated rubber playground ball").program, 48)
    assert dent.operation == "subtract" and abs(dent.transform.translation_m[0]) > 0.15 * body[0]


def test_dusted_food_is_powdered_white_on_top_only() -> None:
    """'a jelly doughnut dusted with sugar' read as a bread roll: the powder whitens what faces up."""
    match = catalogue.design_from_text("a jelly doughnut dusted with icing sugar").concept
    assert match.finish is not None and match.finish.endswith("dusted")
    plain = finish_for("bread", "bread", None)
    dusted = finish_for("bread", "bread", match.finish)
    assert dusted.dust > 0 and plain.dust == 0
    up, side = np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]])
    brown = np.array([[0.6, 0.35, 0.1]])
    pts = np.random.default_rng(0).uniform(0, 0.05, (200, 3))
    light, eye = np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0])

    def mean_lit(normal: np.ndarray, finish) -> float:  # noqa: ANN001
        n = np.repeat(normal, len(pts), 0)
        return float(shade_pixels(np.repeat(brown, len(pts), 0), n, pts, light, eye, finish, 1e-4).mean())

    assert mean_lit(up, dusted) > mean_lit(up, plain) + 0.1
    eye_side = np.array([1.0, 0.0, 0.0])
    n = np.repeat(side, len(pts), 0)
    a = shade_pixels(np.repeat(brown, len(pts), 0), n, pts, eye_side, eye_side, dusted, 1e-4)
    b = shade_pixels(np.repeat(brown, len(pts), 0), n, pts, eye_side, eye_side, plain, 1e-4)
    assert np.allclose(a, b)  # the sides stay brown


def test_a_roll_of_a_known_two_word_noun_is_that_noun_rolled() -> None:
    """'a roll of gauze bandage': the lexicon's 'roll of gauze' took 'gauze' from 'gauze bandage', leaving
    'bandage' unknown (a 0.5 kg fabric piece by analogy)."""
    design = catalogue.design_from_text("a roll of gauze bandage")
    assert design.entry == "gauze_roll" and design.concept.fallback_level in ("exact", "synonym")
    assert planned_mass("a roll of gauze bandage") < 0.06


def test_a_surgical_cap_is_a_light_cap_not_a_baseball_cap() -> None:
    assert catalogue.design_from_text("a disposable surgical cap").entry == "surgical_cap"
    assert planned_mass("a disposable surgical cap") < 0.01


@pytest.mark.parametrize("text, entry, lo, hi", [("a whole raw chicken", "whole_chicken", 1.2, 2.2),
                                                  ("a roast turkey", "whole_turkey", 4.0, 8.5),
                                                  ("a whole duck", "whole_duck", 1.6, 3.0)])
def test_a_whole_bird_is_oven_ready_with_its_drumsticks(text: str, entry: str, lo: float, hi: float) -> None:
    """'a whole raw chicken in shrink wrap' was a pink egg (read as a water balloon); 'a roast turkey' ground meat."""
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    names = {p.name for p in design.program.parts}  # (the plan's 'left wing', a hand-drawn shape's 'wing 1')
    assert sum(bool(re.fullmatch(r"(?:left |right )?drumstick(?: \d)?", n)) for n in names) == 2
    assert sum(bool(re.fullmatch(r"(?:left |right )?wing(?: \d)?", n)) for n in names) == 2
    knuckle = next(p for p in design.program.parts if p.name in ("left knuckle", "knuckle 1")).transform.translation_m
    body = next(p for p in design.program.parts if p.name == "body").transform.translation_m
    assert knuckle[0] < body[0] and knuckle[2] > body[2]  # at the tail end, up
    assert lo <= planned_mass(text) <= hi


@pytest.mark.parametrize("text, entry", [
    ("Can you make a pair of blue denim jeans, folded in half", "jeans"),
    ("I'd like to simulate a plush turtle", "plush_turtle"), ("please generate a red rubber duck", "rubber_duck")])
def test_a_requests_opening_words_are_not_the_object(text: str, entry: str) -> None:
    """Sealed set 17 (after the run): 'Can you make a pair of blue denim jeans' was a 26 g generic block named
    'can'."""
    assert catalogue.design_from_text(text).entry == entry


def test_a_stand_up_pouch_is_a_pouch() -> None:
    """'stand-up refill pouch of liquid hand soap, 500 ml' was a generic block named 'stand' (after the run)."""
    design = catalogue.design_from_text("a stand-up refill pouch of liquid hand soap, 500 ml")
    assert design.concept.body_plan == "pouch"
    assert 0.3 <= planned_mass("a stand-up refill pouch of liquid hand soap, 500 ml") <= 0.8


def test_a_paper_towel_is_a_sheet_of_paper_that_crumples_into_a_wad() -> None:
    """'a crumpled paper towel' was a crumpled bath towel of 0.54 kg (207 times its mass; after the run)."""
    assert catalogue.design_from_text("a crumpled paper towel").entry == "paper_towel_sheet"
    assert planned_mass("a crumpled paper towel") < 0.006
    assert catalogue.design_from_text("a roll of paper towels").entry == "paper_towel_roll"
