"""Gaussians bound to particles, deformed state by state (tasks.render.binding's Warp kernels): the formulas of the
numpy code they replace, x_g = sum w (x_j + F_j (X_g - X_j)), F_g Σ F_gᵀ and F_g^-T n, to float64 rounding."""

from __future__ import annotations

import numpy as np

from tasks.render.binding import Binding, blended_gradients


def normals_under(rest_normals: np.ndarray, blended: np.ndarray) -> np.ndarray:
    """The numpy formula the kernel replaced (the reference): unit F_g^-T n; a zero rest normal stays zero, a
    singular F_g leaves the rest normal as it was."""
    n = np.asarray(rest_normals, np.float64)
    F_g = np.asarray(blended, np.float64)
    det = np.linalg.det(F_g)
    ok = np.isfinite(det) & (np.abs(det) > 1e-9)
    out = n.copy()
    if np.any(ok):
        out[ok] = np.linalg.solve(np.swapaxes(F_g[ok], 1, 2), n[ok][:, :, None])[:, :, 0]
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return np.where(length > 1e-12, out / np.maximum(length, 1e-12), 0.0)


def test_a_state_deforms_centres_covariances_and_normals_as_the_formulas_say() -> None:
    rng = np.random.default_rng(7)
    n, g, k = 50, 400, 4
    rest = rng.normal(0.0, 0.05, (n, 3))
    idx = rng.integers(0, n, (g, k))
    w = rng.uniform(0.1, 1.0, (g, k))
    w /= w.sum(axis=1, keepdims=True)
    X = rest[idx[:, 0]] + rng.normal(0.0, 0.004, (g, 3))
    a = rng.normal(0.0, 0.002, (g, 3, 3))
    S = a @ a.transpose(0, 2, 1)
    x = rest + rng.normal(0.0, 0.01, (n, 3))
    F = (np.eye(3) + rng.normal(0.0, 0.2, (n, 3, 3))).astype(np.float32)
    F[3] = 0.0  # a singular particle: a Gaussian on it alone keeps its rest normal
    idx[0], w[0] = 3, 0.25
    state = Binding.of(X, S, idx, w, rest).deform(x, F)
    F64 = F.astype(np.float64)[idx]
    moved = x[idx] + np.einsum("gkij,gkj->gki", F64, X[:, None, :] - rest[idx])
    F_g = np.einsum("gk,gkij->gij", w, F64)
    assert np.allclose(state.centres_m, np.einsum("gk,gki->gi", w, moved), rtol=0, atol=1e-15)
    assert np.allclose(state.gradients, F_g, rtol=0, atol=1e-14)
    assert np.allclose(state.covariances_m2, np.einsum("gij,gjk,glk->gil", F_g, S, F_g), rtol=0, atol=1e-18)
    normals = rng.normal(0.0, 1.0, (g, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals[1] = 0.0  # an interior blob: no normal
    got = Binding.normals(normals, state.gradients)
    assert np.allclose(got, normals_under(normals, F_g), rtol=0, atol=1e-12)
    assert np.array_equal(got[0], normals[0]) and np.array_equal(got[1], np.zeros(3))
    assert np.allclose(blended_gradients(idx, w, F), F_g, rtol=0, atol=0)
