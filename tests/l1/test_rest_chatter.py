"""L1's rest test on a body that chatters between contacts: L0's sausage lying on its cylinder-like convex proxy stays
still while pybullet reports a steady 0.08 rad/s for it (it swaps contact points every step, there and back); at rest
is the pose's net change over a short window (tasks.probes.rigid.REST_WINDOW_S), so it settles at once and passes L1's
settle gate, which it failed in every throughput run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tasks.probes import rigid

HULL = Path(__file__).parent / "fixtures" / "sausage_hull.txt"
SAUSAGE_COM_M = (8.153426112403951e-09, -5.105423409182668e-07, 0.01090370048151144)  # its built mesh's centre of mass


@pytest.mark.parametrize("probe", ["place", "drop"])
def test_a_sausage_resting_on_its_proxy_settles_at_once(probe: str) -> None:
    body = rigid.RigidBodySpec(hulls_m=[np.loadtxt(HULL)], mass_kg=0.053, center_of_mass_m=SAUSAGE_COM_M, friction=0.5)
    out = rigid.placement_probe(body) if probe == "place" else rigid.drop_probe(body)
    assert out[f"{probe}_settle_time_s"] < 0.5
    assert out[f"{probe}_tilt_deg"] < 1.0


def test_a_body_still_rolling_does_not_settle() -> None:
    """A cylinder balanced on an edge of its polygon rolls off it and on without end (no rolling resistance in the
    rigid probe): never at rest, so the settle time is infinite, as before."""
    import trimesh  # lazy: only this test builds a mesh

    hull = trimesh.creation.cylinder(radius=0.011, height=0.143, sections=20)
    hull.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (0, 1, 0)))  # on an edge
    body = rigid.RigidBodySpec(hulls_m=[np.asarray(hull.vertices)], mass_kg=0.053,
                               center_of_mass_m=tuple(hull.center_mass), friction=0.5)
    assert rigid.placement_probe(body)["place_settle_time_s"] == float("inf")


BANANA = [Path(__file__).parent / "fixtures" / f"banana_hull_{k}.txt" for k in range(2)]
BANANA_COM_M = (-0.0036132137388843353, 2.7787464479442573e-06, 0.022374306661936513)  # its built mesh's


@pytest.mark.parametrize("friction", [0.5, 1.0])
def test_a_banana_still_rocking_when_its_rotation_is_locked_sticks_below_the_friction_angle(friction: float) -> None:
    """The slide probe locks rotation by a huge inertia after 0.3 s; L0's banana was still rocking then, kept that
    spin (0.17 rad/s) through the lock and crept up the incline below atan(mu): the lock now starts it still."""
    body = rigid.RigidBodySpec(hulls_m=[np.loadtxt(p) for p in BANANA], mass_kg=0.12, center_of_mass_m=BANANA_COM_M,
                               friction=friction)
    out = rigid.slide_probe(body)
    assert out["slide_below_sticks"] == 1.0 and out["slide_above_slides"] == 1.0
    assert out["slide_accel_error_rel"] < 0.05  # a = g (sin - mu cos) above the angle
