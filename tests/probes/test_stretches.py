"""The closed-form principal stretches that L2's impact strain and L3's strain labels are computed from."""

import numpy as np

from tasks.probes.metrics import compressive_strain, extreme_stretches


def _gradients() -> np.ndarray:
    rng = np.random.default_rng(3)
    F = np.eye(3) + 0.3 * rng.standard_normal((5000, 3, 3))
    c, s = np.cos(0.7), np.sin(0.7)
    special = [np.eye(3), 1.3 * np.eye(3),                                   # no strain; a uniform stretch (C = q I)
               np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]]),               # a rotation
               np.diag([0.2, 1.0, 1.0]), np.diag([1.0, 2.0, 2.0]),           # repeated singular values
               np.diag([-1.0, 1.0, 1.0]),                                    # a reflection (det < 0)
               np.diag([1e-4, 1.0, 3.0]), np.zeros((3, 3))]                  # nearly and fully collapsed
    return np.concatenate([F, np.stack(special)])


def test_extreme_stretches_are_the_singular_values_of_a_batched_svd() -> None:
    F = _gradients()
    sv = np.linalg.svd(F, compute_uv=False)
    lo, hi = extreme_stretches(F)
    err = np.maximum(np.abs(lo - sv[:, -1]), np.abs(hi - sv[:, 0]))
    # the trigonometric form loses half the digits where two eigenvalues of F^T F coincide (arccos near +-1):
    # ~1e-9 there, and a stretch near 0 is the root of a tiny eigenvalue (1e-4: ~1e-11); far below any strain
    # threshold either way, and 1e-12 everywhere else
    assert np.max(err) < 1e-8
    ordinary = (np.min(np.abs(np.diff(sv, axis=1)), axis=1) > 1e-3) & (sv[:, -1] > 0.05)
    assert ordinary.sum() > 4000 and np.max(err[ordinary]) < 1e-12


def test_extreme_stretches_keep_the_leading_shape_and_take_float32() -> None:
    F = _gradients()[:4000].reshape(40, 100, 3, 3)
    lo, hi = extreme_stretches(F.astype(np.float32))
    assert lo.shape == hi.shape == (40, 100) and lo.dtype == np.float64
    sv = np.linalg.svd(F.astype(np.float32).astype(np.float64), compute_uv=False)
    assert np.allclose(lo, sv[..., -1], atol=1e-12) and np.allclose(hi, sv[..., 0], atol=1e-12)


def test_compressive_strain_counts_shortening_only() -> None:
    F = np.stack([np.diag([0.7, 1.0, 1.0]), np.diag([1.4, 1.0, 1.0]), np.eye(3)])
    assert np.allclose(compressive_strain(F), [0.3, 0.0, 0.0], atol=1e-12)
