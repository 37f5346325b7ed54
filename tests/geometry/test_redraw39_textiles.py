"""Session 39's textiles redraw: soft goods the blind judges could not name as built (a folded hospital gown read as a
chair cushion, a muslin swaddle as a folded bath towel). Each is now a hand-written shape
(tasks/geometry/shapes/redraw39_textiles.yaml) with the cues a person names it by: the gown laid flat back up, its navy
diamond print on pale blue-green, short sleeves, the bound back opening with a bow at the neck and loose waist ties;
the swaddle a thin white 120 cm square with a pastel star and dot print, one corner folded back. Checked on the
programs, built once each."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds

CASES = [
    ("a folded hospital gown", "hospital_gown", {"body", "sleeve", "sleeve hem", "collar band", "opening edge",
                                                 "bow knot", "bow loop", "tie", "dot"}, 1.1),
    ("a muslin swaddle blanket folded in a square", "muslin_swaddle", {"layer", "folded corner", "fold", "star arm",
                                                                        "dot"}, 1.2),
]


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


def _groups(text: str) -> set[str]:
    return {part_group(p.name) for p in _design(text).program.parts if p.operation == "union"}


@pytest.mark.parametrize(("text", "entry", "groups", "size_m"), CASES)
def test_prompt_builds_the_entry_with_its_cue_parts_at_its_size(text: str, entry: str, groups: set[str],
                                                                size_m: float) -> None:
    d = _design(text)
    assert d.entry == entry
    assert groups <= _groups(text), groups - _groups(text)
    assert len(d.program.parts) <= 64
    lo, hi = program_bounds(d.program)
    assert 0.85 * size_m <= float(np.max(hi - lo)) <= 1.1 * size_m


def test_the_gown_lies_flat_and_its_print_contrasts() -> None:
    parts = _design("a folded hospital gown").program.parts
    lo, hi = program_bounds(_design("a folded hospital gown").program)
    ext = hi - lo
    assert ext[2] < 0.1 * min(ext[0], ext[1])  # laid flat and open, not a folded stack
    body = next(p for p in parts if p.name == "body")
    dots = [p for p in parts if part_group(p.name) == "dot"]
    assert len(dots) >= 30
    assert all(np.mean(p.color_rgb) < 0.5 * np.mean(body.color_rgb) for p in dots)  # navy on pale blue-green


def test_the_swaddle_is_a_thin_square_with_a_pastel_print() -> None:
    prog = _design("a muslin swaddle blanket folded in a square").program
    lo, hi = program_bounds(prog)
    ext = hi - lo
    assert 0.9 < ext[0] / ext[1] < 1.1 and ext[2] < 0.15 * ext[0]  # a thin square, one corner folded back
    prints = {tuple(p.color_rgb) for p in prog.parts if part_group(p.name) in ("star arm", "dot")}
    assert len(prints) >= 3 and all(min(c) > 0.2 for c in prints)  # pastel colours on white
