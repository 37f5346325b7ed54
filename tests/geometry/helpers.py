"""Shared builders for the geometry tests: fast settings, synthetic photographs, one-call L0 runs."""

from __future__ import annotations

import cv2
import numpy as np

from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources

FAST_COACD = dict(preprocess_resolution=20, max_convex_hull=8, threshold=0.15, mcts_iterations=30, mcts_nodes=8,
                  mcts_max_depth=2, resolution=500, max_input_faces=3000)


def settings(quality: str = "draft", **coacd: object) -> pipeline.L0Settings:
    """Contract settings with CoACD overrides (e.g. method='hull' for speed)."""
    return pipeline.settings_from_contract(quality, coacd_overrides=coacd or None)  # type: ignore[arg-type]


def run(request: AssetRequest, s: pipeline.L0Settings) -> tuple:
    """All L0 units in order: (mesh, info, proxy, particles, gaussians, checks)."""
    mesh, info = sources.build_mesh(request, s)
    proxy = pipeline.build_proxy(mesh, s.coacd)
    particles = pipeline.build_particles(mesh, s.particles)
    gaussians = pipeline.build_gaussians(mesh, particles, s)
    checks = pipeline.check_geometry(mesh, proxy, particles, gaussians)
    return mesh, info, proxy, particles, gaussians, checks


def object_mask(h: int = 480, w: int = 640) -> np.ndarray:
    """Ground-truth silhouette: a turtle-ish body with a head and four flippers."""
    m = np.zeros((h, w), np.uint8)
    cv2.ellipse(m, (w // 2, h // 2), (150, 90), 0, 0, 360, 1, -1)
    cv2.circle(m, (w // 2 + 175, h // 2 - 20), 45, 1, -1)
    for dx, dy in ((-110, 80), (110, 80), (-120, -75), (120, -75)):
        cv2.ellipse(m, (w // 2 + dx, h // 2 + dy), (40, 22), 30 if dx * dy > 0 else -30, 0, 360, 1, -1)
    return m.astype(bool)


def cluttered_photo(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """BGR photo-like image: a green textured object on a noisy, cluttered table; returns (image, true mask)."""
    rng = np.random.default_rng(seed)
    h, w = 480, 640
    img = (rng.normal(0, 12, (h, w, 3)) + np.array([150, 160, 170])).clip(0, 255).astype(np.uint8)
    for _ in range(60):  # clutter: random objects on the table, also near the object
        c = tuple(int(v) for v in rng.integers(0, 256, 3))
        if c[1] > c[0] + 30 and c[1] > c[2] + 30:
            c = (c[0], c[0], c[2])  # no green clutter (the object is the only green thing)
        x, y = int(rng.integers(0, w)), int(rng.integers(0, h))
        if rng.random() < 0.5:
            cv2.rectangle(img, (x, y), (x + int(rng.integers(10, 60)), y + int(rng.integers(10, 60))), c, -1)
        else:
            cv2.circle(img, (x, y), int(rng.integers(5, 30)), c, -1)
    mask = object_mask(h, w)
    tex = np.zeros((h, w, 3), np.float64)
    yy, xx = np.mgrid[:h, :w]
    shade = 0.75 + 0.25 * np.sin(xx / 9.0) * np.sin(yy / 11.0)
    tex[..., 0], tex[..., 1], tex[..., 2] = 40 * shade, 170 * shade, 50 * shade  # BGR: green
    tex += rng.normal(0, 6, tex.shape)
    img[mask] = tex[mask].clip(0, 255).astype(np.uint8)
    img = cv2.GaussianBlur(img, (3, 3), 0)
    return img, mask


def parts_by_group(program) -> dict[str, list]:  # noqa: ANN001
    """A shape program's parts by their part group ('left ear' and 'right ear' -> 'ear')."""
    from tasks.geometry.grammar.parts import part_group

    out: dict[str, list] = {}
    for p in program.parts:
        out.setdefault(part_group(p.name), []).append(p)
    return out


def designs(texts: dict[str, str]) -> dict[str, tuple]:
    """name -> (lexicon entry, shape program) of each text as design_from_text reads and builds it."""
    from tasks.geometry import catalogue

    return {k: (d.entry, d.program) for k, d in ((k, catalogue.design_from_text(t)) for k, t in texts.items())}
