"""The resting-pose search rolls over a thinned hull for smooth bodies: the same pose as the full hull's."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from tasks.geometry.canonical import POSE_HULL_CELLS, most_stable_rotation, pose_hull


def _rest_height(mesh: trimesh.Trimesh, tf: np.ndarray) -> float:
    """Height of the centre of mass above the table in a resting pose [m] (equal for poses rolled about an axis)."""
    moved = mesh.copy()
    moved.apply_transform(tf)
    return float(moved.center_mass[2] - moved.bounds[0][2])


def _full_hull_pose(mesh: trimesh.Trimesh) -> np.ndarray:
    """trimesh's own search over the whole hull."""
    tfs, probs = trimesh.poses.compute_stable_poses(mesh, sigma=0.0, n_samples=1)
    return np.asarray(tfs[int(np.argmax(probs))])


def _smooth_bodies() -> list[trimesh.Trimesh]:
    """Smooth bodies with thousands of hull facets: a lying egg, a tilted capsule, a cone."""
    egg = trimesh.creation.icosphere(subdivisions=4)
    egg.vertices *= [0.05, 0.035, 0.03]
    egg.vertices[:, 0] += 0.02 * (egg.vertices[:, 0] > 0) * egg.vertices[:, 0] / 0.05
    capsule = trimesh.creation.capsule(height=0.12, radius=0.03, count=[48, 48])
    capsule.apply_transform(trimesh.transformations.rotation_matrix(0.7, [1, 0.3, 0]))
    cone = trimesh.creation.cone(radius=0.04, height=0.1, sections=1024)
    return [egg, capsule, cone]


@pytest.mark.parametrize("index", range(3))
def test_thinned_hull_finds_the_full_hulls_pose(index: int) -> None:
    mesh = _smooth_bodies()[index]
    assert len(mesh.convex_hull.faces) > 2 * POSE_HULL_CELLS**2  # the thinned path is taken
    assert len(pose_hull(mesh).faces) < len(mesh.convex_hull.faces) / 2
    ours, full = _rest_height(mesh, most_stable_rotation(mesh)), _rest_height(mesh, _full_hull_pose(mesh))
    assert ours == pytest.approx(full, rel=0.03)


def test_a_box_keeps_its_exact_hull() -> None:
    box = trimesh.creation.box([0.1, 0.04, 0.02])
    assert len(pose_hull(box).faces) == len(box.convex_hull.faces)
    up = np.linalg.inv(most_stable_rotation(box))[:3, 2]
    assert abs(abs(up[2]) - 1.0) < 1e-9  # lies on its largest face
