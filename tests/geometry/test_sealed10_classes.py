"""Classes sealed set 10's blind judging found missing (#35), fixed by class after it and checked here on other
phrasings than the set's: a hedgehog's spines, a pleated face mask with its ear loops, a slice of sandwich bread (its
crust round the crumb, not a grey slab cut from the loaf), a cloth sack with its neck tied, a felt catnip mouse (ears
and a tail, not a grey egg), cups nested in a pack, a sticky hand toy, a pool noodle at its real 1.5 m, a fluffy pet
bed that weighs what a foam bed weighs, and slender objects meshed with cells across their thickness.

Real masses: typical retail or supplier figures (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.shape import ShapeProgram
from tasks.agents.intent import match_material
from tasks.geometry import catalogue, concepts, grammar
from tasks.geometry.grammar.parts import cylinder, part_group
from tasks.geometry.meshing import MIN_CELLS_ACROSS, mesh_program, slender_resolution
from tests.geometry.test_mass_classes import planned_mass


def _built(text: str) -> tuple[str, ShapeProgram, set[str]]:
    d = catalogue.design_from_text(text)
    return d.entry, d.program, {part_group(p.name) for p in d.program.parts}


@pytest.mark.parametrize("text,entry", [("squeaky latex hedgehog dog toy", "squeaky_hedgehog"),
                                        ("a stuffed hedgehog", "plush_hedgehog"),
                                        ("a plush porcupine", "plush_hedgehog")])
def test_a_hedgehog_has_a_coat_of_spines_on_its_back(text: str, entry: str) -> None:
    got, program, _groups = _built(text)
    assert got == entry
    spines = [p for p in program.parts if part_group(p.name) == "spine"]
    assert len(spines) >= 25
    body = next(p for p in program.parts if part_group(p.name) == "body")
    # on the back and flanks: every spine's centre above the body's lower quarter, none in front of the head's root
    assert all(s.transform.translation_m[2] > body.transform.translation_m[2] - 0.2 * 0.12 for s in spines)


def test_a_surgical_face_mask_has_pleats_a_nose_wire_and_ear_loops() -> None:
    got, program, groups = _built("a blue disposable face mask")
    assert got == "face_mask" and {"pleat", "nose wire", "ear loop"} <= groups
    ext = np.sort(grammar.program_extents(program, 96))[::-1]
    assert 0.2 <= ext[0] <= 0.26 and 0.08 <= ext[1] <= 0.11  # 17.5 x 9.5 cm and its loops lying out at the ends
    # medical-supply listings of 3-ply surgical masks: 2.5-4 g
    assert 0.5 <= planned_mass("a surgical mask") / 0.003 <= 2.0


@pytest.mark.parametrize("text", ["one slice of white sandwich bread", "a slice of brioche", "a slice of bread"])
def test_a_slice_of_bread_is_the_slice_with_its_crust_not_a_block_cut_from_the_loaf(text: str) -> None:
    got, program, groups = _built(text)
    assert got == "bread_slice" and "crust" in groups
    ext = np.sort(grammar.program_extents(program, 96))[::-1]
    assert ext[2] < 0.2 * ext[1]  # a thin slice lying flat
    # USDA FoodData Central: white bread, 1 slice 25-29 g
    assert 0.5 <= planned_mass(text) / 0.027 <= 2.0
    assert concepts.read_text("a slice of cheddar").match.concept != "bread_slice"


def test_a_cloth_sack_is_filled_with_its_neck_gathered_and_tied() -> None:
    got, _program, groups = _built("a burlap sack of flour")
    assert got == "cloth_sack" and {"neck", "tie", "ruffle"} <= groups
    assert planned_mass("a 2 kg cloth sack of rice") == pytest.approx(2.0, rel=0.05)  # the stated mass binds
    # retail 1 kg cloth sacks of rice and flour
    assert 0.5 <= planned_mass("a cotton flour sack") / 1.0 <= 2.0


def test_a_felt_catnip_mouse_has_ears_and_a_tail_and_little_does_not_shrink_a_hand_sized_toy() -> None:
    got, program, groups = _built("a little felt catnip mouse")
    assert got == "cat_toy_mouse" and {"ear", "tail"} <= groups
    # retail felt and fabric catnip mice, 6-8 cm body and a string tail: 5-12 g
    assert 0.5 <= planned_mass("a little felt catnip mouse") / 0.008 <= 2.0
    little = catalogue.design_from_text("a little catnip mouse").size.axis_scale
    assert little == (1.0, 1.0, 1.0)
    assert catalogue.design_from_text("a little teddy bear").size.axis_scale[0] < 1.0  # a 30 cm bear: a small one


def test_a_pack_of_cups_is_a_nested_stack_of_that_many() -> None:
    reading = concepts.read_text("pack of 12 silicone baking cups")
    program, match, _w = concepts.build(reading, "pack of 12 silicone baking cups")
    one = concepts.build(concepts.read_text("a silicone baking cup"), "a silicone baking cup")
    bodies = [p for p in program.parts if part_group(p.name) == "body"]
    assert match.concept == "silicone_mold" and len(bodies) == 12 and "a stack of 12" in match.states
    assert match.typical_mass_kg == pytest.approx(12 * one[1].typical_mass_kg)
    h1, h12 = grammar.program_extents(one[0], 48)[2], grammar.program_extents(program, 48)[2]
    assert 1.8 * h1 < h12 < 3.0 * h1  # nested: each cup a little above the one below, not 12 cups tall
    six = concepts.build(concepts.read_text("a stack of cupcake liners"), "a stack of cupcake liners")[1]
    assert "a stack of 6" in six.states


def test_a_sticky_hand_toy_is_a_small_jelly_hand() -> None:
    got, _program, groups = _built("sticky stretchy jelly hand toy")
    assert got == "sticky_hand" and {"palm", "index finger", "little finger"} <= groups
    # retail party-favour sticky hands: 5-12 g
    assert 0.5 <= planned_mass("a sticky hand toy") / 0.008 <= 2.0


def test_a_pool_noodle_is_its_real_length_with_its_cross_section() -> None:
    arrays_ext = np.sort(np.asarray(_mesh_extents("a bright pink pool noodle")))[::-1]
    assert arrays_ext[0] == pytest.approx(1.5, rel=0.05) and 0.058 <= arrays_ext[1] <= 0.072
    # retail listings of 150-160 cm PE pool noodles: 0.1-0.2 kg
    assert 0.5 <= planned_mass("a pool noodle") / 0.15 <= 2.0


def _mesh_extents(text: str) -> np.ndarray:
    from tasks.geometry import pipeline
    from contracts.request import AssetRequest

    arrays, _info = pipeline.mesh_from_text(AssetRequest(text=text), pipeline.settings_from_contract("draft"))
    return pipeline.arrays_to_mesh(arrays).extents


def test_a_slender_program_is_meshed_with_cells_across_it() -> None:
    rod = ShapeProgram(name="rod", category="foam", parts=[cylinder("body", 0.03, 1.5, (0, 0, 0), rot=(0, 90, 0))])
    res = slender_resolution(rod, 64)
    assert res >= 64 and res * 0.06 / 1.5 >= min(MIN_CELLS_ACROSS, 4 * 64 * 0.06 / 1.5) - 1
    mesh = mesh_program(rod, 64)
    assert np.sort(mesh.extents)[1] == pytest.approx(0.06, rel=0.08)  # 64 cells along it left 2.6 across: 0.052 m
    ball = ShapeProgram(name="ball", category="ball", parts=[cylinder("body", 0.05, 0.1, (0, 0, 0))])
    assert slender_resolution(ball, 64) == 64  # a stout object keeps the resolution it was given


def test_fluffy_is_a_surface_word_that_keeps_a_foam_bed_foam() -> None:
    # retail listings of 60 cm donut pet beds: 0.9-1.6 kg (a plush density over its volume gave 3.7 kg)
    assert 0.5 <= planned_mass("a round fluffy pet bed, 60 cm") / 1.2 <= 2.0
    assert match_material("a fluffy pet bed", concept_material="pu_foam") == "pu_foam"
    assert match_material("a fluffy ball", concept_material="rubber") == "plush"  # a fluffy ball is a plush one


def test_a_scarf_tied_in_a_knot_is_knotted_and_keeps_its_mass() -> None:
    got, program, groups = _built("a silk scarf tied in a loose knot")
    assert got == "silk_scarf" and {"knot wrap", "tail", "end"} <= groups
    flat = catalogue.design_from_text("a silk scarf")
    knot = catalogue.design_from_text("a silk scarf tied in a loose knot")
    assert "knotted" in knot.concept.states and knot.size.longest_m is None
    assert grammar.program_extents(program, 64).max() < 0.85 * grammar.program_extents(flat.program, 64).max()
    # the same scarf: retail 160-180 cm silk scarves 30-50 g
    assert 0.5 <= planned_mass("a silk scarf tied in a loose knot") / 0.04 <= 2.0
    for text in ("a red balloon tied with a string", "a cloth sack of rice tied at the neck"):
        assert not catalogue.design_from_text(text).warnings, text  # 'tied' alone is no knot to draw
