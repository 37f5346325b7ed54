"""Convex-polytope colliders (the convex hull of points, e.g. a CoACD part): exact contact, clear errors."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from contracts.errors import InputError
from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import Simulator, box_collider, build_model, convex_collider
from tasks.mpm.scene import box_scene

MAT = Material(youngs_modulus_pa=5e4, poisson_ratio=0.3, damping_rate_per_s=5.0)
TABLE_HALF = (0.08, 0.08, 0.02)
CORNERS = np.array(list(itertools.product(*[(-h, h) for h in TABLE_HALF])))


def _drop_on(collider, device: str = "cpu") -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """A 3 cm block dropped from 1 cm onto a tilted slab (no ground): final positions and the mean slab force."""
    scene = box_scene((-0.015, -0.015, 0.13), (0.015, 0.015, 0.16), 0.0025, MAT, 300.0, colliders=[collider],
                      ground=False)
    model = build_model([scene], SimConfig(device=device, grid_margin_m=0.02))
    sim = Simulator(model)
    sim.advance(0.3)
    rep = sim.advance(0.1)
    return sim.particles(0)["x"], np.asarray(rep.collider_force(model, 0, 0))


def test_a_box_as_a_convex_hull_gives_the_box_rollout_bit_for_bit() -> None:
    tilt = (0.0, math.sin(0.05), 0.0, math.cos(0.05))  # 5.7 degrees about y
    pose = dict(position_m=(0.0, 0.0, 0.1), rotation_xyzw=tilt, friction=0.9)
    x_box, f_box = _drop_on(box_collider(TABLE_HALF, **pose))
    x_hull, f_hull = _drop_on(convex_collider(CORNERS, **pose))
    np.testing.assert_array_equal(x_hull, x_box)
    np.testing.assert_array_equal(f_hull, f_box)
    # at rest on the slab (mu 0.9 > tan 5.7 deg): the object pushes on it with its weight, straight down
    mg = 300.0 * 0.03 ** 3 * 9.81
    assert abs(f_hull[2] + mg) < 0.05 * mg and np.hypot(f_hull[0], f_hull[1]) < 0.05 * mg


def test_a_wedge_hull_deflects_the_block_along_its_face() -> None:
    """A frictionless wedge (a non-box hull): the block slides down its 30 degree face, away from the ridge."""
    pts = np.array([[-0.1, -0.1, 0.0], [-0.1, 0.1, 0.0], [0.1, -0.1, 0.0], [0.1, 0.1, 0.0],
                    [-0.1, -0.1, 0.2 * math.tan(math.radians(30))], [-0.1, 0.1, 0.2 * math.tan(math.radians(30))]])
    wedge = convex_collider(pts, position_m=(0.0, 0.0, 0.0), friction=0.0)
    assert len(wedge.planes) == 5  # 2 triangles per rectangle merged: bottom, back, slope, two sides
    scene = box_scene((-0.015, -0.015, 0.125), (0.015, 0.015, 0.155), 0.0025, MAT, 300.0, colliders=[wedge],
                      ground=False)
    model = build_model([scene], SimConfig(device="cpu", grid_margin_m=0.03))
    sim = Simulator(model)
    x0 = sim.particles(0)["x"].mean(axis=0)
    sim.advance(0.25)
    x1 = sim.particles(0)["x"].mean(axis=0)
    assert x1[0] - x0[0] > 0.01  # pushed towards +x, down the slope
    assert abs(x1[1] - x0[1]) < 1e-3


@pytest.mark.parametrize("pts, message", [
    (np.zeros((3, 3)), ">= 4 finite points"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]]), "spanning a volume"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]]), ">= 4 finite points"),
])
def test_degenerate_hulls_are_refused(pts: np.ndarray, message: str) -> None:
    with pytest.raises(InputError, match=message):
        convex_collider(pts)


@pytest.mark.gpu
def test_convex_hull_on_cuda_matches_the_cpu() -> None:
    tilt = (0.0, math.sin(0.05), 0.0, math.cos(0.05))
    pose = dict(position_m=(0.0, 0.0, 0.1), rotation_xyzw=tilt, friction=0.9)
    x_cpu, f_cpu = _drop_on(convex_collider(CORNERS, **pose))
    x_gpu, f_gpu = _drop_on(convex_collider(CORNERS, **pose), device="cuda")
    assert np.max(np.abs(x_gpu - x_cpu)) < 1e-4
    assert np.linalg.norm(f_gpu - f_cpu) < 0.02 * np.linalg.norm(f_cpu)
