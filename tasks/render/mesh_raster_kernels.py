"""Warp kernels of the CPU triangle rasteriser (tasks.render.mesh_raster): one thread per triangle culls it (behind
the near plane, back-facing, off screen) and walks its pixel box; pass 1 takes the minimum camera depth per pixel
(atomic min: the order does not matter), pass 2 writes the colour of the triangle whose depth is the pixel's minimum
(on the CPU a launch runs its threads in order, so equal depths resolve the same way every time). Pixel centres are at
(x + 0.5, y + 0.5); depth is 1 / (1/z interpolated in screen space); colours are interpolated perspective-correctly.
"""

from __future__ import annotations

import warp as wp

from tasks.native_output import init_warp_quietly

init_warp_quietly()  # no banner on stdout (it belongs to --json data), no CUDA-driver notice on a CPU machine
wp.set_module_options({"enable_backward": False, "optimization_level": 3})

EDGE_EPS = wp.constant(1e-7)  # barycentric tolerance: pixel centres on a shared edge belong to both triangles
DEPTH_TOL = wp.constant(1.000001)  # a pixel's winner in pass 2: depth within 1 ppm of the minimum (1 um at 1 m)


@wp.func
def _bary(u0: float, v0: float, u1: float, v1: float, u2: float, v2: float, inv_area: float, cx: float,
          cy: float) -> wp.vec3:
    """Barycentric weights of a pixel centre in a screen triangle."""
    w0 = ((u1 - cx) * (v2 - cy) - (u2 - cx) * (v1 - cy)) * inv_area
    w1 = ((u2 - cx) * (v0 - cy) - (u0 - cx) * (v2 - cy)) * inv_area
    return wp.vec3(w0, w1, 1.0 - w0 - w1)


@wp.func
def _depth(w: wp.vec3, iz0: float, iz1: float, iz2: float) -> float:
    """Camera depth at barycentric weights w: 1 / (1/z interpolated in screen space)."""
    return 1.0 / (w[0] * iz0 + w[1] * iz1 + w[2] * iz2)


@wp.func
def _setup(su: wp.array(dtype=float), sv: wp.array(dtype=float), inv_z: wp.array(dtype=float),
           i0: int, i1: int, i2: int, width: int, height: int, max_inv_z: float) -> wp.vec4i:
    """Pixel box (x0, y0, x1, y1) of a visible front-facing triangle; an empty box (x1 < x0) when culled."""
    empty = wp.vec4i(0, 0, -1, -1)
    if inv_z[i0] > max_inv_z or inv_z[i1] > max_inv_z or inv_z[i2] > max_inv_z:
        return empty  # a vertex behind the near plane (or the camera)
    u0, u1, u2 = su[i0], su[i1], su[i2]
    v0, v1, v2 = sv[i0], sv[i1], sv[i2]
    if (u1 - u0) * (v2 - v0) - (u2 - u0) * (v1 - v0) > -1e-9:
        return empty  # back-facing (image v grows downwards: a front face has a negative area) or degenerate
    x0 = wp.max(int(wp.ceil(wp.min(u0, wp.min(u1, u2)) - 0.5)), 0)
    x1 = wp.min(int(wp.floor(wp.max(u0, wp.max(u1, u2)) - 0.5)), width - 1)
    y0 = wp.max(int(wp.ceil(wp.min(v0, wp.min(v1, v2)) - 0.5)), 0)
    y1 = wp.min(int(wp.floor(wp.max(v0, wp.max(v1, v2)) - 0.5)), height - 1)
    return wp.vec4i(x0, y0, x1, y1)


@wp.kernel
def triangle_depth(su: wp.array(dtype=float), sv: wp.array(dtype=float), inv_z: wp.array(dtype=float),
                   faces: wp.array2d(dtype=int), width: int, height: int, max_inv_z: float,
                   zbuf: wp.array(dtype=float)):
    """Pass 1: zbuf[pixel] = min(zbuf[pixel], depth of every triangle covering the pixel centre)."""
    t = wp.tid()
    i0, i1, i2 = faces[t, 0], faces[t, 1], faces[t, 2]
    b = _setup(su, sv, inv_z, i0, i1, i2, width, height, max_inv_z)
    if b[2] < b[0] or b[3] < b[1]:
        return
    u0, u1, u2 = su[i0], su[i1], su[i2]
    v0, v1, v2 = sv[i0], sv[i1], sv[i2]
    inv_area = 1.0 / ((u1 - u0) * (v2 - v0) - (u2 - u0) * (v1 - v0))
    for y in range(b[1], b[3] + 1):
        for x in range(b[0], b[2] + 1):
            w = _bary(u0, v0, u1, v1, u2, v2, inv_area, float(x) + 0.5, float(y) + 0.5)
            if w[0] >= -EDGE_EPS and w[1] >= -EDGE_EPS and w[2] >= -EDGE_EPS:
                wp.atomic_min(zbuf, y * width + x, _depth(w, inv_z[i0], inv_z[i1], inv_z[i2]))


@wp.kernel
def triangle_color(su: wp.array(dtype=float), sv: wp.array(dtype=float), inv_z: wp.array(dtype=float),
                   faces: wp.array2d(dtype=int), width: int, height: int, max_inv_z: float,
                   zbuf: wp.array(dtype=float), vertex_rgb: wp.array(dtype=wp.vec3),
                   face_label: wp.array(dtype=wp.uint8),
                   image: wp.array2d(dtype=wp.uint8), label: wp.array(dtype=wp.uint8)):
    """Pass 2: the colour (vertex colours in [0, 1] -> uint8) and label of the nearest triangle at each pixel it
    covers (the depth pass's winner), written into the image (H * W, 3) and the label map."""
    t = wp.tid()
    i0, i1, i2 = faces[t, 0], faces[t, 1], faces[t, 2]
    b = _setup(su, sv, inv_z, i0, i1, i2, width, height, max_inv_z)
    if b[2] < b[0] or b[3] < b[1]:
        return
    u0, u1, u2 = su[i0], su[i1], su[i2]
    v0, v1, v2 = sv[i0], sv[i1], sv[i2]
    inv_area = 1.0 / ((u1 - u0) * (v2 - v0) - (u2 - u0) * (v1 - v0))
    for y in range(b[1], b[3] + 1):
        for x in range(b[0], b[2] + 1):
            w = _bary(u0, v0, u1, v1, u2, v2, inv_area, float(x) + 0.5, float(y) + 0.5)
            if w[0] >= -EDGE_EPS and w[1] >= -EDGE_EPS and w[2] >= -EDGE_EPS:
                p = y * width + x
                # the same function as pass 1; DEPTH_TOL guards against a compiler contracting the two differently
                if _depth(w, inv_z[i0], inv_z[i1], inv_z[i2]) <= zbuf[p] * DEPTH_TOL:
                    a = w[0] * inv_z[i0]
                    bb = w[1] * inv_z[i1]
                    c = w[2] * inv_z[i2]
                    col = (a * vertex_rgb[i0] + bb * vertex_rgb[i1] + c * vertex_rgb[i2]) * (255.0 / (a + bb + c))
                    for k in range(3):
                        image[p, k] = wp.uint8(int(wp.clamp(col[k] + 0.5, 0.0, 255.0)))
                    label[p] = face_label[t]


@wp.func
def _disc_depth(z: float, radius_m: float, r_px: int, dx: int, dy: int) -> float:
    """Depth of a disc's pixel at offset (dx, dy) from its centre: a sphere-like bulge towards the camera."""
    q = wp.sqrt(float(dx * dx + dy * dy)) / (float(r_px) + 0.5)
    return z - radius_m * wp.sqrt(wp.max(1.0 - q * q, 0.0))


@wp.kernel
def disc_depth(cu: wp.array(dtype=int), cv: wp.array(dtype=int), z: wp.array(dtype=float),
               radius_m: wp.array(dtype=float), radius_px: wp.array(dtype=int), width: int, height: int,
               zbuf: wp.array(dtype=float)):
    """Pass 1 for discs facing the camera (centre pixel, camera depth [m], radius [m] and [px])."""
    t = wp.tid()
    r = radius_px[t]
    lim = (float(r) + 0.25) * (float(r) + 0.25)
    for dy in range(-r, r + 1):
        y = cv[t] + dy
        if y >= 0 and y < height:
            for dx in range(-r, r + 1):
                x = cu[t] + dx
                if x >= 0 and x < width and float(dx * dx + dy * dy) <= lim:
                    wp.atomic_min(zbuf, y * width + x, _disc_depth(z[t], radius_m[t], r, dx, dy))


@wp.kernel
def disc_color(cu: wp.array(dtype=int), cv: wp.array(dtype=int), z: wp.array(dtype=float),
               radius_m: wp.array(dtype=float), radius_px: wp.array(dtype=int), width: int, height: int,
               zbuf: wp.array(dtype=float), rgb: wp.array(dtype=wp.vec3), rim_shade: float, disc_label: wp.uint8,
               image: wp.array2d(dtype=wp.uint8), label: wp.array(dtype=wp.uint8)):
    """Pass 2 for discs: the nearest disc's colour (in [0, 1], darker towards the rim) and label at each pixel."""
    t = wp.tid()
    r = radius_px[t]
    lim = (float(r) + 0.25) * (float(r) + 0.25)
    for dy in range(-r, r + 1):
        y = cv[t] + dy
        if y >= 0 and y < height:
            for dx in range(-r, r + 1):
                x = cu[t] + dx
                d2 = float(dx * dx + dy * dy)
                if x >= 0 and x < width and d2 <= lim:
                    p = y * width + x
                    if _disc_depth(z[t], radius_m[t], r, dx, dy) <= zbuf[p] * DEPTH_TOL:
                        shade = 1.0 - rim_shade * wp.min(wp.sqrt(d2) / wp.max(float(r), 1.0), 1.0)
                        col = rgb[t] * (255.0 * shade)
                        for k in range(3):
                            image[p, k] = wp.uint8(int(wp.clamp(col[k] + 0.5, 0.0, 255.0)))
                        label[p] = disc_label
