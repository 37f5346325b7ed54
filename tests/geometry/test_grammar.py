"""The shape grammar: every body plan builds a watertight, named program, and its parameters do what they say."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.errors import InputError
from tasks.geometry import grammar
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import mesh_program
from tasks.geometry.sdf import program_bounds, program_sdf

BODY = {"body": (0.5, 0.3, 0.2)}


def _build(plan: str, size_m: float = 0.2, **params: object):  # noqa: ANN202
    return grammar.build_program(plan, params, BODY, plan, "test", size_m)


@pytest.mark.parametrize("plan", grammar.plan_names())
def test_every_plan_builds_a_watertight_named_program_of_its_size(plan: str) -> None:
    program = _build(plan, 0.2)
    names = [p.name for p in program.parts]
    assert "part" not in names and len(set(names)) == len(names), names  # named uniquely: 'left ear', 'right ear'
    assert program.parts[0].color_rgb == BODY["body"] or names[0] != "body"  # the main part takes the body colour
    mesh = mesh_program(program, 48)
    assert mesh.is_watertight and mesh.volume > 0
    assert mesh.extents.max() == pytest.approx(0.2, rel=0.08)  # resized to its longest extent


@pytest.mark.parametrize("legs", [2, 4, 6])
def test_quadruped_leg_count_gives_that_many_legs(legs: int) -> None:
    program = _build("quadruped", leg_count=legs)
    assert sum(part_group(p.name) == "leg" for p in program.parts) == legs


@pytest.mark.parametrize("arms", [5, 8, 10])
def test_cephalopod_arm_count(arms: int) -> None:
    program = _build("cephalopod", arm_count=arms)
    assert len({p.name.split()[1] for p in program.parts if p.name.startswith("arm ")}) == arms


def test_ring_has_a_hole_and_a_ball_none() -> None:
    """The signed distance at a ring's centre is positive (outside: a real hole); a ball's is negative; the ring's
    surface has genus 1 (Euler characteristic 0), the ball's genus 0."""
    ring = _build("ring", 0.1)
    b = program_bounds(ring)
    centre = (b[0] + b[1]) / 2
    assert program_sdf(centre[None], ring)[0] > 0.005
    assert mesh_program(ring, 40).euler_number == 0
    ball = _build("ball", 0.1)
    assert program_sdf(((program_bounds(ball)[0] + program_bounds(ball)[1]) / 2)[None], ball)[0] < 0
    assert mesh_program(ball, 32).euler_number == 2


def test_tube_hole_parameter_opens_the_axis() -> None:
    solid, hollow = _build("tube", 0.3), _build("tube", 0.3, hole=0.5)
    axis = np.array([[0.0, 0.0, float(program_bounds(solid).mean(axis=0)[2])]])
    assert program_sdf(axis, solid)[0] < 0 < program_sdf(axis, hollow)[0]
    assert mesh_program(hollow, 48).volume < 0.8 * mesh_program(solid, 48).volume


def test_parameters_change_proportions() -> None:
    """A giraffe's neck makes the animal taller than long-bodied; a flat fish is wide and low; an elongated
    fruit's curvature lifts its middle; ears 'long' reach above ears 'round'."""
    plain, giraffe = mesh_program(_build("quadruped"), 32), mesh_program(_build("quadruped", neck_length=1.0,
                                                                               neck_angle_deg=75), 32)
    assert giraffe.extents[2] / giraffe.extents[0] > 1.5 * plain.extents[2] / plain.extents[0]
    flat = mesh_program(_build("fish", flat=True), 32)
    assert flat.extents[1] > 3 * flat.extents[2]
    straight = mesh_program(_build("elongated"), 32)
    banana = mesh_program(_build("elongated", curvature=1.2), 32)
    assert banana.extents[2] > 1.5 * straight.extents[2]
    top = {k: program_bounds(grammar.build_program("biped_seated", {"ears": k}, BODY, "b", "t"))[1][2]
           for k in ("round", "long")}
    assert top["long"] > top["round"] * 1.1


def test_mirrored_pairs_are_symmetric() -> None:
    program = _build("quadruped")
    parts = {p.name: p for p in program.parts}
    for name, part in parts.items():
        if name.startswith("left "):
            right = parts["right " + name[5:]]
            tl, tr = part.transform.translation_m, right.transform.translation_m
            assert tl[0] == pytest.approx(tr[0]) and tl[1] == pytest.approx(-tr[1]) and tl[2] == pytest.approx(tr[2])


def test_colours_go_to_parts_by_name_and_group() -> None:
    colors = {"body": (1.0, 0.0, 0.0), "ears": (0.0, 1.0, 0.0), "left front leg": (0.0, 0.0, 1.0)}
    program = grammar.build_program("quadruped", {"ears": "pointed"}, colors, "q", "test")
    by = {p.name: p.color_rgb for p in program.parts}
    assert by["left ear"] == by["right ear"] == (0.0, 1.0, 0.0)
    assert by["left front leg"] == (0.0, 0.0, 1.0) and by["right rear leg"] == (1.0, 0.0, 0.0)
    assert by["left eye"] == grammar.BLACK and by["head"] == (1.0, 0.0, 0.0)


def test_bad_parameters_are_one_line_errors() -> None:
    with pytest.raises(InputError, match="body plan 'quadruped': parameter leg_count"):
        grammar.plan_parameters("quadruped", {"leg_count": 40})
    with pytest.raises(InputError, match="unknown body plan 'hexapod'"):
        grammar.plan_parameters("hexapod")
    with pytest.raises(InputError, match="parameter wings"):
        grammar.plan_parameters("fish", {"wings": True})  # an unknown parameter is refused, not ignored


# ------------------------------------------------------------------ household goods (#35): states, parts, hollows
SHEET_STATES = ["flat", "rolled", "folded", "stacked"]
MAT = {"width": 0.33, "thickness": 0.0033}  # a 183 x 61 x 0.6 cm yoga mat
TOWEL = {"width": 0.5, "thickness": 0.004}  # a 140 x 70 cm bath towel


@pytest.mark.parametrize("shape", ["rect", "round"])
@pytest.mark.parametrize("state", SHEET_STATES)
def test_a_sheet_builds_watertight_in_every_state(state: str, shape: str) -> None:
    mesh = mesh_program(_build("sheet", 0.3, state=state, shape=shape, **MAT), 64)
    assert mesh.is_watertight and mesh.volume > 0


@pytest.mark.parametrize("plan, params", [
    ("pouch", {"port": "iv", "fill": 0.4}), ("pouch", {"port": "cap", "fill": 0.9}), ("pouch", {"port": "spout"}),
    ("glove", {"mitten": True}), ("sock", {"leg_length": 2.0}), ("hat", {"brim": 0.4, "cuff": 0.0}),
    ("hat", {"pompom": True}), ("tool", {"head": "brush"}), ("tool", {"head": "spoon"}),
    ("tool", {"head": "toothbrush", "handle": 0.75}), ("tool", {"head": "scraper", "handle": 0.0}),
    ("tool", {"head": "turner"}), ("mould", {"outline": "heart"}), ("mould", {"outline": "star"}),
    ("mould", {"outline": "square", "columns": 7, "rows": 2}), ("mould", {"outline": "round", "rim": True}),
    ("holey", {"shape": "wedge", "height": 0.3}), ("holey", {"shape": "block", "height": 0.5}), ("layered", {"shape": "wedge", "layers": 3}),
    ("layered", {"shape": "round", "layers": 3, "topping": 0.2}),
])
def test_goods_variants_build_watertight(plan: str, params: dict) -> None:
    program = _build(plan, 0.2, **params)
    names = [p.name for p in program.parts]
    assert len(set(names)) == len(names), names
    mesh = mesh_program(program, 64)
    assert mesh.is_watertight and mesh.volume > 0
    assert mesh.body_count == 1  # one object, not loose pieces


def test_plan_states_name_the_sheet_states_and_no_others() -> None:
    assert grammar.plan_states("sheet") == (*SHEET_STATES, "crumpled", "loop", "twisted", "knotted", "draped")
    # crumpled, loop: test_goods, test_garment_classes; twisted: test_sealed9_classes; knotted: test_sealed10_classes;
    # draped: test_dev17_classes
    assert grammar.plan_states("ball") == () and grammar.plan_states("pouch") == ()
    program = grammar.build_program("sheet", {**MAT, "state": "rolled"}, BODY, "mat", "t", 0.6)
    assert program.parts[0].name == "body"
    with pytest.raises(InputError, match="no state 'sitting'"):
        grammar.state_change("sheet", MAT, 1.83, "sitting")


def test_a_rolled_mat_is_a_roll_of_the_same_sheet() -> None:
    """A 1.83 m mat rolled up: as long as the mat is wide (0.61 m), a diameter much smaller than the mat's length,
    and (with the density factor) the flat mat's mass; its layers show as rings at the ends."""
    change = grammar.state_change("sheet", MAT, 1.83, "rolled")
    assert change.size_m == pytest.approx(0.61, rel=0.05) and change.mass_factor == 1.0
    flat = mesh_program(_build("sheet", 1.83, **MAT), 96)
    rolled = mesh_program(_build("sheet", change.size_m, state="rolled", **MAT), 96)
    length, d1, d2 = rolled.extents
    assert length == pytest.approx(0.61, rel=0.05) and max(d1, d2) < 0.12 * 1.83
    assert max(d1, d2) > 0.08  # a real 6 mm mat rolls to ~13 cm
    assert rolled.volume * change.density_factor == pytest.approx(flat.volume, rel=0.1)
    program = _build("sheet", change.size_m, state="rolled", **MAT)
    assert any(p.name.endswith("ring 1") and p.operation == "subtract" for p in program.parts)


def test_a_folded_towel_is_twice_as_thick_and_half_as_long() -> None:
    change = grammar.state_change("sheet", TOWEL, 1.4, "folded")
    flat = mesh_program(_build("sheet", 1.4, **TOWEL), 96)
    folded = mesh_program(_build("sheet", change.size_m, state="folded", **TOWEL), 96)
    assert folded.extents[0] == pytest.approx(flat.extents[0] / 2, rel=0.08)
    assert folded.extents[1] == pytest.approx(flat.extents[1], rel=0.08)
    assert folded.extents[2] == pytest.approx(2 * flat.extents[2], rel=0.15)
    assert folded.volume == pytest.approx(flat.volume, rel=0.1) and change.density_factor == pytest.approx(1, rel=0.1)
    stack = grammar.state_change("sheet", TOWEL, 1.4, "stacked")
    assert stack.mass_factor == 4 and stack.size_m == pytest.approx(1.4, rel=0.05)


@pytest.mark.parametrize("outline", ["round", "square", "heart", "star"])
def test_a_mould_is_hollow(outline: str) -> None:
    """An open shell: its volume is a small share of the solid its outline encloses (its convex hull here), and the
    middle of the cavity is outside the solid."""
    program = _build("mould", 0.2, outline=outline, height=0.4)
    mesh = mesh_program(program, 64)
    assert mesh.volume < 0.35 * mesh.convex_hull.volume
    b = program_bounds(program)
    centre = np.array([[(b[0][0] + b[1][0]) / 2, (b[0][1] + b[1][1]) / 2, b[1][2] * 0.6]])
    assert program_sdf(centre, program)[0] > 0
    tray = mesh_program(_build("mould", 0.25, outline="square", columns=7, rows=2, height=0.8), 64)
    assert tray.volume < 0.6 * tray.convex_hull.volume  # its walls are built at least 2.5 % of its length


def test_a_glove_has_five_fingers_and_a_mitten_a_thumb() -> None:
    fingers = {"thumb", "index finger", "middle finger", "ring finger", "little finger"}
    glove = _build("glove", 0.25)
    assert fingers <= {p.name for p in glove.parts} and sum(part_group(p.name).endswith("finger")
                                                            for p in glove.parts) == 4
    mitten = {p.name for p in _build("glove", 0.25, mitten=True).parts}
    assert "thumb" in mitten and not (fingers - {"thumb"}) & mitten
    program = grammar.build_program("glove", {}, {"body": (1, 1, 0), "finger": (1, 0, 0)}, "g", "t", 0.25)
    assert {p.color_rgb for p in program.parts if p.name.endswith("finger")} == {(1, 0, 0)}


def test_holey_cheese_has_holes_and_layered_food_its_layers() -> None:
    slice_ = _build("holey", 0.2)
    solid = _build("holey", 0.2, holes=0)
    assert mesh_program(slice_, 64).volume < 0.95 * mesh_program(solid, 64).volume
    cake = _build("layered", 0.12, shape="wedge", layers=3, topping=0.2)
    groups = [part_group(p.name) for p in cake.parts]
    assert groups.count("filling") == 2 and "topping" in groups


def test_quadruped_poses_sit_and_lie() -> None:
    """A sitting animal is taller than long with its chest up; a lying one is low, its head near the ground; both
    are one watertight body, and 'a dog lying down' takes the posable dog's shape."""
    from tasks.geometry.catalogue import design_from_text
    from tasks.geometry.meshing import mesh_program

    ext = {}
    for state in ("standing", "sitting", "lying"):
        d = design_from_text(f"a plush fox {'' if state == 'standing' else state}".strip())
        mesh = mesh_program(d.program, 48)
        assert mesh.is_watertight and mesh.body_count == 1, state
        ext[state] = mesh.extents / mesh.extents.max()
        assert d.concept.states == ([] if state == "standing" else [state])
    assert ext["sitting"][2] > 1.15 * ext["standing"][2]  # upright chest
    assert ext["lying"][2] < 0.8 * ext["standing"][2]  # low on the ground
    dog = design_from_text("a floppy stuffed dog lying down with its head on its paws")
    assert dog.concept.shape_from == "plush_labrador" and dog.concept.states == ["lying"]
