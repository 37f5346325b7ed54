"""Session 37's audit, textiles group: flat and folded cloth, paper, garments, straps and bags the blind judges could
not name, given what people name them by: a tea towel's stripes, a gingham tablecloth's checks, a newspaper's
headline and columns, a magazine's cover, a sleeping bag's hood, a pillowcase's open end, a dress's bodice and
waist, an apron's bib and ties, a swimsuit's leg openings, a belt's buckle, a leash's handle and clip, a hammock's
spreader bars and cords, a bin bag standing tied, a duffel bag's handles and zip."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry.concepts import concept_program
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import mesh_program
from tasks.geometry.sdf import program_bounds

KEYS = ("tea_towel", "tablecloth", "newspaper", "magazine", "sleeping_bag", "pillowcase", "belt", "dog_leash",
        "dress", "apron", "swimsuit", "camping_hammock", "trash_bag", "duffel_bag", "scarf", "sock_single",
        "rubber_boot", "ribbon", "foam_sword", "foam_rocket", "foam_dart", "dry_bag", "baby_bodysuit")


@pytest.fixture(scope="module")
def programs():  # noqa: ANN201
    return {k: concept_program(k) for k in KEYS}


def _groups(program) -> set[str]:  # noqa: ANN001
    return {part_group(p.name) for p in program.parts}


def _colour(program, group: str) -> np.ndarray:  # noqa: ANN001
    return np.asarray(next(p.color_rgb for p in program.parts if part_group(p.name) == group and
                           p.operation == "union"))


def _extent(program) -> np.ndarray:  # noqa: ANN001
    b = program_bounds(program)
    return b[1] - b[0]


@pytest.mark.parametrize(("key", "groups"), [
    ("tea_towel", {"stripe"}), ("tablecloth", {"stripe", "check"}), ("scarf", {"stripe", "tassel"}),
    ("newspaper", {"headline", "text", "photo"}), ("magazine", {"masthead", "cover photo", "cover line"}),
    ("sleeping_bag", {"hood", "opening", "zip"}), ("pillowcase", {"cuff"}),
    ("belt", {"buckle", "buckle window", "prong"}), ("dog_leash", {"handle", "clip", "swivel ring"}),
    ("dress", {"bodice", "waistband", "sleeve"}), ("apron", {"bib", "neck strap", "tie", "pocket"}),
    ("swimsuit", {"leg opening", "strap", "crotch"}), ("camping_hammock", {"spreader bar", "cord", "ring", "rope"}),
    ("trash_bag", {"knot", "ear", "lump"}), ("duffel_bag", {"handle", "handle wrap", "zip", "end panel"}),
    ("sock_single", {"heel", "toe", "cuff"}), ("rubber_boot", {"sole", "hollow", "opening"}),
    ("ribbon", {"loop", "tail", "tail notch"}), ("foam_sword", {"crossguard", "grip", "pommel", "point"}),
    ("foam_rocket", {"nose", "fin"}), ("foam_dart", {"tip"}), ("dry_bag", {"roll", "strap", "buckle"}),
    ("baby_bodysuit", {"sleeve", "snap", "crotch"}),
])
def test_each_has_the_parts_it_is_named_by(programs, key: str, groups: set[str]) -> None:  # noqa: ANN001
    assert groups <= _groups(programs[key]), key


@pytest.mark.parametrize(("key", "patch", "ground"), [
    ("tea_towel", "stripe", "body"), ("tablecloth", "check", "body"), ("newspaper", "headline", "body"),
    ("magazine", "masthead", "body"), ("sock_single", "heel", "foot"), ("belt", "buckle", "body"),
])
def test_patterns_and_parts_have_their_own_colour(programs, key: str, patch: str, ground: str) -> None:  # noqa: ANN001
    assert np.abs(_colour(programs[key], patch) - _colour(programs[key], ground)).max() > 0.25, key


def test_a_sleeping_bag_face_opening_is_darker_than_its_hood(programs) -> None:  # noqa: ANN001
    prog = programs["sleeping_bag"]
    assert _colour(prog, "opening").sum() < 0.6 * _colour(prog, "hood").sum()


def test_a_pattern_is_tiled_flush_and_the_sheet_stays_one_piece(programs) -> None:  # noqa: ANN001
    """Pattern tiles share the sheet's top (no relief), and overlapping a little they leave no seam where the
    mesher would split the sheet (a magazine lost a quarter of its page along a tile's edge)."""
    prog = programs["magazine"]
    tops = {round(p.transform.translation_m[2] + p.primitive.size_m[2] / 2, 6) for p in prog.parts
            if p.primitive.kind == "rounded_box" and p.operation == "union"}
    assert len(tops) == 1
    mesh = mesh_program(prog, 48)
    assert mesh.body_count == 1
    assert mesh.extents[0] == pytest.approx(_extent(prog)[0], rel=0.06)


def test_a_dress_flares_from_a_narrow_bodice_and_a_belt_lies_buckled_in_a_loop(programs) -> None:  # noqa: ANN001
    dress = programs["dress"]
    bodice = next(p for p in dress.parts if part_group(p.name) == "bodice")
    skirt = next(p for p in dress.parts if p.name == "body")
    assert skirt.primitive.radius_bottom_m > 1.6 * bodice.primitive.radii_m[1]
    ext = _extent(programs["belt"])
    assert ext[0] < 2.5 * ext[1]  # a loop, not a 1.1 m stick


def test_a_bin_bag_stands_and_a_leash_lies_out_at_length(programs) -> None:  # noqa: ANN001
    ext = _extent(programs["trash_bag"])
    assert ext[2] > 1.2 * max(ext[0], ext[1])
    leash = _extent(programs["dog_leash"])
    assert leash[0] > 4 * leash[1]


def test_a_rubber_boot_stands_and_a_ribbon_is_tied_in_a_bow(programs) -> None:  # noqa: ANN001
    boot = _extent(programs["rubber_boot"])
    assert boot[2] > 1.2 * boot[1]  # the leg upright, not an L lying on its side
    bow = _extent(programs["ribbon"])
    assert bow[0] < 2.0 * bow[1]  # two loops and the tails: no longer a ring band
