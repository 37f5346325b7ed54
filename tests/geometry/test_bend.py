"""A long object said bent is drawn bent, with its length and volume kept (#35: 'a green pool noodle bent into a U'
was a straight tube, named a drinking straw)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from contracts.request import AssetRequest
from tasks.geometry.bend import bend_along_length, can_bend, stated_bend
from tasks.geometry.pipeline import arrays_to_mesh, mesh_from_text, settings_from_contract


@pytest.mark.parametrize(("text", "degrees"), [
    ("a green pool noodle bent into a U", 180), ("a U-shaped foam bolster", 180), ("a sausage bent in half", 180),
    ("a rubber hose bent double", 180), ("a foam tube bent at a right angle", 90), ("an L-shaped foam strip", 90),
    ("a slightly bent licorice rope", 60), ("a horseshoe-shaped draught excluder", 180),
    ("a pool noodle folded into a U shape", 180)])
def test_the_words_give_the_angle(text: str, degrees: float) -> None:
    bend = stated_bend(text)
    assert bend is not None and math.degrees(bend.angle_rad) == pytest.approx(degrees)


@pytest.mark.parametrize("text", ["a curved banana", "a cat curled up asleep", "a pool noodle", "a bend in the road",
                                  "an arched foam bridge", "a bus pillow"])
def test_no_bend_is_read_where_none_is_said(text: str) -> None:
    assert stated_bend(text) is None


def test_a_bend_keeps_the_length_and_the_volume() -> None:
    """A 1 m x 6 cm rod bent by 180 deg: a U whose chord is 2 R + d and depth R + d / 2 with R = L / pi, of the same
    volume (to the marching of its facets) and still watertight."""
    rod = trimesh.creation.cylinder(radius=0.03, height=1.0, sections=24)
    rod.apply_transform(trimesh.transformations.rotation_matrix(math.pi / 2, [0, 1, 0]))
    for _ in range(5):
        rod = rod.subdivide()  # (watertight: 3 cm along the length)
    rod.apply_translation(-rod.bounds[0] * [0, 0, 1])
    bent = bend_along_length(rod, math.pi)
    radius = 1.0 / math.pi
    assert bent.extents[0] == pytest.approx(2 * radius + 0.06, rel=0.02)
    assert bent.extents[1] == pytest.approx(radius + 0.03, rel=0.03)
    assert bent.extents[2] == pytest.approx(0.06, rel=1e-6) and bent.bounds[0][2] == pytest.approx(0.0, abs=1e-12)
    assert bent.is_watertight and bent.volume == pytest.approx(rod.volume, rel=0.01)
    assert np.abs(bent.bounds.mean(axis=0)[:2]).max() < 1e-9


def test_only_long_objects_bend() -> None:
    assert can_bend(np.array([1.5, 0.065, 0.065])) and not can_bend(np.array([0.3, 0.1, 0.1]))


def test_a_pool_noodle_bent_into_a_u_is_built_as_a_u_of_the_straight_ones_mass() -> None:
    """The lexicon's 1.5 m pool noodle bent into a U: a U 2 x 1.5 / pi across (not a 1.5 m rod), its volume the straight
    noodle's, and the record saying so."""
    settings = settings_from_contract("draft")
    straight, _ = mesh_from_text(AssetRequest(text="a green pool noodle"), settings)
    arrays, info = mesh_from_text(AssetRequest(text="a green pool noodle bent into a U"), settings)
    a, b = arrays_to_mesh(straight), arrays_to_mesh(arrays)
    length = float(a.extents.max())
    assert b.extents.max() == pytest.approx(2 * length / math.pi + a.extents[1], rel=0.04)
    assert sorted(b.extents)[1] == pytest.approx(length / math.pi + a.extents[1] / 2, rel=0.05)
    assert b.volume == pytest.approx(a.volume, rel=0.02)
    assert info.reoriented and any("bent by 180 deg" in n for n in info.notes)
    assert info.concept is not None and info.concept.typical_mass_range_kg is not None
    lo, hi = info.concept.typical_mass_range_kg
    assert lo < info.concept.typical_mass_kg < hi  # the straight noodle's range, not a 0.6x-long one's


def test_a_short_object_said_bent_is_not_bent_and_says_so() -> None:
    _, info = mesh_from_text(AssetRequest(text="a squishy foam ball bent in half"), settings_from_contract("draft"))
    assert any("not long enough to bend" in n for n in info.notes) and not info.reoriented
