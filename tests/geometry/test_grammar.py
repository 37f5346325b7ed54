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
