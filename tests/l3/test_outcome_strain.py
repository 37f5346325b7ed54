"""The trial's strain label: largest |principal stretch - 1| over deformation gradients, as an SVD gives it."""

from __future__ import annotations

import numpy as np

from tasks.manipulation.outcome import max_principal_strain


def test_closed_form_matches_svd_for_rest_small_and_large_deformations() -> None:
    rng = np.random.default_rng(1)
    for scale in (0.0, 1e-4, 0.05, 0.4):
        F = np.eye(3) + scale * rng.standard_normal((5000, 3, 3))
        s = np.linalg.svd(F, compute_uv=False)
        assert abs(max_principal_strain(F) - float(np.max(np.abs(s - 1.0)))) < 1e-9


def test_pure_stretch_and_compression_and_nan() -> None:
    assert abs(max_principal_strain(np.diag([1.3, 1.0, 1.0])[None]) - 0.3) < 1e-12
    assert abs(max_principal_strain(np.diag([1.0, 0.6, 1.1])[None]) - 0.4) < 1e-12
    rot = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert max_principal_strain(rot[None]) < 1e-12  # a rotation is no strain
    assert np.isnan(max_principal_strain(np.full((1, 3, 3), np.nan)))


def test_bulk_strain_ignores_a_lone_rim_particle_but_not_a_deformed_volume() -> None:
    from tasks.manipulation.outcome import bulk_strain

    n = 1000
    F = np.repeat(np.diag([0.9, 1.0, 1.0])[None], n, axis=0)  # 0.1 compression everywhere
    F[7] = np.diag([0.1, 1.0, 1.0])                           # one particle at 0.9 (a pad rim)
    frames = np.stack([np.repeat(np.eye(3)[None], n, axis=0), F])
    assert abs(max_principal_strain(frames) - 0.9) < 1e-9
    assert abs(bulk_strain(frames) - 0.1) < 1e-9               # 0.1 % of the volume is beyond 0.1: within 1 %
    # the same particle carrying 5 % of the volume is 5 % of the object deformed by 0.9: the bound sees it
    vol = np.ones(n)
    vol[7] = 0.05 * (n - 1) / 0.95
    assert abs(bulk_strain(frames, vol) - 0.9) < 1e-9
    F[:20] = np.diag([1.5, 1.0, 1.0])                          # 2 % of particles stretched by 0.5
    assert abs(bulk_strain(F[None]) - 0.5) < 1e-9
    assert np.isnan(bulk_strain(np.full((1, 2, 3, 3), np.nan)))
