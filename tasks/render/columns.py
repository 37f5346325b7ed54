"""Triangle / lattice-column overlap: the one vectorised kernel behind the CPU reference views (tasks.render.views)
and geometry's inside tests (tasks.geometry.raster.lattice_winding)."""

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
