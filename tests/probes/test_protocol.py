"""Drop protocol: plausibility metrics tell a sound material from a collapsing one; renders are deterministic."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.probes.protocol import drop_protocol, plausibility_metrics
from tasks.probes.rollout import DeformableBody


def _cube(edge_m: float = 0.04, n: int = 8, density: float = 300.0) -> DeformableBody:
    s = edge_m / n
    g = (np.arange(n) + 0.5) * s
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3) - [edge_m / 2, edge_m / 2, 0.0]
    return DeformableBody(pts, np.full(len(pts), s ** 3), s, density)


def test_firm_cube_drop_is_plausible_and_keeps_its_shape() -> None:
    arrays, m = drop_protocol(_cube(), Material(youngs_modulus_pa=2e5, poisson_ratio=0.3, damping_rate_per_s=5.0),
                              SimConfig(), duration_s=0.6)
    assert arrays["x_m"].shape == (19, 512, 3) and arrays["F"].shape == (19, 512, 3, 3)
    assert m["healthy"] == 1 and m["plausible"] == 1
    assert m["shape_retention"] > 0.97 and abs(m["volume_ratio_end"] - 1) < 0.05
    assert m["drop_height_m"] == pytest.approx(0.25 * 0.035, rel=0.2)  # a quarter of the particle-extent height


def test_a_material_too_soft_for_its_weight_is_flagged() -> None:
    body = _cube(edge_m=0.06, density=1000.0)
    _, m = drop_protocol(body, Material(youngs_modulus_pa=60.0, poisson_ratio=0.3, damping_rate_per_s=5.0),
                         SimConfig(), duration_s=1.0)
    assert m["plausible"] == 0
    assert m["shape_retention"] < 0.8 or m["collapsed"] == 1 or m["healthy"] == 0


def test_non_finite_frames_count_as_an_explosion() -> None:
    rest = np.random.default_rng(0).random((20, 3))
    x = np.stack([rest, rest * np.nan])
    F = np.tile(np.eye(3), (2, 20, 1, 1))
    m = plausibility_metrics(rest, np.ones(20), x, F, healthy=True)
    assert m["exploded"] == 1 and m["plausible"] == 0


def test_protocol_frames_render_deterministically(tmp_path: Path) -> None:
    from tasks.render.protocol_video import render_protocol_frames, write_mp4

    body = _cube()
    arrays, _ = drop_protocol(body, Material(youngs_modulus_pa=2e5, poisson_ratio=0.3, damping_rate_per_s=5.0),
                              SimConfig(), duration_s=0.2)
    rng = np.random.default_rng(1)
    idx = rng.integers(0, len(body.positions_m), (100, 4))
    gaussians = {"positions_m": body.positions_m[idx[:, 0]], "colors": rng.random((100, 3)),
                 "particle_index": idx, "particle_weight": np.full((100, 4), 0.25)}
    cov = np.tile(np.eye(3) * 1e-5, (100, 1, 1))
    a = render_protocol_frames(gaussians, cov, body.positions_m, arrays["x_m"], arrays["F"], "front", 96, 72)
    b = render_protocol_frames(gaussians, cov, body.positions_m, arrays["x_m"], arrays["F"], "front", 96, 72)
    assert len(a) == len(arrays["x_m"]) and all(np.array_equal(p, q) for p, q in zip(a, b))
    assert a[0].shape == (72, 96, 3) and a[0].std() > 1.0  # something was drawn
    video = write_mp4(a, tmp_path / "drop.mp4", 30.0)
    import imageio.v2 as imageio

    assert imageio.get_reader(video).count_frames() == len(a)


def test_a_tall_body_that_tips_over_has_not_collapsed_but_a_squashed_one_has() -> None:
    """Collapse is judged along the body's own vertical axis: a 1 x 1 x 4 column lying on its side after the drop keeps
    its shape (world height ratio 0.25, body height ratio 1, tilt 90 deg: plausible); the same column squashed to 0.3
    of its height in place has collapsed."""
    g = np.arange(4) * 0.01
    rest = np.stack(np.meshgrid(g[:2], g[:2], np.arange(16) * 0.01, indexing="ij"), -1).reshape(-1, 3)
    lying = np.stack([rest[:, 0], 0.15 - rest[:, 2], rest[:, 1]], axis=1)  # turned 90 deg about x, on the ground
    squashed = rest * [1.8, 1.8, 0.3]
    F = np.tile(np.eye(3), (2, len(rest), 1, 1))
    vol = np.full(len(rest), 1e-6)
    tipped = plausibility_metrics(rest, vol, np.stack([rest, lying]), F, healthy=True)
    assert tipped["height_ratio_end"] < 0.3 and abs(tipped["body_height_ratio_end"] - 1.0) < 1e-9
    assert abs(tipped["tilt_deg_end"] - 90.0) < 1e-6 and tipped["collapsed"] == 0 and tipped["plausible"] == 1
    flat = plausibility_metrics(rest, vol, np.stack([rest, squashed]), F, healthy=True)
    assert flat["body_height_ratio_end"] < 0.5 and flat["collapsed"] == 1 and flat["plausible"] == 0
