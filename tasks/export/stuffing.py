"""Isosurface stuffing (Labelle & Shewchuk, SIGGRAPH 2007): a deterministic tet mesh of a closed triangle surface.

A body-centred cubic (BCC) lattice of spacing h covers the surface; lattice vertices get the surface's signed distance
(libigl, negative inside); lattice edges that cross the surface get a cut point on it (bracketed root finding); lattice
vertices too close to a cut point are warped onto it; each lattice tet is then replaced by the stencil of its sign
pattern (inside part only). With the paper's warp thresholds and stencils (quad diagonals: through the cut point of a
long edge, else by the parity rule) every tet's dihedral angles lie in [10.7, 164.8] deg, whatever the surface (the
paper's computer-assisted proof; tetmesh.py still measures every mesh). Every boundary vertex lies on the isosurface (sharp edges are chamfered, and parts thinner than
about a lattice spacing are lost: tetmesh.py checks both and refines).

Deterministic: one fixed sequence of numpy and libigl operations (libigl's per-point queries are independent of
its thread count), no random numbers; nodes are numbered by lattice vertex then by cut edge, tets by lattice tet, and
coordinates are rounded to a 2^-40 m grid so that a last-bit difference of another CPU cannot change the bytes.
"""

from __future__ import annotations

import numpy as np

from contracts.errors import InputError

ALPHA_LONG = 0.24999   # warp thresholds of the paper (fractions of the edge length): dihedral angles in
ALPHA_SHORT = 0.41189  # [10.7, 164.8] deg
MIN_GUARANTEED_DEG, MAX_GUARANTEED_DEG = 10.7, 164.8
ROOT_ITERATIONS = 60   # at most: each cut point is found by bracketed root finding (Illinois regula falsi) ...
ROOT_TOLERANCE = 1e-9  # ... to within this x the lattice spacing of the isosurface
MAX_LATTICE_VERTICES = 20_000_000  # a finer lattice (an edge length far too small for the surface) is an InputError
QUANTUM_M = 2.0 ** -40  # output coordinates are multiples of this (about 1e-12 m)


def signed_distance_m(points_m: np.ndarray, vertices_m: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Signed distance [m] from each point to the closed surface (negative inside; libigl, pseudonormal sign)."""
    import igl

    if len(points_m) == 0:
        return np.zeros(0)
    s = igl.signed_distance(np.ascontiguousarray(points_m, dtype=np.float64), vertices_m, faces,
                            sign_type=igl.SignedDistanceType.SIGNED_DISTANCE_TYPE_PSEUDONORMAL)[0]
    return np.asarray(s, dtype=np.float64)


def _bcc_lattice(lo: np.ndarray, hi: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The BCC lattice around [lo, hi]: vertex positions [m], doubled integer coordinates (black: even, red: odd),
    colours (True: black) and the lattice tets (each one black edge and one red edge), a padding cell all round."""
    origin = lo - h
    n = np.floor((hi - origin) / h).astype(np.int64) + 2  # cells per axis; the lattice's tets reach past hi
    if 2 * int(np.prod(n + 1)) > MAX_LATTICE_VERTICES:
        raise InputError(f"tet mesh: a lattice spacing of {h:.3g} m is too fine for a surface of extent "
                         f"{np.round(hi - lo, 4).tolist()} m (over {MAX_LATTICE_VERTICES:,} lattice vertices)")
    bi = np.stack(np.meshgrid(*[np.arange(k + 1) for k in n], indexing="ij"), axis=-1).reshape(-1, 3)
    ri = np.stack(np.meshgrid(*[np.arange(k) for k in n], indexing="ij"), axis=-1).reshape(-1, 3)
    q = np.concatenate([2 * bi, 2 * ri + 1])
    black = np.concatenate([np.ones(len(bi), bool), np.zeros(len(ri), bool)])
    nb = len(bi)

    def black_id(i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        return (i * (n[1] + 1) + j) * (n[2] + 1) + k

    def red_id(i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        return nb + (i * n[1] + j) * n[2] + k

    tets = []
    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        shape = n.copy()
        shape[axis] -= 1  # red edges between neighbouring cells along this axis
        c = np.stack(np.meshgrid(*[np.arange(k) for k in shape], indexing="ij"), axis=-1).reshape(-1, 3)
        if len(c) == 0:
            continue
        e = np.zeros(3, np.int64)
        e[axis] = 1
        r0, r1 = red_id(*c.T), red_id(*(c + e).T)
        corner = []  # the shared face's four black corners, in cyclic order
        for du, dw in ((0, 0), (1, 0), (1, 1), (0, 1)):
            d = e.copy()
            d[u], d[w] = du, dw
            corner.append(black_id(*(c + d).T))
        for m in range(4):
            tets.append(np.stack([r0, r1, corner[m], corner[(m + 1) % 4]], axis=1))
    positions = origin + q * (h / 2.0)
    return positions, q, black, np.concatenate(tets).astype(np.int64)


def _cut_parameters(a_m: np.ndarray, b_m: np.ndarray, fa: np.ndarray, fb: np.ndarray, vertices_m: np.ndarray,
                    faces: np.ndarray, offset_m: float, tolerance_m: float) -> np.ndarray:
    """Where each segment a -> b (f(a) < 0 < f(b) or f(a) > 0 > f(b), f = signed distance - offset) crosses the
    isosurface, as a fraction of its length: Illinois regula falsi, to |f| <= tolerance_m."""
    lo, hi = np.zeros(len(a_m)), np.ones(len(a_m))
    flo, fhi = fa.copy(), fb.copy()
    best_t = np.where(np.abs(fa) <= np.abs(fb), 0.0, 1.0)
    best_f = np.minimum(np.abs(fa), np.abs(fb))
    side = np.zeros(len(a_m), np.int64)  # which end moved last (+1 lo, -1 hi): the other end's value is halved
    active = np.flatnonzero(best_f > tolerance_m)
    for _ in range(ROOT_ITERATIONS):
        if len(active) == 0:
            break
        lo_a, hi_a, flo_a, fhi_a = lo[active], hi[active], flo[active], fhi[active]
        t = lo_a - flo_a * (hi_a - lo_a) / (fhi_a - flo_a)
        t = np.where((t > lo_a) & (t < hi_a), t, 0.5 * (lo_a + hi_a))
        ft = signed_distance_m(a_m[active] + t[:, None] * (b_m[active] - a_m[active]), vertices_m, faces) - offset_m
        better = np.abs(ft) < best_f[active]
        best_t[active[better]], best_f[active[better]] = t[better], np.abs(ft[better])
        move_lo = np.sign(ft) == np.sign(flo_a)
        last = side[active]
        lo[active] = np.where(move_lo, t, lo_a)
        hi[active] = np.where(move_lo, hi_a, t)
        flo[active] = np.where(move_lo, ft, np.where(last == -1, flo_a / 2, flo_a))
        fhi[active] = np.where(move_lo, np.where(last == 1, fhi_a / 2, fhi_a), ft)
        side[active] = np.where(move_lo, 1, -1)
        active = active[(best_f[active] > tolerance_m) & (hi[active] - lo[active] > 1e-12)]
    return best_t


def _within_bounds(pos: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Whether each tet's dihedral angles lie within [MIN_GUARANTEED_DEG, MAX_GUARANTEED_DEG] (either orientation)."""
    p = pos[tets]
    normals = []
    for a, b, c in ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)):  # face k opposite vertex k, outward if positive
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        normals.append(n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300))
    cos = np.stack([-np.einsum("ij,ij->i", normals[i], normals[j]) for i in range(4) for j in range(i + 1, 4)], axis=1)
    lo, hi = np.cos(np.radians(MAX_GUARANTEED_DEG)), np.cos(np.radians(MIN_GUARANTEED_DEG))
    return np.all((cos >= lo) & (cos <= hi), axis=1)


def _node_position(i: int, pos: np.ndarray, cut: np.ndarray, n_vert: int) -> np.ndarray:
    """Position of node i (a lattice vertex, or a cut point when i >= n_vert)."""
    return pos[i] if i < n_vert else cut[i - n_vert]


def stuff(vertices_m: np.ndarray, faces: np.ndarray, spacing_m: float,
          offset_m: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Nodes [m] and tets (not yet oriented; unreferenced nodes kept) filling the surface offset outwards by offset_m
    (the isosurface signed distance = offset_m), lattice spacing spacing_m."""
    v = np.ascontiguousarray(vertices_m, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    h = float(spacing_m)
    pos, q, black, lattice_tets = _bcc_lattice(v.min(axis=0) - offset_m, v.max(axis=0) + offset_m, h)
    sd = signed_distance_m(pos, v, f) - offset_m
    sign = np.sign(sd).astype(np.int8)
    # only the lattice tets that touch the inside matter
    lattice_tets = lattice_tets[(sign[lattice_tets] < 0).any(axis=1) | (sign[lattice_tets] == 0).all(axis=1)]
    n_vert = len(pos)

    # lattice edges of those tets crossing the surface, each once (ordered by key: deterministic)
    pairs = lattice_tets[:, [0, 0, 0, 1, 1, 2]], lattice_tets[:, [1, 2, 3, 2, 3, 3]]
    lo_id, hi_id = np.minimum(*pairs).ravel(), np.maximum(*pairs).ravel()
    keys = np.unique(lo_id * n_vert + hi_id)
    ea, eb = keys // n_vert, keys % n_vert
    crossing = sign[ea] * sign[eb] < 0
    ea, eb, keys = ea[crossing], eb[crossing], keys[crossing]
    t = _cut_parameters(pos[ea], pos[eb], sd[ea], sd[eb], v, f, offset_m, ROOT_TOLERANCE * h)
    cut = pos[ea] + t[:, None] * (pos[eb] - pos[ea])

    # warp: a vertex closer to a cut point than alpha x the edge length moves onto the closest such cut point
    alpha = np.where(black[ea] == black[eb], ALPHA_LONG, ALPHA_SHORT)
    length = np.where(black[ea] == black[eb], 1.0, np.sqrt(0.75))
    cand_v = np.concatenate([ea[t < alpha], eb[1 - t < alpha]])
    cand_d = np.concatenate([(t * length)[t < alpha], ((1 - t) * length)[1 - t < alpha]])
    cand_c = np.concatenate([np.flatnonzero(t < alpha), np.flatnonzero(1 - t < alpha)])
    order = np.lexsort((cand_c, cand_d, cand_v))
    cand_v, cand_c = cand_v[order], cand_c[order]
    first = np.ones(len(cand_v), bool)
    first[1:] = cand_v[1:] != cand_v[:-1]
    warped_v, warped_c = cand_v[first], cand_c[first]
    pos = pos.copy()
    pos[warped_v] = cut[warped_c]
    sign = sign.copy()
    sign[warped_v] = 0
    survive = (sign[ea] != 0) & (sign[eb] != 0)
    keys, cut = keys[survive], cut[survive]
    cut_id = {int(k): n_vert + i for i, k in enumerate(keys.tolist())}

    def c(a: int, b: int) -> int:
        return cut_id[min(a, b) * n_vert + max(a, b)]

    def quad(u: int, w: int, o: int) -> tuple[tuple[int, int, int], tuple[int, int, int], tuple[int, int]]:
        """The two triangles and the diagonal of quad (u, w, c(w, o), c(u, o)) on lattice face (u, w, o)."""
        cu, cw = c(u, o), c(w, o)
        if black[u] == black[o]:      # the cut point on a long edge takes the diagonal
            use_cu = True
        elif black[w] == black[o]:
            use_cu = False
        else:                         # parity rule (u-w is the long edge)
            even = int(np.count_nonzero(q[o] < q[w])) % 2 == 0
            use_cu = bool(black[u]) != even
        if use_cu:                    # diagonal cu - w
            return (u, w, cu), (cu, w, cw), (cu, w)
        return (u, w, cw), (u, cw, cu), (u, cw)

    out: list[tuple[int, ...]] = []
    s4 = sign[lattice_tets]
    whole = (s4 <= 0).all(axis=1) & (s4 < 0).any(axis=1)
    flat = (s4 == 0).all(axis=1)
    if flat.any():  # four vertices warped onto the surface (rare; outside the paper's stencils and proof): kept when
        # its centre is inside and its angles are within the bounds the stencils guarantee, else left out (a notch)
        flat_tets = lattice_tets[flat]
        inside = signed_distance_m(pos[flat_tets].mean(axis=1), v, f) < offset_m
        inside &= _within_bounds(pos, flat_tets)
        whole[np.flatnonzero(flat)[inside]] = True
    mixed = (s4 < 0).any(axis=1) & (s4 > 0).any(axis=1)
    keep = whole | mixed
    for tet, sg, is_whole in zip(lattice_tets[keep].tolist(), s4[keep].tolist(), whole[keep].tolist(), strict=True):
        if is_whole:
            out.append(tuple(tet))
            continue
        neg = [x for x, s in zip(tet, sg, strict=True) if s < 0]
        zero = [x for x, s in zip(tet, sg, strict=True) if s == 0]
        posv = [x for x, s in zip(tet, sg, strict=True) if s > 0]
        if len(neg) == 1:
            n0 = neg[0]
            out.append((n0, *zero, *[c(n0, p) for p in posv]))
            continue
        tris: list[tuple[int, int, int]] = []
        diagonals: list[tuple[int, ...]] = []
        if len(neg) == 2 and len(posv) == 1:           # pyramid: apex the zero vertex
            t1, t2, _ = quad(neg[0], neg[1], posv[0])
            out += [(zero[0], *t1), (zero[0], *t2)]
            continue
        if len(neg) == 3:                              # prism: three lattice-face quads, the cut triangle, the base
            a, b, d = neg
            p = posv[0]
            for u, w in ((a, b), (b, d), (d, a)):
                t1, t2, dg = quad(u, w, p)
                tris += [t1, t2]
                diagonals.append(dg)
            tris += [(a, b, d), (c(a, p), c(b, p), c(d, p))]
        else:                                          # wedge: two lattice-face quads, two end triangles, cut quad
            a, b = neg
            p, r = posv
            for o in (p, r):
                t1, t2, dg = quad(a, b, o)
                tris += [t1, t2]
                diagonals.append(dg)
            tris += [(a, c(a, p), c(a, r)), (b, c(b, p), c(b, r))]
            ends = [x for dg in diagonals for x in dg]
            kept = [x for x in (a, b) if ends.count(x) == 2]
            if kept:  # both diagonals from one kept vertex: the cut quad's diagonal is free, take the shorter
                d1 = np.linalg.norm(_node_position(c(a, p), pos, cut, n_vert) - _node_position(c(b, r), pos, cut, n_vert))
                d2 = np.linalg.norm(_node_position(c(a, r), pos, cut, n_vert) - _node_position(c(b, p), pos, cut, n_vert))
                cq: tuple[int, ...] = (c(a, p), c(b, r)) if d1 <= d2 else (c(a, r), c(b, p))
            else:     # the diagonals end at two cut points: the cut quad's diagonal joins them
                cq = tuple(x for dg in diagonals for x in dg if x >= n_vert)
            others = [x for x in (c(a, p), c(a, r), c(b, r), c(b, p)) if x not in cq]
            tris += [(cq[0], cq[1], others[0]), (cq[0], cq[1], others[1])]
            diagonals.append(cq)
        ends = [x for dg in diagonals for x in dg]
        apex = next((x for x in sorted(set(ends), key=ends.index) if ends.count(x) >= 2), None)
        if apex is None:  # cyclic diagonals: cannot occur with the rules above (two diagonals meet at the long edge's cut)
            raise AssertionError("isosurface stuffing: twisted prism")
        out += [(apex, *t) for t in tris if apex not in t]

    nodes = np.concatenate([pos, cut]) if len(cut) else pos
    nodes = np.round(nodes / QUANTUM_M) * QUANTUM_M
    return nodes, np.asarray(out, dtype=np.int64).reshape(-1, 4)

