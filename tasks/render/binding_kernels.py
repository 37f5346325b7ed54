"""Warp kernels of tasks.render.binding: Gaussians bound to particles, deformed by one recorded state (a thread per
Gaussian, float64 as the numpy formulas they replace).

``deform``: x_g = sum_k w_k (x_j + F_j (X_g - X_j)), F_g = sum_k w_k F_j, Σ_g = F_g Σ F_gᵀ over the Gaussian's k
particles j; ``normals``: n' = F_g^-T n / |F_g^-T n| (a zero rest normal stays zero; a singular or non-finite F_g
leaves n as it is). Lengths in metres.
"""

from __future__ import annotations

import warp as wp

from tasks.native_output import init_warp_quietly

init_warp_quietly()  # no banner on stdout (it belongs to --json data), no CUDA-driver notice on a CPU machine
wp.set_module_options({"enable_backward": False, "optimization_level": 3})

SINGULAR_DET = wp.constant(wp.float64(1.0e-9))  # |det F_g| at or below this: the rest normal is kept
SHORT = wp.constant(wp.float64(1.0e-12))  # a normal shorter than this is an interior blob's: zero


@wp.kernel
def deform(index: wp.array2d(dtype=int), weight: wp.array2d(dtype=wp.float64), offsets: wp.array2d(dtype=wp.vec3d),
           x: wp.array(dtype=wp.vec3d), F: wp.array(dtype=wp.mat33d), rest_cov: wp.array(dtype=wp.mat33d),
           centres: wp.array(dtype=wp.vec3d), cov: wp.array(dtype=wp.mat33d), blended: wp.array(dtype=wp.mat33d)):
    """Gaussian g's centre, covariance and blended gradient in the state (x, F) of its particles."""
    g = wp.tid()
    c = wp.vec3d()
    Fg = wp.mat33d()
    for k in range(index.shape[1]):
        j = index[g, k]
        w = weight[g, k]
        c += w * (x[j] + F[j] * offsets[g, k])
        Fg += w * F[j]
    centres[g] = c
    blended[g] = Fg
    cov[g] = Fg * rest_cov[g] * wp.transpose(Fg)


@wp.kernel
def normals(blended: wp.array(dtype=wp.mat33d), rest: wp.array(dtype=wp.vec3d), out: wp.array(dtype=wp.vec3d)):
    """Gaussian g's unit normal under its blended gradient."""
    g = wp.tid()
    Fg = blended[g]
    n = rest[g]
    det = wp.determinant(Fg)
    if wp.isfinite(det) and wp.abs(det) > SINGULAR_DET:
        n = wp.transpose(wp.inverse(Fg)) * n
    length = wp.length(n)
    if length > SHORT:
        out[g] = n / length
    else:
        out[g] = wp.vec3d()
