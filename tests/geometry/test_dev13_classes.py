"""Classes development set 13 (120 prompts written in session 27 by two reviewers who never opened the repository)
found missing, misread or slow (#35), fixed by class and checked here on other phrasings than the set's.

Real masses: typical retail or rule figures (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from contracts.request import AssetRequest
from tasks.geometry.collision import convex_parts
from tasks.geometry.pipeline import proxy_parts
from tasks.probes.rigid import RigidBodySpec, placement_probe
from tests.geometry.helpers import run, settings


@pytest.mark.parametrize("text", ["a ball of chunky yarn", "a yarn pom pom"])
def test_a_grooved_near_convex_object_is_proxied_by_its_hull(text: str) -> None:
    """A yarn ball's grooves kept CoACD splitting into its whole budget (40 s on a core): its hull covers it."""
    s = settings("draft")
    mesh, _info, proxy, _p, _g, checks = run(AssetRequest(text=text), s)
    assert len(proxy["part_vertex_count"]) == 1
    # the hull's own excess (<= 1/0.93) and CoACD's remeshing (a few percent: its voxel copy is slightly fuller)
    assert 1.0 <= checks.metrics["proxy_volume_ratio"] <= 1.15


@pytest.mark.parametrize("text", ["a stress ball", "a peach"])
def test_a_round_object_proxied_by_one_hull_settles_on_the_table(text: str) -> None:
    """The hull is CoACD's faceted root hull: the smooth hull of every vertex of a ball kept rolling in pybullet and
    failed L1's settle gate (11 of 40 throughput requests in one run)."""
    _mesh, _info, proxy, particles, _g, _c = run(AssetRequest(text=text), settings("draft"))
    hulls = proxy_parts(proxy)
    assert len(hulls) == 1
    body = RigidBodySpec(hulls_m=[h.vertices for h in hulls], mass_kg=0.1,
                         center_of_mass_m=np.asarray(hulls[0].center_mass), friction=0.6)
    m = placement_probe(body, duration_s=3.0)
    assert m["place_settle_time_s"] < 2.0


def test_a_concave_object_is_still_decomposed() -> None:
    """A C-shaped body (volume ~0.5 of its hull) is not replaced by its hull."""
    ring = trimesh.creation.annulus(r_min=0.03, r_max=0.05, height=0.02)
    half = ring.slice_plane([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], cap=True)
    parts = convex_parts(half, settings("draft").coacd)
    assert len(parts) > 1
    assert sum(p.volume for p in parts) < 1.3 * half.volume
