"""Session 45's folded cloth: blind judges named a folded horse rug, a tarp, a sail and a moving blanket 'an
accordion-folded foam pad' or 'a foam floor tile': the folded sheet was a tall squared block of eight equal layers
with even grooves. Folded cloth is now drawn low (no higher than FOLD_FLAT of its smaller side), each layer its own
soft slab a little shifted, turned, narrower or wider than the next (the middle ones bulging), the same every time;
its entry's effective density was recalibrated to the new built volume, so its mass is kept."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import grammar
from tasks.geometry.catalogue import design_from_text
from tasks.geometry.grammar import goods
from tasks.geometry.meshing import mesh_program
from tasks.geometry.sdf import program_bounds

THROW = {"width": 0.86667, "thickness": 0.004, "folds": 3, "state": "folded"}  # the lexicon's throw blanket
TARP = {"width": 0.67, "thickness": 0.00012, "folds": 3, "state": "folded", "grommets": 3}
# masses blind_bench gave at 55f5a5d (before this change), at the draft mesh: kept within 2 %
MASS_BEFORE = {"a folded moving blanket": 1.599, "a folded blue tarp": 0.7038, "a folded bath towel": 0.5883,
               "a folded horse turnout rug": 2.4935}


def _program(params: dict):
    return grammar.build_program("sheet", params, {"body": (0.5, 0.1, 0.1)}, "sheet", "textile", 1.0)


@functools.lru_cache(maxsize=8)
def _design(text: str):
    return design_from_text(text)


def test_a_folded_blankets_layers_are_not_all_the_same_footprint() -> None:
    layers = [p for p in _program(THROW).parts if p.name == "body" or p.name.startswith("layer ")]
    assert len(layers) >= 3
    sizes = {tuple(round(v, 4) for v in p.primitive.size_m[:2]) for p in layers}
    centres = {tuple(round(v, 4) for v in p.transform.translation_m[:2]) for p in layers}
    assert len(sizes) == len(layers) and len(centres) == len(layers)  # each a little off the others
    turns = {round(p.transform.rotation_deg[2], 3) for p in layers}
    assert len(turns) > 1


def test_folded_cloth_lies_low_not_a_cube_of_layers() -> None:
    for params in (THROW, TARP):
        lo, hi = program_bounds(_program(params))
        ext = hi - lo
        assert ext[2] < 0.4 * min(ext[0], ext[1])


def test_the_folded_drawing_is_deterministic() -> None:
    a, b = _program(THROW), _program(THROW)
    assert [p.model_dump() for p in a.parts] == [p.model_dump() for p in b.parts]


def test_each_drawn_layer_is_thick_enough_for_the_draft_mesher() -> None:
    for params in (THROW, TARP, {"width": 0.5, "thickness": 0.00357, "folds": 2, "state": "folded"}):
        p = goods.SheetParams(**params)
        length, width, _ = goods.folded_footprint(p)
        m, td = goods.fold_drawn(length, width, goods.fold_layers(p), goods.sheet_layer(p))
        assert m >= 2 and td >= 2.5 * max(length, width) / 64


def test_a_foam_pad_and_cut_sheets_stay_a_squared_block() -> None:
    """Not cloth: a folded crash pad (its real thickness built) and cut sheets keep the block of equal layers."""
    for params in ({"width": 0.833, "thickness": 0.083, "folds": 1, "state": "folded"},
                   {"width": 0.9, "thickness": 0.0004, "folds": 3, "state": "folded", "crisp": True}):
        groups = {p.name.split()[0] for p in _program(params).parts}
        assert "gap" in groups and "layer" not in groups


@pytest.mark.parametrize("text", sorted(MASS_BEFORE))
def test_folded_cloth_keeps_its_mass(text: str) -> None:
    d = _design(text)
    mesh = mesh_program(d.program, 64)
    mass = d.concept.mass_estimate_kg(float(mesh.volume), float(mesh.area))
    assert mass == pytest.approx(MASS_BEFORE[text], rel=0.02)
    assert np.isfinite(mass)
