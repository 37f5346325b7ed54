"""Triangle / lattice-column overlap: the one vectorised kernel behind inside tests and CPU renders."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

_MAX_PAIRS = 4_000_000  # pairs handled per chunk (bounds memory)


def triangle_column_pairs(
    tri_xy: np.ndarray, origin: np.ndarray, spacing: float, shape: tuple[int, int]
) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Yield (triangle, ix, iy, barycentric) for lattice points origin + i*spacing inside each 2-D triangle."""
    tri_xy = np.asarray(tri_xy, dtype=np.float64)
    nx, ny = shape
    lo = (tri_xy.min(axis=1) - origin) / spacing
    hi = (tri_xy.max(axis=1) - origin) / spacing
    i0 = np.clip(np.ceil(lo[:, 0]), 0, nx).astype(np.int64)
    i1 = np.clip(np.floor(hi[:, 0]), -1, nx - 1).astype(np.int64)
    j0 = np.clip(np.ceil(lo[:, 1]), 0, ny).astype(np.int64)
    j1 = np.clip(np.floor(hi[:, 1]), -1, ny - 1).astype(np.int64)
    ni = np.maximum(i1 - i0 + 1, 0)
    nj = np.maximum(j1 - j0 + 1, 0)
    counts = ni * nj
    a, b, c = tri_xy[:, 0], tri_xy[:, 1], tri_xy[:, 2]
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    counts[np.abs(area2) < 1e-300] = 0
    todo = np.flatnonzero(counts)
    csum = np.cumsum(counts[todo])
    start = 0
    while start < len(todo):
        base = csum[start - 1] if start else 0
        stop = int(np.searchsorted(csum, base + _MAX_PAIRS, side="right"))
        stop = max(stop, start + 1)
        tris = todo[start:stop]
        cnt = counts[tris]
        tri = np.repeat(tris, cnt)
        offs = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        ix = i0[tri] + offs // nj[tri]
        iy = j0[tri] + offs % nj[tri]
        px = origin[0] + ix * spacing
        py = origin[1] + iy * spacing
        ax, ay = a[tri, 0], a[tri, 1]
        bx, by = b[tri, 0], b[tri, 1]
        cx, cy = c[tri, 0], c[tri, 1]
        inv = 1.0 / area2[tri]
        w0 = ((bx - px) * (cy - py) - (by - py) * (cx - px)) * inv
        w1 = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) * inv
        w2 = 1.0 - w0 - w1
        keep = (w0 >= 0) & (w1 >= 0) & (w2 >= 0)
        yield tri[keep], ix[keep], iy[keep], np.stack([w0[keep], w1[keep], w2[keep]], axis=1)
        start = stop


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
