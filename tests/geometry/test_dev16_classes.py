"""Development set 16 and sealed set 15's after-run findings (#35, session 30): what reviewers who never saw the
lexicon asked for and L0 built wrong, fixed by class and tested here with other phrasings than the sets' (the set
itself: docs/blind/dev16/)."""

from __future__ import annotations

import pytest

from contracts.request import AssetRequest
from tasks.geometry import catalogue, pipeline
from tests.geometry.test_mass_classes import planned_mass


def _built(text: str):  # noqa: ANN202
    arrays, info = pipeline.mesh_from_text(AssetRequest(text=text), pipeline.settings_from_contract("draft"))
    return pipeline.arrays_to_mesh(arrays), info


def test_a_crumpled_sheet_of_paper_is_a_hand_sized_wad_of_its_own_mass() -> None:
    """'a crumpled sheet of A4 printer paper' was a yellow foam block (paper was not in the lexicon); a stiff sheet
    crumples into a round wad ~6.5 cm across, not a cloth's heap, of the sheet's 5 g."""
    mesh, info = _built("a crumpled sheet of A4 printer paper")
    assert info.entry == "paper_sheet"
    assert 0.05 <= mesh.extents.max() <= 0.08 and mesh.extents.min() > 0.75 * mesh.extents.max()  # round
    assert 0.0035 <= planned_mass("a crumpled sheet of A4 printer paper") <= 0.007
    flat, _ = _built("a sheet of printer paper")
    assert flat.extents.max() == pytest.approx(0.297, rel=0.05) and flat.extents.min() < 0.02


@pytest.mark.parametrize("text, entry", [
    ("a crumpled ball of baking paper", "baking_paper"), ("a wad of newsprint", "newspaper_sheet"),
    ("a ball of crumpled printer paper", "paper_sheet")])
def test_a_ball_of_a_sheet_is_the_sheet_crumpled(text: str, entry: str) -> None:
    """'a ball of X' for a sheet: the sheet crumpled (a 41 cm ball of baking paper of 131 g before)."""
    design = catalogue.design_from_text(text)
    assert design.entry == entry and design.program.parts[0].name == "body"
    assert any(p.name.startswith("facet") for p in design.program.parts)  # the wad's creased facets
    assert planned_mass(text) < 0.05


def test_a_ball_of_a_non_sheet_stays_its_own_ball() -> None:
    assert catalogue.design_from_text("a ball of wool").entry == "yarn_ball"
    assert not any(p.name.startswith("facet") for p in catalogue.design_from_text("a ball of wool").program.parts)


@pytest.mark.parametrize("text, lo, hi", [
    ("a sheet of newspaper", 0.008, 0.04), ("a folded newspaper", 0.15, 0.4), ("a baguette", 0.18, 0.35)])
def test_paper_and_bread_masses(text: str, lo: float, hi: float) -> None:
    assert lo <= planned_mass(text) <= hi


def test_an_inflated_known_object_keeps_its_shells_material() -> None:
    """'an inflated 33 cm balance cushion' read 'inflated' as the air-filled material (20 g); it is the cushion's
    PVC shell blown up (0.8-1.1 kg)."""
    assert 0.5 <= planned_mass("an inflated 33 cm balance cushion") <= 1.5
    assert planned_mass("an inflated 33 cm balance cushion") == pytest.approx(planned_mass("a balance cushion"),
                                                                              rel=0.1)


@pytest.mark.parametrize("text", ["a red resistance band tied in a loop", "a latex exercise band tied in a knot"])
def test_a_resistance_band_said_tied_is_a_flat_band(text: str) -> None:
    """A loop band is a loop already: one said tied is a flat therapy band (0.26 kg pull-up loop before, ~40 g)."""
    assert catalogue.design_from_text(text).entry == "therapy_band"
    assert 0.02 <= planned_mass(text) <= 0.1


@pytest.mark.parametrize("text, entry, lo, hi", [
    ("an uncut 20 cm maki roll", "maki_roll", 0.12, 0.35),  # a 20 cm blob of maki pieces: 4.8 kg
    ("a horseshoe ring of smoked sausage", "kielbasa", 0.2, 0.6),  # a generic block of 20 g
    ("a stack of four folded fat quarters", "fat_quarter", 0.08, 0.25),  # a metre of fabric x 4: 2 kg
    ("a rolled-up bamboo sushi mat", "sushi_mat_rolled", 0.04, 0.12),  # a generic block
    ("a silicone stacking cup", "stacking_cup", 0.02, 0.08),  # a blob of 170 g
    ("a crumpled empty bread bag", "carrier_bag", 0.003, 0.02),  # a loaf of bread: 0.94 kg
    ("a crumpled sheet of brown kraft paper", "kraft_paper", 0.025, 0.1),
    ("a 25 cm rolled-up hand towel", "rolled_hand_towel", 0.1, 0.3),  # 0.5 kg
])
def test_dev16_objects_and_masses(text: str, entry: str, lo: float, hi: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert lo <= planned_mass(text) <= hi


def test_a_long_object_in_a_horseshoe_is_drawn_bent() -> None:
    mesh, info = _built("a green pool noodle laid in a horseshoe")
    assert any("bent by 180 deg" in n for n in info.notes) and mesh.extents[1] > 0.3 * mesh.extents[0]


@pytest.mark.parametrize("text", ["a balled-up fitted sheet", "a wadded-up pillowcase"])
def test_balled_up_cloth_is_crumpled(text: str) -> None:
    design = catalogue.design_from_text(text)
    assert any(p.name.startswith("fold") for p in design.program.parts)  # the heap's folds, not a stack of layers


def test_a_colour_word_of_the_objects_own_name_is_not_painted_over_it() -> None:
    """'a salmon nigiri' was salmon-pink all over (read as a pink eraser): its rice base stays white; a colour the
    entry does not paint still applies ('a red cabbage'), and 'salmon-coloured' is a colour."""
    parts = {p.name: p.color_rgb for p in catalogue.design_from_text("a salmon nigiri").program.parts}
    assert min(parts["body"]) > 0.8 and parts["fish"][0] > 2 * parts["fish"][2]
    assert catalogue.design_from_text("a red cabbage").program.parts[0].color_rgb[0] > 0.6
    assert catalogue.design_from_text("a salmon-coloured towel").program.parts[0].color_rgb[2] < 0.5


@pytest.mark.parametrize("text, entry, lo, hi", [
    ("raw salmon fillet portion, skin on", "salmon_fillet", 0.1, 0.35),  # a generic block of 26 g
    ("an unmoulded vanilla panna cotta", "panna_cotta", 0.07, 0.25),  # a 0.37 kg red jelly
])
def test_sealed16_after_run_objects(text: str, entry: str, lo: float, hi: float) -> None:
    """Sealed set 16's misses fixed after its run (no longer blind)."""
    design = catalogue.design_from_text(text)
    assert design.entry == entry and lo <= planned_mass(text) <= hi
    if entry == "panna_cotta":
        assert min(design.program.parts[0].color_rgb) > 0.5  # cream, not the jelly's red
