"""L1 rigid probes against physical laws: Coulomb friction on an incline, stable rest, tipping, drop."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from tasks.probes.rigid import RigidBodySpec, drop_probe, placement_probe, slide_probe


def _body(mesh: trimesh.Trimesh, mass_kg: float = 0.4, mu: float = 0.5, com_offset=(0.0, 0.0, 0.0)) -> RigidBodySpec:
    return RigidBodySpec([np.asarray(mesh.vertices)], mass_kg, np.asarray(mesh.center_mass) + com_offset, mu)


def _box(sx: float, sy: float, sz: float) -> trimesh.Trimesh:
    m = trimesh.creation.box((sx, sy, sz))
    m.apply_translation((0, 0, sz / 2))
    return m


def _ball(r: float) -> trimesh.Trimesh:
    m = trimesh.creation.icosphere(subdivisions=2, radius=r)
    m.apply_translation((0, 0, r))
    return m


@pytest.mark.parametrize("mu", [0.3, 0.8])
@pytest.mark.parametrize("shape", ["box", "ball"])
def test_slide_sticks_below_and_follows_coulomb_above_friction_angle(mu: float, shape: str) -> None:
    mesh = _box(0.12, 0.1, 0.06) if shape == "box" else _ball(0.04)
    m = slide_probe(_body(mesh, mu=mu), margin_deg=2.0, measure_s=0.6)
    assert m["slide_critical_angle_deg"] == pytest.approx(math.degrees(math.atan(mu)))
    assert m["slide_below_sticks"] == 1.0
    assert m["slide_above_slides"] == 1.0
    assert m["slide_accel_error_rel"] < 0.05


def test_box_rests_stably_without_penetration() -> None:
    m = placement_probe(_body(_box(0.2, 0.15, 0.1)), duration_s=1.0)
    assert m["place_tilt_deg"] < 1.0
    assert m["place_penetration_m"] <= 1e-3
    assert m["place_settle_time_s"] < 0.5


def test_top_heavy_offset_object_tips_over() -> None:
    # a tall slab whose centre of mass sits outside its footprint must fall over
    body = _body(_box(0.03, 0.1, 0.25), com_offset=(0.04, 0.0, 0.0))
    m = placement_probe(body, duration_s=2.0)
    assert m["place_tilt_deg"] > 45.0


def test_drop_from_quarter_height_settles_on_the_ground() -> None:
    mesh = _box(0.1, 0.1, 0.08)
    m = drop_probe(_body(mesh), clearance_fraction=0.25, duration_s=1.5)
    assert m["drop_clearance_m"] == pytest.approx(0.02, rel=1e-6)
    assert m["drop_penetration_m"] <= 1e-3
    assert m["drop_tilt_deg"] < 2.0
    assert math.isfinite(m["drop_settle_time_s"])
