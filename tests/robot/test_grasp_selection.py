"""Antipodal grasp selection on analytic shapes: narrow side of a box, through a sphere's centre, none when too wide."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from tasks.robot.grasp import NoGraspError, select_grasps


def _box(sx: float, sy: float, sz: float, n: int = 2500) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    mesh = trimesh.creation.box((sx, sy, sz))
    mesh.apply_translation((0, 0, sz / 2))
    pts, faces = trimesh.sample.sample_surface_even(mesh, n, seed=1)
    return pts, mesh.face_normals[faces], np.asarray(mesh.center_mass)


def _ball(r: float, n: int = 2500) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(2)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * r + [0, 0, r], d, np.array([0.0, 0.0, r])


def test_box_is_grasped_across_its_narrow_side() -> None:
    sel = select_grasps(*_box(0.05, 0.12, 0.06), friction=0.5, seed=0)
    assert sel.ok and len(sel.candidates) >= 3
    best = sel.best()
    assert abs(best.closing_axis[0]) > 0.99 and best.width_m == pytest.approx(0.05, abs=1e-3)
    assert best.approach_axis == pytest.approx((0.0, 0.0, -1.0), abs=1e-3)
    assert np.linalg.norm(np.subtract(best.center_m, (0, 0, 0.03))) < 0.01  # near the centre of mass
    for g in sel.candidates:
        assert g.width_m <= 0.08 and abs(g.closing_axis[1]) < 0.5  # never across the 0.12 m side
        assert g.friction_cone_ok
    assert [g.rank for g in sel.candidates] == list(range(len(sel.candidates)))
    assert all(a.score >= b.score for a, b in zip(sel.candidates, sel.candidates[1:]))


def test_sphere_is_grasped_antipodally_through_its_centre() -> None:
    sel = select_grasps(*_ball(0.03), friction=0.5, seed=0)
    best = sel.best()
    c, u = np.asarray(best.center_m), np.asarray(best.closing_axis)
    centre = np.array([0, 0, 0.03])
    off_line = np.linalg.norm((centre - c) - ((centre - c) @ u) * u)
    assert off_line < 3e-3 and np.linalg.norm(c - centre) < 3e-3
    assert best.width_m == pytest.approx(0.06, abs=1.5e-3)
    assert abs(u[2]) < 0.1  # horizontal closing: a top-down grasp


def test_object_wider_than_the_opening_everywhere_has_no_grasp() -> None:
    sel = select_grasps(*_box(0.1, 0.12, 0.1), friction=0.5, seed=0)
    assert not sel.ok and sel.candidates == []
    assert sel.reason.startswith("no grasp") and "wider than the gripper" in sel.reason
    with pytest.raises(NoGraspError, match="no grasp"):
        sel.best()


def test_friction_cone_prunes_more_with_lower_friction() -> None:
    data = _box(0.05, 0.12, 0.06)
    low, high = select_grasps(*data, friction=0.1, seed=0), select_grasps(*data, friction=1.0, seed=0)
    assert low.counts["cone_ok"] < high.counts["cone_ok"]
    assert low.counts["table_ok"] < high.counts["table_ok"]
    assert len(low.candidates) <= len(high.candidates)


def test_flat_object_too_low_for_the_fingertips() -> None:
    sel = select_grasps(*_box(0.05, 0.05, 0.01), friction=0.5, seed=0)
    assert not sel.ok and "table" in sel.reason


def test_selection_is_deterministic_for_a_seed() -> None:
    data = _ball(0.03)
    a, b = select_grasps(*data, friction=0.5, seed=7), select_grasps(*data, friction=0.5, seed=7)
    assert [g.canonical_json() for g in a.candidates] == [g.canonical_json() for g in b.candidates]
