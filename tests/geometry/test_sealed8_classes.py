"""The classes sealed set 8's blind judging found missing or wrong (#35): a plush octopus read as the rubber one, a
bunch of grapes built as one grape, a T-rex on its back legs laid on its side, a baseball cap built as a beanie, a
generic bird for an owl, a keychain toy at full size, a crumpled t-shirt without its outline, a silk scarf at a knit
scarf's mass, an inflatable cuff weighed as air, size words of the ears and the pose read as the object's."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.lexicon import load_lexicon
from tasks.agents.intent import targets_from_intent
from tasks.geometry import concepts, grammar
from tasks.geometry.canonical import is_resting_stable, rest_on_ground
from tasks.geometry.catalogue import parse_modifiers
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import mesh_program


def _built(text: str):  # noqa: ANN202
    reading = concepts.read_text(text)
    program, match, _warnings = concepts.build(reading, text)
    return reading, program, match


def _groups(program) -> set[str]:  # noqa: ANN001
    return {part_group(p.name) for p in program.parts}


def test_a_plush_word_keeps_the_plush_toy_over_a_squishy_rubber_one() -> None:
    assert concepts.read_text("squishy plush octopus").match.concept == "plush_octopus"
    assert concepts.read_text("squishy stuffed octopus").match.default_material == "plush"
    assert concepts.read_text("a squishy octopus").match.concept == "rubber_octopus"  # the vinyl squeeze toy


def test_a_bunch_of_grapes_is_a_cluster_of_grapes_with_a_bunchs_mass() -> None:
    _reading, program, match = _built("a bunch of green seedless grapes on the stem")
    assert match.concept == "grape" and "a bunch" in match.states
    grapes = [p for p in program.parts if part_group(p.name) == "body"]
    assert len(grapes) >= 30 and "stem" in _groups(program)
    # USDA: a grape ~5 g; a bunch of table grapes is 30-100 of them, ~0.15-1 kg
    assert 0.15 <= match.typical_mass_kg <= 1.0, match.mass_source
    assert 0.12 <= match.typical_size_m <= 0.3
    one = _built("a green grape")[2]
    assert one.typical_mass_kg == pytest.approx(0.005, rel=0.3) and "a bunch" not in one.states


def test_a_t_rex_on_its_back_legs_stands_on_its_feet_and_tail() -> None:
    _reading, program, _match = _built("a plush T-rex standing on its back legs")
    mesh = mesh_program(program, 64)
    rest_on_ground(mesh)
    assert is_resting_stable(mesh)  # not laid on its side by the resting-pose search
    assert mesh.extents[2] > 0.6 * mesh.extents.max()  # upright
    tail = [p for p in program.parts if part_group(p.name) == "tail"]
    lo = min(float(mesh.vertices[:, 2].min()), 0.0)
    tip = max(tail, key=lambda p: -p.transform.translation_m[0])
    assert tip.transform.translation_m[2] - lo < 0.25 * mesh.extents[2]  # the tail runs down to the ground


def test_a_baseball_cap_has_a_peak_and_a_beanie_has_none() -> None:
    _reading, cap, match = _built("a cotton baseball cap")
    assert match.concept == "baseball_cap" and "visor" in _groups(cap)
    ext = grammar.program_extents(cap, 48)
    assert ext[0] > 1.3 * ext[1]  # the peak reaches out in front of the crown
    assert concepts.read_text("a red knitted beanie").match.concept == "beanie_hat"
    assert concepts.read_text("a knitted cap").match.concept == "beanie_hat"


def test_an_owl_has_its_face_and_ear_tufts_and_a_keychain_one_is_small_on_a_ring() -> None:
    _reading, owl, match = _built("a plush owl")
    assert {"face disc", "ear tuft", "eye"} <= _groups(owl)
    _reading, key, kmatch = _built("a plush owl keychain")
    assert "keyring" in _groups(key) and "keychain" in kmatch.states
    assert kmatch.typical_size_m == pytest.approx(concepts.KEYCHAIN_SIZE_M)
    # the same toy, smaller, its mass ~L^2 as any plush's (session 34: ~L^3 made a keychain bunny 3 g, retail 25-35 g)
    expected = match.typical_mass_kg * (concepts.KEYCHAIN_SIZE_M / match.typical_size_m) ** concepts.PLUSH_MASS_EXPONENT
    assert kmatch.typical_mass_kg == pytest.approx(expected) and 0.01 <= kmatch.typical_mass_kg <= 0.06  # not 150 g


def test_a_crumpled_t_shirt_keeps_its_outline_and_a_heap_is_a_heap() -> None:
    _reading, shirt, match = _built("a crumpled t-shirt")
    assert "crumpled" in match.states and {"sleeve", "wrinkle"} <= _groups(shirt)
    ext = grammar.program_extents(shirt, 64)
    assert ext[2] < 0.2 * ext.max()  # spread out, wrinkled, not a mound
    _reading, heap, _match = _built("a t-shirt in a heap on the floor")
    assert "wrinkle" not in _groups(heap)


def test_a_silk_scarf_weighs_a_silk_scarf() -> None:
    reading, program, match = _built("thin silk scarf")
    assert match.concept == "silk_scarf"
    mesh = mesh_program(program, 96)
    mass = match.density_kg_per_m3 * float(mesh.volume)  # what L1's density x built volume gives
    assert 0.02 <= mass <= 0.08, mass  # retail: 25-60 g (a knit scarf is 150-250 g)
    knit = load_lexicon().entries["scarf"]
    assert knit.mass_kg > 3 * load_lexicon().entries["silk_scarf"].mass_kg


def test_a_word_of_the_objects_own_name_is_no_material() -> None:
    cuff = concepts.read_text("inflatable arm cuff from a blood pressure monitor, tube attached").match
    assert cuff.concept == "blood_pressure_cuff"
    targets = targets_from_intent("inflatable arm cuff from a blood pressure monitor", None, None, cuff)
    assert "inflatable" not in targets.matched_words  # its nylon sleeve, not an air-filled inflatable
    ball = concepts.read_text("an inflatable beach ball").match
    assert "inflatable" in targets_from_intent("an inflatable beach ball", None, None, ball).matched_words


@pytest.mark.parametrize(("text", "found"), [
    ("floppy stuffed bunny with long ears, lying flat on its belly", []),
    ("a long-eared bunny", []),
    ("a bunny with long and floppy ears", []),
    ("a big teddy with short legs", ["big"]),
    ("a long scarf", ["long"]),
    ("a flat cushion", ["flat"]),
])
def test_size_words_of_a_part_or_a_pose_do_not_scale_the_object(text: str, found: list[str]) -> None:
    assert parse_modifiers(text)[0] == found


def test_a_seated_toy_asked_to_lie_on_its_belly_lies_down() -> None:
    reading = concepts.read_text("a stuffed bunny lying on its belly")
    assert reading.donor is not None and "lying" in grammar.plan_states(reading.donor.plan or "")
    _reading, program, _match = _built("a stuffed bunny lying on its belly")
    ext = grammar.program_extents(program, 48)
    assert ext[2] < ext[0]  # longer than tall


def test_a_curled_up_cat_shows_its_head_and_ears_over_its_body() -> None:
    _reading, program, _match = _built("a white cat curled up asleep")
    tops = {}
    for p in program.parts:
        g = part_group(p.name).split()[0]
        tops[g] = max(tops.get(g, -np.inf), p.transform.translation_m[2])
    assert tops["ear"] > tops["body"] and tops["head"] > tops["body"]


def test_a_sloth_has_its_pale_face_dark_eye_stripes_and_claws_a_panda_its_eye_patches() -> None:
    _reading, sloth, _match = _built("a plush sloth")
    assert {"face", "eye patch", "claw"} <= _groups(sloth)
    patch = next(p for p in sloth.parts if part_group(p.name) == "eye patch")
    face = next(p for p in sloth.parts if part_group(p.name) == "face")
    assert patch.color_rgb != face.color_rgb and sum(patch.color_rgb) < sum(face.color_rgb)
    _reading, panda, _match = _built("a panda plush toy")
    assert "eye patch" in _groups(panda) and "claw" not in _groups(panda)


def test_a_slice_of_a_loaf_is_one_slice_across_it_with_a_slices_mass() -> None:
    """Set 9 (after its judging): 'a single slice of white sandwich bread' was built 24 cm across at a loaf's 350 g."""
    _reading, program, match = _built("a single slice of white sandwich bread")
    ext = np.sort(grammar.program_extents(program, 40))[::-1]
    assert 0.08 <= ext[0] <= 0.16 and ext[2] < 0.02  # ~11 x 11 x 1.2 cm
    assert 0.012 <= match.typical_mass_kg <= 0.05  # USDA: one slice of white bread ~25-29 g


def test_a_mouse_cat_toy_is_the_cat_toy_mouse_not_a_plush_mouse() -> None:
    assert concepts.read_text("felt mouse cat toy").match.concept == "cat_toy_mouse"
    assert concepts.read_text("a teether ring").match.concept != "cat_toy_mouse"
