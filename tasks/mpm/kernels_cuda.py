"""CUDA-only kernels of the MLS-MPM step: warp- and block-level variants of the particle-to-grid scatter and of the
per-scene re-fit reduction. Same physics and the same formulas as ``kernels.py`` (whose device functions they call);
only the order of the float additions differs (it already does on CUDA: global float atomics).

* ``p2g_warp``: one particle per thread; the lanes of a warp whose 3x3x3 stencils coincide (same base node: with
  2 particles per cell per axis in a spatially coherent order, pairs of neighbours) add their 27 contributions
  with warp shuffles and one lane issues the 16-byte atomics, so the global atomics (the bound of p2g) drop by
  the group size. Any particle order is correct; coherent orders are faster.
* ``refit_fused``: the grid re-fit (bounds, max speed, kinetic energy, window fit) in one launch: each block
  reduces one chunk of one scene (threads stride over it; warp shuffles + shared memory) into the chunk's partials;
  the last block of each scene to finish combines the scene's partials and fits its window (instead of a reset
  launch, one serial loop per thread with same-address atomics, and a fit launch).
* Variants (selected by ``plan_cuda.py`` from ``SimConfig.kernel``; each in a module of its own, compiled on first
  use): ``g2p_kernel`` and ``grid_update_kernel`` return the kernels of ``kernels.make_g2p`` / ``make_grid_update``
  without the collider contact (scenes with only the ground), with warp-summed ground impulses, and (g2p) with
  warp-cooperative particle loads/stores; ``p2g_kernel(True)`` is p2g_warp with warp-cooperative loads (not used by
  default).
* ``scatter_stencil_scan``: the scatter of one particle per thread as a row scan: the warp's 32 particles' terms go
  through shared memory and 27 lanes (9 stencil rows x 3 runs of ~11 particles) add consecutive particles'
  overlapping rows in a 3-node window along z, issuing each node once per run: ~7 atomics per particle in lattice
  order instead of 13.5 (pairs merged by ``scatter_stencil_warp``). ``p2g_kernel(coop, SCATTER_SCAN)`` uses it.
* ``make_g2p2g``: the g2p of step n and the p2g of step n+1 in one kernel (the scatter reads the new state from
  registers: no reload of the particle records, one launch fewer per step), used by ``plan_cuda.py`` inside
  multi-step graphs wherever no re-fit comes between the two steps.

Launch contract: the launch dimension is a multiple of the block size (threads past ``n_items`` take part in the
warp/block collectives but write nothing). Never launched on CPU (the CPU path keeps ``kernels.py``, bit for bit;
the CPU branches of the native snippets exist only so that tests can check the index arithmetic there).
"""

from __future__ import annotations

import functools

import warp as wp

from tasks.mpm import kernels as K

wp.set_module_options({"enable_backward": False, "optimization_level": 3})

@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    __shared__ float red_min_f[32];
    float r = v;
    for (int o = 16; o > 0; o >>= 1) r = fminf(r, __shfl_xor_sync(0xffffffffu, r, o));
    const int nw = (blockDim.x + 31) >> 5;
    __syncthreads();
    if ((threadIdx.x & 31) == 0) red_min_f[threadIdx.x >> 5] = r;
    __syncthreads();
    r = red_min_f[0];
    for (int k = 1; k < nw; ++k) r = fminf(r, red_min_f[k]);
    return r;
#else
    return v;
#endif
"""
)
def block_min_float(v: float) -> float:
    """Minimum of v over the thread block (every thread of the block must call it; all get the result)."""
    ...


@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    __shared__ float red_sum_f[32];
    float r = v;
    for (int o = 16; o > 0; o >>= 1) r += __shfl_xor_sync(0xffffffffu, r, o);
    const int nw = (blockDim.x + 31) >> 5;
    __syncthreads();
    if ((threadIdx.x & 31) == 0) red_sum_f[threadIdx.x >> 5] = r;
    __syncthreads();
    r = red_sum_f[0];
    for (int k = 1; k < nw; ++k) r += red_sum_f[k];
    return r;
#else
    return v;
#endif
"""
)
def block_sum_float(v: float) -> float:
    """Sum of v over the thread block (every thread of the block must call it; all get the result)."""
    ...


_SCATTER_WARP_SNIPPET = """
    // the 27 stencil contributions w_ijk (q0 + i a0 + j a1 + k a2), in the order and arithmetic of kernels.py;
    // this thread's part of the stencil: nparts = 1 (all 27), 3 (slab i = part) or 9 (row i, j = part / 3, part % 3)
#if defined(__CUDA_ARCH__)
    const unsigned FULL = 0xffffffffu;
    const int lane = threadIdx.x & 31;
    // lanes scattering the same part of the same stencil (every lane of a warp runs the same number of iterations)
    const unsigned long long key = ok ? ((unsigned long long)base << 4) | (unsigned long long)part
                                      : (1ull << 63) | (unsigned long long)lane;
    const unsigned grp = __match_any_sync(FULL, key);
    const bool leader = ok && ((__ffs(grp) - 1) == lane);
    const unsigned extra = __reduce_max_sync(FULL, (unsigned)(__popc(grp) - 1));  // warp-uniform loop count
    const unsigned mates = leader ? (grp & ~(1u << lane)) : 0u;
#endif
    auto emit_row = [&](const int i, const int j, const float* qij) {
        const float wij = wx.c[i] * wy.c[j];
        const int row = base + i * nyz + j * nz;
        float qk[4] = {qij[0], qij[1], qij[2], qij[3]};
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
        for (int k = 0; k < 3; ++k) {
            const float w = wij * wz.c[k];
            float val[4] = {w * qk[0], w * qk[1], w * qk[2], w * qk[3]};
#if defined(__CUDA_ARCH__)
            unsigned r = mates;
            for (unsigned e = 0; e < extra; ++e) {
                const int src = r ? (__ffs(r) - 1) : lane;
                r &= r - 1u;
                const float o0 = __shfl_sync(FULL, val[0], src);
                const float o1 = __shfl_sync(FULL, val[1], src);
                const float o2 = __shfl_sync(FULL, val[2], src);
                const float o3 = __shfl_sync(FULL, val[3], src);
                if (src != lane) { val[0] += o0; val[1] += o1; val[2] += o2; val[3] += o3; }
            }
            if (leader) {
                float* p = reinterpret_cast<float*>(&grid[row + k]);
#if (__CUDA_ARCH__ >= 900) && (__CUDACC_VER_MAJOR__ >= 12)
                atomicAdd(reinterpret_cast<float4*>(p), make_float4(val[0], val[1], val[2], val[3]));
#else
                atomicAdd(p, val[0]); atomicAdd(p + 1, val[1]); atomicAdd(p + 2, val[2]); atomicAdd(p + 3, val[3]);
#endif
            }
#else
            if (ok) {
                float* p = reinterpret_cast<float*>(&grid[row + k]);
                p[0] += val[0]; p[1] += val[1]; p[2] += val[2]; p[3] += val[3];
            }
#endif
            for (int c = 0; c < 4; ++c) qk[c] += a2.c[c];
        }
    };
    float qi[4] = {q0.c[0], q0.c[1], q0.c[2], q0.c[3]};
    if (nparts == 1) {  // whole stencil (unrolled: register-resident weights)
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
        for (int i = 0; i < 3; ++i) {
            float qij[4] = {qi[0], qi[1], qi[2], qi[3]};
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
            for (int j = 0; j < 3; ++j) {
                emit_row(i, j, qij);
                for (int c = 0; c < 4; ++c) qij[c] += a1.c[c];
            }
            for (int c = 0; c < 4; ++c) qi[c] += a0.c[c];
        }
    } else {  // one slab (nparts = 3) or one row (nparts = 9); same incremental sums as above
        const int ip = nparts == 3 ? part : part / 3;
        const int j0 = nparts == 9 ? part % 3 : 0;
        const int j1 = nparts == 9 ? j0 + 1 : 3;
        for (int i = 0; i < ip; ++i)
            for (int c = 0; c < 4; ++c) qi[c] += a0.c[c];
        float qij[4] = {qi[0], qi[1], qi[2], qi[3]};
        for (int j = 0; j < j0; ++j)
            for (int c = 0; c < 4; ++c) qij[c] += a1.c[c];
        for (int j = j0; j < j1; ++j) {
            emit_row(ip, j, qij);
            for (int c = 0; c < 4; ++c) qij[c] += a1.c[c];
        }
    }
"""


@wp.func_native(_SCATTER_WARP_SNIPPET)
def scatter_stencil_warp(
    ok: int,
    base: int,
    part: int,
    nparts: int,
    nyz: int,
    nz: int,
    q0: wp.vec4,
    a0: wp.vec4,
    a1: wp.vec4,
    a2: wp.vec4,
    wx: wp.vec3,
    wy: wp.vec3,
    wz: wp.vec3,
    grid: wp.array(dtype=wp.vec4),
):
    """Scatter a particle's 27 weighted contributions to the grid; lanes of a warp with the same stencil base are
    summed by warp shuffles first and their lowest lane issues the atomics (every lane of the warp must call)."""
    ...


_SCATTER_SCAN_SNIPPET = """
    // the 27 stencil contributions w_ijk (q0 + i a0 + j a1 + k a2) of the warp's 32 particles (one per lane), scattered
    // row by row: the lanes write their particle's terms to shared memory, then lane 9 g + r (r = row (i, j) = 3 i + j,
    // g = 0, 1, 2: particles [11 g, 11 g + 11) of the warp) walks its particles in order with a window of 3 nodes along
    // z: a particle with the same stencil base as the previous one adds to the window, one based 1 or 2 nodes further
    // (the same grid line: bases are valid nodes) slides it, issuing the nodes left behind; anything else issues the
    // window and starts a new one. In a spatially coherent order (z fastest) the atomics per particle drop from 27
    // (13.5 with pairs merged) to about 7; any order is correct (every contribution is issued exactly once).
#if defined(__CUDA_ARCH__)
    __shared__ float4 scan_buf[(WP_TILE_BLOCK_DIM / 32) * 32 * 7];
    const int lane = threadIdx.x & 31;
    float4* wb = scan_buf + (threadIdx.x >> 5) * (32 * 7);
    __syncwarp();
    {
        float4* my = wb + lane * 7;
        my[0] = make_float4(q0.c[0], q0.c[1], q0.c[2], q0.c[3]);
        my[1] = make_float4(a0.c[0], a0.c[1], a0.c[2], a0.c[3]);
        my[2] = make_float4(a1.c[0], a1.c[1], a1.c[2], a1.c[3]);
        my[3] = make_float4(a2.c[0], a2.c[1], a2.c[2], a2.c[3]);
        my[4] = make_float4(wx.c[0], wx.c[1], wx.c[2], wy.c[0]);
        my[5] = make_float4(wy.c[1], wy.c[2], wz.c[0], wz.c[1]);
        my[6] = make_float4(wz.c[2], __int_as_float(ok ? base : -1), 0.0f, 0.0f);
    }
    __syncwarp();
    if (lane < 27) {
        const int r = lane % 9;
        const int g = lane / 9;
        const int i = r / 3;
        const int j = r - 3 * i;
        const float fi = (float)i;
        const float fj = (float)j;
        const int roff = i * nyz + j * nz;
        const int pend = g == 2 ? 32 : 11 * g + 11;
        float acc0[4] = {0.0f, 0.0f, 0.0f, 0.0f}, acc1[4] = {0.0f, 0.0f, 0.0f, 0.0f}, acc2[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        int cur = -1;
        auto red4 = [&](const int node, const float* val) {
            float* p = reinterpret_cast<float*>(&grid[node]);
#if (__CUDA_ARCH__ >= 900) && (__CUDACC_VER_MAJOR__ >= 12)
            atomicAdd(reinterpret_cast<float4*>(p), make_float4(val[0], val[1], val[2], val[3]));
#else
            atomicAdd(p, val[0]); atomicAdd(p + 1, val[1]); atomicAdd(p + 2, val[2]); atomicAdd(p + 3, val[3]);
#endif
        };
#pragma unroll 1
        for (int pp = 11 * g; pp < pend; ++pp) {
            const float4* d = wb + pp * 7;
            const float4 d6 = d[6];
            const int b = __float_as_int(d6.y);
            if (b < 0) continue;
            const int n = b + roff;
            const int dd = n - cur;
            if (cur >= 0 && dd != 0) {
                if (dd == 1) {
                    red4(cur, acc0);
#pragma unroll
                    for (int c = 0; c < 4; ++c) { acc0[c] = acc1[c]; acc1[c] = acc2[c]; acc2[c] = 0.0f; }
                } else if (dd == 2) {
                    red4(cur, acc0);
                    red4(cur + 1, acc1);
#pragma unroll
                    for (int c = 0; c < 4; ++c) { acc0[c] = acc2[c]; acc1[c] = 0.0f; acc2[c] = 0.0f; }
                } else {
                    red4(cur, acc0);
                    red4(cur + 1, acc1);
                    red4(cur + 2, acc2);
#pragma unroll
                    for (int c = 0; c < 4; ++c) { acc0[c] = 0.0f; acc1[c] = 0.0f; acc2[c] = 0.0f; }
                }
            }
            cur = n;
            const float4 d4 = d[4];
            const float4 d5 = d[5];
            const float wxi = i == 0 ? d4.x : (i == 1 ? d4.y : d4.z);
            const float wyj = j == 0 ? d4.w : (j == 1 ? d5.x : d5.y);
            const float wij = wxi * wyj;
            const float4 e0 = d[0];
            const float4 e1 = d[1];
            const float4 e2 = d[2];
            const float4 e3 = d[3];
            float q[4] = {e0.x + fi * e1.x + fj * e2.x, e0.y + fi * e1.y + fj * e2.y,
                          e0.z + fi * e1.z + fj * e2.z, e0.w + fi * e1.w + fj * e2.w};
            const float a2v[4] = {e3.x, e3.y, e3.z, e3.w};
            const float w0 = wij * d5.z;
            const float w1 = wij * d5.w;
            const float w2 = wij * d6.x;
#pragma unroll
            for (int c = 0; c < 4; ++c) {
                acc0[c] += w0 * q[c];
                const float q1 = q[c] + a2v[c];
                acc1[c] += w1 * q1;
                acc2[c] += w2 * (q1 + a2v[c]);
            }
        }
        if (cur >= 0) {
            red4(cur, acc0);
            red4(cur + 1, acc1);
            red4(cur + 2, acc2);
        }
    }
    __syncwarp();
#else
    if (ok) {
        float qi[4] = {q0.c[0], q0.c[1], q0.c[2], q0.c[3]};
        for (int i = 0; i < 3; ++i) {
            float qij[4] = {qi[0], qi[1], qi[2], qi[3]};
            for (int j = 0; j < 3; ++j) {
                const float wij = wx.c[i] * wy.c[j];
                const int row = base + i * nyz + j * nz;
                float qk[4] = {qij[0], qij[1], qij[2], qij[3]};
                for (int k = 0; k < 3; ++k) {
                    const float w = wij * wz.c[k];
                    float* p = reinterpret_cast<float*>(&grid[row + k]);
                    p[0] += w * qk[0]; p[1] += w * qk[1]; p[2] += w * qk[2]; p[3] += w * qk[3];
                    for (int c = 0; c < 4; ++c) qk[c] += a2.c[c];
                }
                for (int c = 0; c < 4; ++c) qij[c] += a1.c[c];
            }
            for (int c = 0; c < 4; ++c) qi[c] += a0.c[c];
        }
    }
#endif
"""


@wp.func_native(_SCATTER_SCAN_SNIPPET)
def scatter_stencil_scan(
    ok: int,
    base: int,
    nyz: int,
    nz: int,
    q0: wp.vec4,
    a0: wp.vec4,
    a1: wp.vec4,
    a2: wp.vec4,
    wx: wp.vec3,
    wy: wp.vec3,
    wz: wp.vec3,
    grid: wp.array(dtype=wp.vec4),
):
    """Scatter the warp's 32 particles' 27 weighted contributions to the grid row by row, merging consecutive
    particles' overlapping stencil rows in registers (every lane of the warp must call; one particle per thread)."""
    ...


# scatter variants of the one-particle-per-thread kernels: per-node warp shuffles (scatter_stencil_warp) or the row
# scan (scatter_stencil_scan)
SCATTER_WARP, SCATTER_SCAN = 0, 1


def make_p2g_warp(coop: bool = False, module: str | None = None, scatter: int = 0) -> wp.Kernel:
    """The warp-aggregated p2g; coop=True (nparts = 1 only) loads a warp's 32 particles' x, v, F, C as contiguous
    16-byte vector loads through shared memory (``kernels.coop_vec3``)."""

    def _p2g_warp_body(
        x: wp.array(dtype=wp.vec3),
        v: wp.array(dtype=wp.vec3),
        C: wp.array(dtype=wp.mat33),
        F: wp.array(dtype=wp.mat33),
        particle_mass: wp.array(dtype=float),
        particle_vol: wp.array(dtype=float),
        particle_scene: wp.array(dtype=wp.int32),
        scene_start: wp.array(dtype=wp.int32),
        scene_mu: wp.array(dtype=float),
        scene_lambda: wp.array(dtype=float),
        scene_eta: wp.array(dtype=float),
        grid_origin: wp.array(dtype=wp.vec3),
        nx: int,
        ny: int,
        nz: int,
        dx: float,
        dt_arr: wp.array(dtype=float),
        clock_step: wp.array(dtype=wp.int32),
        grid_mvm: wp.array(dtype=wp.vec4),
        fail_step: wp.array(dtype=wp.int32),
        fail_particle: wp.array(dtype=wp.int32),
        nparts: int,
        n_items: int,
    ):
        """Particle to grid (as ``kernels.p2g_apic_neohookean``) with warp-aggregated atomics; nparts (1, 3 or 9)
        consecutive threads share a particle, each scattering its part of the stencil (more threads at small sizes)."""
        t = wp.tid()
        pt = t // nparts
        part = t - pt * nparts
        p = wp.min(pt, n_items - 1)
        ok = pt < n_items
        if wp.static(coop):  # nparts == 1: a warp's 32 consecutive particles as one contiguous span per array
            xp = K.coop_vec3(x, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            vp = K.coop_vec3(v, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            Fp = K.coop_mat33(F, t, n_items, 0, wp.mat33(0.0))
            Cp = K.coop_mat33(C, t, n_items, 0, wp.mat33(0.0))
        else:
            xp = x[p]
            vp = v[p]
            Fp = F[p]
            Cp = C[p]
        if not K.is_finite(K.state_sum(xp, vp, Fp, Cp)):
            ok = False  # gated (never written to the grid); g2p reports it
        s = particle_scene[p]
        inv_dx = 1.0 / dx
        o = grid_origin[s]
        local = xp * inv_dx - o
        bx = int(0)
        by = int(0)
        bz = int(0)
        if ok:
            bx = int(wp.floor(local[0] - 0.5))
            by = int(wp.floor(local[1] - 0.5))
            bz = int(wp.floor(local[2] - 0.5))
            if bx < 0 or by < 0 or bz < 0 or bx > nx - 3 or by > ny - 3 or bz > nz - 3:
                if part == 0:
                    K.flag_failure(fail_step, fail_particle, s, K.FLAG_OUT_OF_GRID, clock_step[0] + 1, p - scene_start[s])
                ok = False
        fx = local - wp.vec3(float(bx), float(by), float(bz))
        wx = K.quadratic_weights(fx[0])
        wy = K.quadratic_weights(fx[1])
        wz = K.quadratic_weights(fx[2])
        q = K.apic_momentum(Fp, Cp, vp, particle_mass[p], particle_vol[p], scene_mu[s], scene_lambda[s], scene_eta[s],
                            dt_arr[0], dx, fx)
        nyz = ny * nz
        base = s * nx * nyz + bx * nyz + by * nz + bz
        ok_i = int(0)
        if ok:
            ok_i = 1
        if wp.static(scatter == SCATTER_SCAN):  # nparts == 1
            scatter_stencil_scan(ok_i, base, nyz, nz, q[0], q[1], q[2], q[3], wx, wy, wz, grid_mvm)
        else:
            scatter_stencil_warp(ok_i, base, part, nparts, nyz, nz, q[0], q[1], q[2], q[3], wx, wy, wz, grid_mvm)

    return wp.kernel(_p2g_warp_body, enable_backward=False, module=module,
                     module_options=None if module != "unique" else dict(K._UNIQUE_OPTIONS))


p2g_warp = make_p2g_warp()


@functools.cache
def p2g_kernel(coop: bool, scatter: int = SCATTER_WARP) -> wp.Kernel:
    """p2g_warp, or its variants with warp-cooperative particle loads and/or the row-scan scatter (SCATTER_SCAN: one
    particle per thread; own modules, compiled on first use)."""
    if not coop and scatter == SCATTER_WARP:
        return p2g_warp
    return make_p2g_warp(coop, module="unique", scatter=scatter)


def make_g2p2g(colliders: bool, coop: bool, agg: bool, scatter: int = SCATTER_WARP, max_regs: int = 0,
               keep_c: bool = False) -> wp.Kernel:
    """g2p of step n fused with p2g of step n+1 (CUDA only; one particle per thread, whole-block launches).

    The g2p part calls the same steps as ``kernels.make_g2p`` (``kernels.g2p_gather``, ``g2p_advect``, ``g2p_ground``,
    ``g2p_colliders``, ``g2p_health``: same switches, same arithmetic in the same order), followed by ``p2g_warp`` on
    the particle's new state, still in registers: the next step's scatter needs no reload of x, v, F, C and no launch
    of its own. Valid when no re-fit comes between the two steps (same grid window) and the grid update of step n
    has run (grid_mvm is clear: it reads grid_v only, and scatters into grid_mvm); ``plan_cuda.py`` uses it inside
    multi-step graphs. The clock: ``clock_step`` already counts step n here (the grid update of step n advanced it),
    as it does for the separate p2g of step n+1, so the out-of-grid flag names the same step.

    keep_c=False (default): C makes no round trip through memory. A live particle's C is rebuilt from the grid by
    every g2p and the fused scatter takes it from registers, so the kernel neither loads nor stores C (72 of the 192
    bytes that a step moves per particle, and the costliest cooperative record moves). The state is updated in place
    (solver.py), so C in memory keeps its value from the block's start until the block's last step, a plain g2p,
    writes the current one; a frozen particle keeps its whole state as before. The frozen test reads x, v and F: a
    non-finite C at a g2p always comes with a non-finite v (both are sums over the same grid velocities with positive
    weights), so C adds nothing to it. keep_c=True loads and stores C as the plain g2p does."""

    def _g2p2g_body(
        x: wp.array(dtype=wp.vec3),
        v: wp.array(dtype=wp.vec3),
        C: wp.array(dtype=wp.mat33),
        F: wp.array(dtype=wp.mat33),
        particle_mass: wp.array(dtype=float),
        particle_scene: wp.array(dtype=wp.int32),
        scene_start: wp.array(dtype=wp.int32),
        grid_v: wp.array(dtype=wp.vec4),
        grid_origin: wp.array(dtype=wp.vec3),
        nx: int,
        ny: int,
        nz: int,
        dx: float,
        dt_arr: wp.array(dtype=float),
        scene_gravity: wp.array(dtype=wp.vec3),
        ground: K.Ground,
        ground_impulse: wp.array(dtype=wp.vec3),
        cols: K.Colliders,
        col_end: K.ColliderMotion,
        col_impulse: wp.array(dtype=wp.vec3),
        limits: K.HealthLimits,
        clock_step: wp.array(dtype=wp.int32),
        fail_step: wp.array(dtype=wp.int32),
        fail_particle: wp.array(dtype=wp.int32),
        x_out: wp.array(dtype=wp.vec3),
        v_out: wp.array(dtype=wp.vec3),
        C_out: wp.array(dtype=wp.mat33),
        F_out: wp.array(dtype=wp.mat33),
        particle_vol: wp.array(dtype=float),
        scene_mu: wp.array(dtype=float),
        scene_lambda: wp.array(dtype=float),
        scene_eta: wp.array(dtype=float),
        grid_mvm: wp.array(dtype=wp.vec4),
        n_items: int,
    ):
        """Grid to particle (as ``kernels.g2p_apic``), then particle to grid for the next step (as ``p2g_warp``)."""
        t = wp.tid()
        live = t < n_items
        p = wp.min(t, n_items - 1)
        if wp.static(coop):
            xp = K.coop_vec3(x, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            vp = K.coop_vec3(v, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            Fp = K.coop_mat33(F, t, n_items, 0, wp.mat33(0.0))
            Cp = wp.mat33(0.0)
            if wp.static(keep_c):
                Cp = K.coop_mat33(C, t, n_items, 0, wp.mat33(0.0))
        else:
            xp = x[p]
            vp = v[p]
            Fp = F[p]
            Cp = wp.mat33(0.0)
            if wp.static(keep_c):
                Cp = C[p]
        if wp.static(agg):
            g_imp = wp.vec3(0.0, 0.0, 0.0)
            g_has = int(0)
            g_scene = int(0)
        s = particle_scene[p]
        pl = p - scene_start[s]
        step = clock_step[0]
        dt = dt_arr[0]
        inv_dx = 1.0 / dx
        o = grid_origin[s]
        m = particle_mass[p]
        # a frozen (non-finite) particle keeps its state and scatters nothing
        xn = xp
        vn = vp
        Cn = Cp
        Fn = Fp
        scat = int(0)
        if live:
            if not K.is_finite(K.state_sum(xp, vp, Fp, Cp)):
                K.flag_failure(fail_step, fail_particle, s, K.FLAG_NONFINITE, step, pl)
            else:
                scat = 1
                vn, Cn = K.g2p_gather(grid_v, xp, vp, s, o, nx, ny, nz, dx, dt, scene_gravity)
                xn, Fn = K.g2p_advect(xp, Fp, vn, Cn, dt)
                if ground.enabled[s] != 0:
                    xn, vn, g_imp_p, g_hit = K.g2p_ground(xn, vn, m, ground.height[s], ground.mu[s])
                    if g_hit != 0:
                        if wp.static(agg):
                            g_imp = g_imp_p
                            g_has = 1
                            g_scene = s
                        else:
                            wp.atomic_add(ground_impulse, s, g_imp_p)
                if wp.static(colliders):
                    xn, vn = K.g2p_colliders(xn, vn, m, s, cols, col_end, col_impulse)
                K.g2p_health(xn, vn, Fn, s, pl, step, limits, fail_step, fail_particle)
                if not wp.static(coop):
                    x_out[p] = xn
                    v_out[p] = vn
                    if wp.static(keep_c):
                        C_out[p] = Cn
                    F_out[p] = Fn
        if wp.static(agg):
            K.warp_add_vec3(ground_impulse, g_scene, g_imp, g_has)  # every lane of the warp
        if wp.static(coop):  # a frozen particle stores back what it loaded
            K.coop_vec3(x_out, t, n_items, 1, xn)
            K.coop_vec3(v_out, t, n_items, 1, vn)
            if wp.static(keep_c):
                K.coop_mat33(C_out, t, n_items, 1, Cn)
            K.coop_mat33(F_out, t, n_items, 1, Fn)
        # p2g of the next step from the state just written (p2g_warp, one thread per particle)
        if scat != 0:
            if not K.is_finite(K.state_sum(xn, vn, Fn, Cn)):
                scat = 0  # gated; the next g2p reports it
        local2 = xn * inv_dx - o
        cx = int(0)
        cy = int(0)
        cz = int(0)
        if scat != 0:
            cx = int(wp.floor(local2[0] - 0.5))
            cy = int(wp.floor(local2[1] - 0.5))
            cz = int(wp.floor(local2[2] - 0.5))
            if cx < 0 or cy < 0 or cz < 0 or cx > nx - 3 or cy > ny - 3 or cz > nz - 3:
                K.flag_failure(fail_step, fail_particle, s, K.FLAG_OUT_OF_GRID, step + 1, pl)
                scat = 0
        f2 = local2 - wp.vec3(float(cx), float(cy), float(cz))
        ux = K.quadratic_weights(f2[0])
        uy = K.quadratic_weights(f2[1])
        uz = K.quadratic_weights(f2[2])
        qm = K.apic_momentum(Fn, Cn, vn, m, particle_vol[p], scene_mu[s], scene_lambda[s], scene_eta[s], dt, dx,
                                 f2)
        nyz2 = ny * nz
        base2 = s * nx * nyz2 + cx * nyz2 + cy * nz + cz
        if wp.static(scatter == SCATTER_SCAN):
            scatter_stencil_scan(scat, base2, nyz2, nz, qm[0], qm[1], qm[2], qm[3], ux, uy, uz, grid_mvm)
        else:
            scatter_stencil_warp(scat, base2, 0, 1, nyz2, nz, qm[0], qm[1], qm[2], qm[3], ux, uy, uz, grid_mvm)

    return wp.kernel(_g2p2g_body, enable_backward=False, module="unique", module_options=dict(K._UNIQUE_OPTIONS),
                     cuda_max_registers=max_regs or None)


@functools.cache
def g2p2g_kernel(colliders: bool, coop: bool, agg: bool, scatter: int = SCATTER_WARP, max_regs: int = 0,
                 keep_c: bool = False) -> wp.Kernel:
    """The fused g2p + next p2g of ``make_g2p2g`` (own module, compiled on first use); max_regs caps its registers
    per thread (0: the compiler's choice); keep_c: C round-trips through memory as in the plain g2p."""
    return make_g2p2g(colliders, coop, agg, scatter, max_regs, keep_c)


@functools.cache
def g2p_kernel(colliders: bool, coop: bool, agg: bool) -> wp.Kernel:
    """kernels.g2p_apic (colliders, not coop, not agg) or one of its CUDA variants (own module, built on first use)."""
    if colliders and not coop and not agg:
        return K.g2p_apic
    return K.make_g2p(colliders, coop, agg, module="unique")


@functools.cache
def grid_update_kernel(colliders: bool, agg: bool, lazy: bool = False) -> wp.Kernel:
    """kernels.grid_update (colliders, not agg, not lazy) or one of its CUDA variants (own module, built on first
    use)."""
    if colliders and not agg and not lazy:
        return K.grid_update
    return K.make_grid_update(colliders, agg, module="unique", lazy=lazy)


@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    __shared__ int last_block_flag;
    __syncthreads();  // this block's partials (written by its thread 0) are issued
    if (threadIdx.x == 0) {
        __threadfence();  // ... and visible device-wide before the ticket is taken
        const int ticket = atomicAdd(&counter[s], 1);
        last_block_flag = (ticket == nblocks - 1) ? 1 : 0;
        if (last_block_flag) counter[s] = 0;  // every block of the scene has counted: ready for the next launch
    }
    __syncthreads();
    if (last_block_flag) __threadfence();
    return last_block_flag;
#else
    counter[s] = counter[s] + 1;  // CPU (tests only): blocks of one thread run in order
    if (counter[s] == nblocks) { counter[s] = 0; return 1; }
    return 0;
#endif
"""
)
def block_is_last(counter: wp.array(dtype=wp.int32), s: int, nblocks: int) -> int:
    """1 in the last of a scene's nblocks thread blocks to get here (all its threads), else 0 (every thread of the
    block must call; the caller's thread 0 has written the block's partials before)."""
    ...


@wp.kernel
def refit_fused(
    x: wp.array(dtype=wp.vec3),
    v: wp.array(dtype=wp.vec3),
    particle_mass: wp.array(dtype=float),
    chunk_scene: wp.array(dtype=wp.int32),
    chunk_begin: wp.array(dtype=wp.int32),
    chunk_end: wp.array(dtype=wp.int32),
    scene_chunk_begin: wp.array(dtype=wp.int32),
    domain_lo: wp.array(dtype=wp.vec3),
    domain_hi: wp.array(dtype=wp.vec3),
    part_lo: wp.array(dtype=wp.vec3),
    part_hi: wp.array(dtype=wp.vec3),
    part_v2: wp.array(dtype=float),
    part_ke: wp.array(dtype=float),
    counter: wp.array(dtype=wp.int32),
    bmin: wp.array(dtype=wp.vec3),
    bmax: wp.array(dtype=wp.vec3),
    speed_max: wp.array(dtype=float),
    kinetic: wp.array(dtype=float),
    nx: int,
    ny: int,
    nz: int,
    dx: float,
    guard_cells: int,
    grid_slide: wp.array(dtype=wp.float64),
    clock_time: wp.array(dtype=wp.float64),
    grid_origin: wp.array(dtype=wp.vec3),
    grid_overflow: wp.array(dtype=wp.int32),
    block: int,
):
    """The whole grid re-fit in one launch: per chunk (one thread block each, block = the launch's block size) the
    reduction of ``kernels.reduce_scene_stats`` into the chunk's partials; then the last block of each scene
    combines the scene's partials into bmin/bmax/speed_max/kinetic and fits its window (``kernels.fit_window``)."""
    t = wp.tid()
    c = t // block
    lane = t - c * block
    s = chunk_scene[c]
    lo = wp.vec3(K.BIG, K.BIG, K.BIG)
    hi = wp.vec3(-K.BIG, -K.BIG, -K.BIG)
    vm = float(0.0)
    ke = float(0.0)
    dlo = domain_lo[s]
    dhi = domain_hi[s]
    for p in range(chunk_begin[c] + lane, chunk_end[c], block):
        xp = x[p]
        vp = v[p]
        v2 = wp.dot(vp, vp)
        if K.is_finite((xp[0] + xp[1]) + (xp[2] + v2)):
            ke += 0.5 * particle_mass[p] * v2
            vm = wp.max(vm, v2)
            inside = xp[0] >= dlo[0] and xp[1] >= dlo[1] and xp[2] >= dlo[2]
            inside = inside and xp[0] <= dhi[0] and xp[1] <= dhi[1] and xp[2] <= dhi[2]
            if inside:
                lo = wp.min(lo, xp)
                hi = wp.max(hi, xp)
        else:
            ke += K.BIG
    lo = wp.vec3(block_min_float(lo[0]), block_min_float(lo[1]), block_min_float(lo[2]))
    hi = wp.vec3(-block_min_float(-hi[0]), -block_min_float(-hi[1]), -block_min_float(-hi[2]))
    vm = -block_min_float(-vm)
    ke = block_sum_float(ke)
    if lane == 0:
        part_lo[c] = lo
        part_hi[c] = hi
        part_v2[c] = vm
        part_ke[c] = ke
    c0 = scene_chunk_begin[s]
    c1 = scene_chunk_begin[s + 1]
    if block_is_last(counter, s, c1 - c0) != 0:  # block-uniform
        lo = wp.vec3(K.BIG, K.BIG, K.BIG)
        hi = wp.vec3(-K.BIG, -K.BIG, -K.BIG)
        vm = float(0.0)
        ke = float(0.0)
        for cc in range(c0 + lane, c1, block):
            lo = wp.min(lo, part_lo[cc])
            hi = wp.max(hi, part_hi[cc])
            vm = wp.max(vm, part_v2[cc])
            ke += part_ke[cc]
        lo = wp.vec3(block_min_float(lo[0]), block_min_float(lo[1]), block_min_float(lo[2]))
        hi = wp.vec3(-block_min_float(-hi[0]), -block_min_float(-hi[1]), -block_min_float(-hi[2]))
        vm = -block_min_float(-vm)
        ke = block_sum_float(ke)
        if lane == 0:
            bmin[s] = lo
            bmax[s] = hi
            speed_max[s] = wp.sqrt(vm)
            kinetic[s] = ke
            K.fit_window(s, lo, hi, nx, ny, nz, dx, guard_cells, K.lattice_shift(s, grid_slide, clock_time), grid_origin,
                         grid_overflow)

