"""Classes sealed set 9's blind judging found missing (#35), fixed after it: a wrung-out wet washcloth (a twisted rope
holding water), a hacky sack (a panelled footbag, not a plain juggling ball), a solid rubber chew bone (not the hollow
squeaky one), a neoprene knee brace (the compression sleeve, not a generic block)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import concepts, grammar
from tasks.geometry.grammar.parts import part_group


def _built(text: str):  # noqa: ANN202
    reading = concepts.read_text(text)
    program, match, _warnings = concepts.build(reading, text)
    return reading, program, match


def test_a_wrung_out_wet_washcloth_is_a_twisted_rope_that_holds_water() -> None:
    _reading, program, match = _built("a wet washcloth wrung out")
    assert match.concept == "face_cloth" and {"twisted", "wet"} <= set(match.states)
    assert "twist" in {part_group(p.name) for p in program.parts}
    ext = np.sort(grammar.program_extents(program, 40))[::-1]
    assert ext[0] > 3 * ext[1] and ext[1] == pytest.approx(ext[2], rel=0.3)  # a rope, not a flat square
    assert 0.2 <= ext[0] <= 0.45  # a 30 x 30 cm cloth twisted along its diagonal
    dry = _built("a washcloth")[2]
    # wrung out by hand, cotton terry keeps ~0.6-1x its dry weight in water
    assert match.typical_mass_kg == pytest.approx(concepts.WRUNG_WET_FACTOR * dry.typical_mass_kg)
    assert _built("a soaked kitchen sponge")[2].typical_mass_kg > 2 * _built("a kitchen sponge")[2].typical_mass_kg
    assert "wet" not in _built("a wet plush dog")[2].states  # a plush toy's water is not modelled


def test_a_hacky_sack_is_a_panelled_footbag_and_a_chew_bone_is_solid_rubber() -> None:
    sack = _built("hacky sack")
    assert sack[2].concept == "footbag" and sack[2].typical_mass_kg == pytest.approx(0.045)
    assert "seam" in " ".join(p.name for p in sack[1].parts)  # the panels' raised seams
    bone = concepts.read_text("a chewy rubber bone toy for a medium dog").match
    assert bone.concept == "rubber_chew_bone" and not bone.hollow and bone.typical_mass_kg >= 0.1
    assert concepts.read_text("a squeaky bone").match.hollow  # the vinyl squeaker stays hollow


def test_a_knee_brace_is_the_neoprene_sleeve() -> None:
    match = concepts.read_text("neoprene knee brace").match  # (set 38: its own hinged brace, not the plain sleeve
    # a blind judge took for foam pipe insulation)
    assert match.concept == "knee_brace" and match.fallback_level in ("exact", "synonym")


@pytest.mark.parametrize("text,concept", [
    ("floppy-eared stuffed bunny sitting upright, 30cm tall", "plush_bunny"),  # set 10: 'upright' read as the noun
    ("a teddy bear propped upright", "teddy_bear"),
    ("a plush dog leaning sideways", "plush_dog"),
])
def test_a_pose_word_after_the_noun_is_not_the_object(text: str, concept: str) -> None:
    match = concepts.read_text(text).match
    assert match.concept == concept and not match.by_analogy
