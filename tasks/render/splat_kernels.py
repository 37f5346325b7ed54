"""Warp kernels of the 3D Gaussian splatting rasteriser (tasks.render.splats), the algorithm of Kerbl et al. 2023.

One pass per stage, the same kernels on the CPU and on CUDA:

1. ``preprocess`` (a thread per Gaussian): camera-space centre, EWA projection of the 3-D covariance
   (Σ' = J W Σ Wᵀ Jᵀ, plus 0.3 px² on the diagonal as a low-pass), its inverse (the conic), the 3-sigma pixel radius,
   its rectangle of square tiles and how many of them the 3-sigma ellipse really reaches (an exact ellipse-box test);
2. ``duplicate``: one (tile, depth) key per tile reached, at offsets from an exclusive scan; the keys are radix-sorted
   (stable: equal keys keep the Gaussians' order); ``gather`` lays the Gaussians out in that order;
3. ``tile_ranges``: each tile's slice of the sorted list;
4. ``render_pixels`` (a thread per pixel of the tiles listed): the studio backdrop (or a flat colour, or a given
   picture) and the front-to-back compositing of the tile's Gaussians: alpha = min(0.99, o exp(-d²/2)) inside 3 sigma, skipped below 1/255, stopped when the
   transmittance would fall below 1e-4 or at the table's depth; C + T * background, rounded to 8 bits.

Pixel centres are at (x + 0.5, y + 0.5); the camera frame is tasks.render.camera.Camera.frame() (rows right, down,
forward). Lengths in metres.
"""

from __future__ import annotations

import warp as wp

from tasks.native_output import init_warp_quietly

init_warp_quietly()  # no banner on stdout (it belongs to --json data), no CUDA-driver notice on a CPU machine
wp.set_module_options({"enable_backward": False, "optimization_level": 3})

TILE_EDGE_PX = 16  # square tiles: the pixels that share one sorted list (the default; each launch names its own)
LOW_PASS_PX2 = wp.constant(0.3)  # added to the projected covariance's diagonal (3DGS's screen-space low-pass)
ALPHA_MAX = wp.constant(0.99)
ALPHA_MIN = wp.constant(1.0 / 255.0)
T_MIN = wp.constant(1.0e-4)  # compositing stops before the transmittance falls below this
POWER_MIN = wp.constant(-4.5)  # -d²/2 at d = 3 sigma: nothing drawn beyond the 3-sigma ellipse
DEPTH_KEY_PER_M = wp.constant(4.0e6)  # depth quantum of the sort key: 0.25 µm, up to 500 m
DEPTH_KEY_MAX_M = wp.constant(500.0)
TILE_KEY = wp.constant(wp.int64(4294967296))  # key = tile * 2^32 + quantised depth


@wp.func
def _q_max(o: float) -> float:
    """Largest Mahalanobis distance² drawn: 3 sigma, or less where o exp(-q/2) falls below 1/255 sooner."""
    return wp.min(9.0, 2.0 * wp.log(o / ALPHA_MIN))


@wp.func
def _edge_q(a: float, b: float, c: float, fixed: float, lo: float, hi: float) -> float:
    """Least a s² + 2 b s t + c t² over s in [lo, hi] at t = fixed (a > 0)."""
    s = wp.clamp(-b * fixed / a, lo, hi)
    return a * s * s + 2.0 * b * s * fixed + c * fixed * fixed


@wp.func
def _tile_hit(u: float, v: float, co: wp.vec4, tx: int, ty: int, tile: int) -> bool:
    """Whether some pixel centre of tile (tx, ty) lies inside the Gaussian's drawn ellipse (exact, not its box)."""
    x0 = float(tx * tile) + 0.5 - u
    x1 = x0 + float(tile - 1)
    y0 = float(ty * tile) + 0.5 - v
    y1 = y0 + float(tile - 1)
    if x0 <= 0.0 and x1 >= 0.0 and y0 <= 0.0 and y1 >= 0.0:
        return True
    q = wp.min(wp.min(_edge_q(co[0], co[1], co[2], y0, x0, x1), _edge_q(co[0], co[1], co[2], y1, x0, x1)),
               wp.min(_edge_q(co[2], co[1], co[0], x0, y0, y1), _edge_q(co[2], co[1], co[0], x1, y0, y1)))
    return q <= _q_max(co[3])


@wp.kernel
def preprocess(means: wp.array(dtype=wp.vec3), covs: wp.array(dtype=wp.mat33), opacity: wp.array(dtype=float),
               rot: wp.mat33, eye: wp.vec3, focal: float, width: int, height: int, tile: int, tiles_x: int,
               tiles_y: int, near: float, xy: wp.array(dtype=wp.vec2), conic_o: wp.array(dtype=wp.vec4),
               depth: wp.array(dtype=float), rect: wp.array(dtype=wp.vec4i), touched: wp.array(dtype=int)):
    """Project Gaussian i: screen centre, conic and opacity, depth, tile rectangle and the number of tiles whose
    pixels its ellipse reaches."""
    i = wp.tid()
    touched[i] = 0
    rect[i] = wp.vec4i(0, 0, 0, 0)
    t = rot * (means[i] - eye)
    z = t[2]
    o = opacity[i]
    if z <= near or o < ALPHA_MIN:
        return
    lim_x = 1.3 * 0.5 * float(width) / focal
    lim_y = 1.3 * 0.5 * float(height) / focal
    tx = wp.clamp(t[0] / z, -lim_x, lim_x) * z
    ty = wp.clamp(t[1] / z, -lim_y, lim_y) * z
    jac = wp.mat33(focal / z, 0.0, -focal * tx / (z * z),
                   0.0, focal / z, -focal * ty / (z * z),
                   0.0, 0.0, 0.0)
    m = jac * rot
    cov = m * covs[i] * wp.transpose(m)
    a = cov[0, 0] + LOW_PASS_PX2
    b = cov[0, 1]
    c = cov[1, 1] + LOW_PASS_PX2
    det = a * c - b * b
    if det <= 0.0:
        return
    inv = 1.0 / det
    mid = 0.5 * (a + c)
    lam = mid + wp.sqrt(wp.max(0.1, mid * mid - det))
    radius = wp.ceil(wp.sqrt(_q_max(o) * lam))
    u = focal * t[0] / z + 0.5 * float(width)
    v = focal * t[1] / z + 0.5 * float(height)
    fx = float(tiles_x)
    fy = float(tiles_y)
    ft = float(tile)
    x0 = int(wp.clamp(wp.floor((u - radius) / ft), 0.0, fx))
    x1 = int(wp.clamp(wp.floor((u + radius) / ft) + 1.0, 0.0, fx))
    y0 = int(wp.clamp(wp.floor((v - radius) / ft), 0.0, fy))
    y1 = int(wp.clamp(wp.floor((v + radius) / ft) + 1.0, 0.0, fy))
    co = wp.vec4(c * inv, -b * inv, a * inv, o)
    n = int(0)
    for iy in range(y0, y1):
        for ix in range(x0, x1):
            if _tile_hit(u, v, co, ix, iy, tile):
                n += 1
    if n == 0:
        return
    xy[i] = wp.vec2(u, v)
    conic_o[i] = co
    depth[i] = z
    rect[i] = wp.vec4i(x0, y0, x1, y1)
    touched[i] = n


@wp.kernel
def duplicate(touched: wp.array(dtype=int), offsets: wp.array(dtype=int), rect: wp.array(dtype=wp.vec4i),
              xy: wp.array(dtype=wp.vec2), conic_o: wp.array(dtype=wp.vec4), depth: wp.array(dtype=float),
              tile: int, tiles_x: int, n_tiles: int, keys: wp.array(dtype=wp.int64), values: wp.array(dtype=int)):
    """One sort key (tile, quantised depth) and value (Gaussian index) per tile Gaussian i reaches: exactly
    touched[i] slots from offsets[i] (should a compiler round the tile test otherwise than in ``preprocess``, extra
    hits are dropped and missing ones become keys of tile n_tiles, past every real tile)."""
    i = wp.tid()
    n = touched[i]
    if n == 0:
        return
    r = rect[i]
    p = xy[i]
    co = conic_o[i]
    dq = wp.int64(wp.min(depth[i], DEPTH_KEY_MAX_M) * DEPTH_KEY_PER_M)
    k = offsets[i]
    stop = k + n
    for ty in range(r[1], r[3]):
        for tx in range(r[0], r[2]):
            if k < stop and _tile_hit(p[0], p[1], co, tx, ty, tile):
                keys[k] = wp.int64(ty * tiles_x + tx) * TILE_KEY + dq
                values[k] = i
                k += 1
    while k < stop:
        keys[k] = wp.int64(n_tiles) * TILE_KEY
        values[k] = i
        k += 1


@wp.kernel
def gather(values: wp.array(dtype=int), xy: wp.array(dtype=wp.vec2), conic_o: wp.array(dtype=wp.vec4),
           color: wp.array(dtype=wp.vec3), depth: wp.array(dtype=float), s_xy: wp.array(dtype=wp.vec2),
           s_conic_o: wp.array(dtype=wp.vec4), s_color: wp.array(dtype=wp.vec3), s_depth: wp.array(dtype=float)):
    """The sorted list's Gaussians copied into contiguous arrays (each pixel reads its tile's run in order)."""
    j = wp.tid()
    g = values[j]
    s_xy[j] = xy[g]
    s_conic_o[j] = conic_o[g]
    s_color[j] = color[g]
    s_depth[j] = depth[g]


@wp.kernel
def tile_ranges(keys: wp.array(dtype=wp.int64), count: int, n_tiles: int, start: wp.array(dtype=int),
                end: wp.array(dtype=int)):
    """start[tile], end[tile]: the slice of the sorted list that belongs to each tile (start = end = 0 when empty);
    keys of tile n_tiles (placeholders) end the list and belong to none."""
    i = wp.tid()
    tile = int(keys[i] / TILE_KEY)
    if i == 0:
        if tile < n_tiles:
            start[tile] = 0
    else:
        prev = int(keys[i - 1] / TILE_KEY)
        if prev != tile:
            end[prev] = i
            if tile < n_tiles:
                start[tile] = i
    if i == count - 1 and tile < n_tiles:
        end[tile] = count


@wp.func
def _shadow(px: float, py: float, shadow: wp.array(dtype=float), origin: wp.vec2, cell: float, nx: int,
            ny: int) -> float:
    """Bilinear sample of the shadow map (darkening in 0..1) at world (x, y); 0 outside it."""
    gx = (px - origin[0]) / cell - 0.5
    gy = (py - origin[1]) / cell - 0.5
    if gx < 0.0 or gy < 0.0 or gx >= float(nx - 1) or gy >= float(ny - 1):
        return 0.0
    ix = int(gx)
    iy = int(gy)
    fx = gx - float(ix)
    fy = gy - float(iy)
    s00 = shadow[iy * nx + ix]
    s01 = shadow[iy * nx + ix + 1]
    s10 = shadow[(iy + 1) * nx + ix]
    s11 = shadow[(iy + 1) * nx + ix + 1]
    return (1.0 - fy) * ((1.0 - fx) * s00 + fx * s01) + fy * ((1.0 - fx) * s10 + fx * s11)


@wp.func
def _smooth(e0: float, e1: float, x: float) -> float:
    """Smoothstep from 0 at e0 to 1 at e1."""
    t = wp.clamp((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


@wp.kernel
def render_pixels(start: wp.array(dtype=int), end: wp.array(dtype=int), xy: wp.array(dtype=wp.vec2),
                  conic_o: wp.array(dtype=wp.vec4), color: wp.array(dtype=wp.vec3), depth: wp.array(dtype=float),
                  width: int, height: int, tile: int, tile_origin: wp.array(dtype=wp.vec2i),
                  tiles: wp.array(dtype=int), first: int,
                  rot: wp.mat33, eye: wp.vec3, focal: float, studio: int, flat: wp.vec3, table: wp.vec3,
                  horizon: wp.vec3, top: wp.vec3, target: wp.vec2, spot_m: float, falloff: float, fade_m: float,
                  shadow: wp.array(dtype=float), shadow_origin: wp.vec2, shadow_cell: float, shadow_nx: int,
                  shadow_ny: int, bg_rgb: wp.array(dtype=wp.vec3), bg_depth: wp.array(dtype=float),
                  out: wp.array(dtype=wp.uint8)):
    """One pixel: its background (and the table's depth), then its tile's Gaussians front to back. Threads run tile
    by tile (tile² pixels each) through the listed tiles from tiles[first] on, so a tile's list is read while it is in
    cache; tile_origin holds each tile's first pixel (x, y). studio: 0 a flat colour, 1 the studio, 2 the given image
    (bg_rgb, bg_depth per pixel: the Gaussians stop at its depth)."""
    t = wp.tid()
    tile_id = tiles[first + t / (tile * tile)]
    local = t % (tile * tile)
    origin = tile_origin[tile_id]
    px = origin[0] + local % tile
    py = origin[1] + local / tile
    if px >= width or py >= height:
        return
    p = py * width + px
    cx = float(px) + 0.5
    cy = float(py) + 0.5
    bg = flat
    table_z = float(1.0e30)
    if studio == 2:
        bg = bg_rgb[p]
        table_z = bg_depth[p]
    elif studio != 0:
        ray = wp.transpose(rot) * wp.vec3((cx - 0.5 * float(width)) / focal, (cy - 0.5 * float(height)) / focal, 1.0)
        if ray[2] >= -1.0e-6:  # the backdrop, lighter upwards
            bg = wp.lerp(horizon, top, _smooth(0.0, 0.6, ray[2] / wp.length(ray)))
        else:  # the table
            hit = -eye[2] / ray[2]  # camera depth of the table point (the ray's forward component is 1)
            hx = eye[0] + hit * ray[0]
            hy = eye[1] + hit * ray[1]
            r = wp.sqrt((hx - target[0]) * (hx - target[0]) + (hy - target[1]) * (hy - target[1]))
            lit = table * (1.0 - falloff * _smooth(0.0, spot_m, r))
            lit = lit * (1.0 - _shadow(hx, hy, shadow, shadow_origin, shadow_cell, shadow_nx, shadow_ny))
            bg = wp.lerp(lit, horizon, _smooth(spot_m, fade_m, r))
            table_z = hit
    acc = wp.vec3(0.0, 0.0, 0.0)
    trans = float(1.0)
    for j in range(start[tile_id], end[tile_id]):
        if depth[j] > table_z:
            break
        d = xy[j] - wp.vec2(cx, cy)
        co = conic_o[j]
        power = -0.5 * (co[0] * d[0] * d[0] + co[2] * d[1] * d[1]) - co[1] * d[0] * d[1]
        if power < POWER_MIN:
            continue
        alpha = wp.min(ALPHA_MAX, co[3] * wp.exp(power))
        if alpha < ALPHA_MIN:
            continue
        test_t = trans * (1.0 - alpha)
        if test_t < T_MIN:
            break
        acc = acc + color[j] * (alpha * trans)
        trans = test_t
    acc = acc + bg * trans
    for ch in range(3):
        out[3 * p + ch] = wp.uint8(int(wp.clamp(acc[ch] * 255.0 + 0.5, 0.0, 255.0)))
