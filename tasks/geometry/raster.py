"""Winding numbers of a mesh on a lattice, column by column (the triangle / column overlap: tasks.render.columns)."""

from __future__ import annotations

import numpy as np

from tasks.render.columns import triangle_column_pairs


def lattice_winding(
    vertices: np.ndarray, faces: np.ndarray, origin: np.ndarray, spacing: float, shape: tuple[int, ...]
) -> tuple[np.ndarray, float]:
    """Winding number of an outward-oriented mesh at lattice points (shape (nx, ny, nz)), and the fraction of unbalanced
    columns (open mesh)."""
    nx, ny, nz = shape
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(faces)]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    nz_sign = np.sign(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    cols, zs, contrib = [], [], []
    for t, ix, iy, w in triangle_column_pairs(tri[:, :, :2], origin[:2], spacing, (nx, ny)):
        cols.append(ix * ny + iy)
        zs.append(np.einsum("ij,ij->i", w, tri[t, :, 2]))
        contrib.append(-nz_sign[t])
    winding = np.zeros((nx, ny, nz), dtype=np.int32)
    if not cols:
        return winding, 0.0
    col = np.concatenate(cols)
    z = np.concatenate(zs)
    con = np.concatenate(contrib)
    zmin = min(float(z.min()), float(origin[2])) - 1.0
    span = max(float(z.max()), float(origin[2] + nz * spacing)) - zmin + 1.0
    key = col * span + (z - zmin)
    order = np.argsort(key, kind="stable")
    key, con, col = key[order], con[order], col[order]
    cs = np.concatenate([[0.0], np.cumsum(con)])
    col_net = np.bincount(col, weights=con, minlength=nx * ny)
    touched = np.bincount(col, minlength=nx * ny) > 0
    unbalanced = float(np.count_nonzero(np.abs(col_net) > 0.5)) / max(int(touched.sum()), 1)
    zq = origin[2] + np.arange(nz) * spacing - zmin
    all_cols = np.arange(nx * ny)
    col_start = np.searchsorted(key, all_cols * span)
    for c0 in range(0, nx * ny, max(1, 2_000_000 // max(nz, 1))):
        cs_ = all_cols[c0 : c0 + max(1, 2_000_000 // max(nz, 1))]
        q = cs_[:, None] * span + zq[None, :]
        idx = np.searchsorted(key, q)
        wn = cs[idx] - cs[col_start[cs_]][:, None]
        winding.reshape(nx * ny, nz)[cs_] = np.rint(wn).astype(np.int32)
    return winding, unbalanced
