"""Warp kernels of the MLS-MPM step (SI units: m, s, kg, Pa); each kernel does one thing.

Grid layout: B scenes share one flat node array; scene s owns nodes [s*nx*ny*nz, (s+1)*nx*ny*nz). Nodes sit on a
lattice of spacing dx: the world lattice (multiples of dx), or one offset by ``lattice_shift`` when the scene's lattice
moves (a gripper carrying the object); ``grid_origin[s]`` is the position of the scene's node (0, 0, 0) in cells
(lattice index + offset), moved by ``fit_grid`` so that the window follows the particles. A particle whose stencil falls outside its window is gated
(never written to the grid) and flagged, so no kernel can index out of bounds.
"""

from __future__ import annotations

import warp as wp

wp.set_module_options({"enable_backward": False, "optimization_level": 3})

# health flag codes (columns of the per-scene failure tables)
FLAG_NONFINITE = wp.constant(0)
FLAG_LEFT_DOMAIN = wp.constant(1)
FLAG_J_OUT_OF_BOUNDS = wp.constant(2)
FLAG_OUT_OF_GRID = wp.constant(3)
N_FLAGS = 4

# collider kinds
COLLIDER_BOX = wp.constant(0)
COLLIDER_CAPSULE = wp.constant(1)
COLLIDER_HALFSPACE = wp.constant(2)
COLLIDER_PAD = wp.constant(3)  # 3 + 2 axis + (0: gripping face at -axis, 1: at +axis); a box otherwise
COLLIDER_CONVEX = wp.constant(9)  # a convex polytope: params = (first plane, plane count, 0) in the planes array

EPS_V = wp.constant(1.0e-7)  # [m/s] smallest tangential speed in the friction law (avoids 0/0)
BIG = wp.constant(1.0e30)


@wp.func_native(
    """
#if defined(__CUDA_ARCH__) && (__CUDA_ARCH__ >= 900) && (__CUDACC_VER_MAJOR__ >= 12)
    atomicAdd(reinterpret_cast<float4*>(&arr[idx]), make_float4(v.c[0], v.c[1], v.c[2], v.c[3]));
#elif defined(__CUDA_ARCH__)
    float* p = reinterpret_cast<float*>(&arr[idx]);
    atomicAdd(p, v.c[0]); atomicAdd(p + 1, v.c[1]); atomicAdd(p + 2, v.c[2]); atomicAdd(p + 3, v.c[3]);
#else
    float* p = reinterpret_cast<float*>(&arr[idx]);
    p[0] += v.c[0]; p[1] += v.c[1]; p[2] += v.c[2]; p[3] += v.c[3];
#endif
"""
)
def scatter_add_vec4(arr: wp.array(dtype=wp.vec4), idx: int, v: wp.vec4):
    """arr[idx] += v: one 16-byte vector atomic on sm_90+ (4 scalar atomics on older GPUs, plain add on CPU)."""
    ...


# module options of the CUDA-only kernel variants (each built in a module of its own, compiled only when used)
_UNIQUE_OPTIONS = {"enable_backward": False, "optimization_level": 3}


@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    // every lane of the warp calls (one particle per thread, t = the global thread index, whole-warp launches)
    __shared__ float4 coop_buf_v3[(WP_TILE_BLOCK_DIM / 32) * 24];
    const int lane = threadIdx.x & 31;
    float* fb = reinterpret_cast<float*>(coop_buf_v3 + (threadIdx.x >> 5) * 24);
    const int p0 = t - lane;
    int nv = n - p0;
    nv = nv < 0 ? 0 : (nv > 32 ? 32 : nv);
    float* g = reinterpret_cast<float*>(arr.data) + (size_t)p0 * 3;
    __syncwarp();
    if (store) {
        fb[lane * 3] = val.c[0]; fb[lane * 3 + 1] = val.c[1]; fb[lane * 3 + 2] = val.c[2];
        __syncwarp();
        if (nv == 32) { if (lane < 24) reinterpret_cast<float4*>(g)[lane] = reinterpret_cast<const float4*>(fb)[lane]; }
        else { for (int k = lane; k < nv * 3; k += 32) g[k] = fb[k]; }
        __syncwarp();
        return val;
    }
    if (nv == 32) { if (lane < 24) reinterpret_cast<float4*>(fb)[lane] = reinterpret_cast<const float4*>(g)[lane]; }
    else { for (int k = lane; k < nv * 3; k += 32) fb[k] = g[k]; }
    __syncwarp();
    const wp::vec_t<3, float> r(fb[lane * 3], fb[lane * 3 + 1], fb[lane * 3 + 2]);
    __syncwarp();
    return r;
#else
    if (t >= n) return val;
    if (store) { arr.data[t] = val; return val; }
    return arr.data[t];
#endif
"""
)
def coop_vec3(arr: wp.array(dtype=wp.vec3), t: int, n: int, store: int, val: wp.vec3) -> wp.vec3:
    """Warp-cooperative arr[t] (store=0) or arr[t] = val (store=1) for t < n: the warp's 32 consecutive records move
    as 16-byte vector accesses through shared memory (array 16-byte aligned, contiguous). Every lane must call."""
    ...


@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    __shared__ float4 coop_buf_m33[(WP_TILE_BLOCK_DIM / 32) * 72];
    const int lane = threadIdx.x & 31;
    float* fb = reinterpret_cast<float*>(coop_buf_m33 + (threadIdx.x >> 5) * 72);
    const int p0 = t - lane;
    int nv = n - p0;
    nv = nv < 0 ? 0 : (nv > 32 ? 32 : nv);
    float* g = reinterpret_cast<float*>(arr.data) + (size_t)p0 * 9;
    __syncwarp();
    if (store) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) fb[lane * 9 + i * 3 + j] = val.data[i][j];
        __syncwarp();
        if (nv == 32) {
            for (int k = lane; k < 72; k += 32) reinterpret_cast<float4*>(g)[k] = reinterpret_cast<const float4*>(fb)[k];
        } else {
            for (int k = lane; k < nv * 9; k += 32) g[k] = fb[k];
        }
        __syncwarp();
        return val;
    }
    if (nv == 32) {
        for (int k = lane; k < 72; k += 32) reinterpret_cast<float4*>(fb)[k] = reinterpret_cast<const float4*>(g)[k];
    } else {
        for (int k = lane; k < nv * 9; k += 32) fb[k] = g[k];
    }
    __syncwarp();
    wp::mat_t<3, 3, float> r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.data[i][j] = fb[lane * 9 + i * 3 + j];
    __syncwarp();
    return r;
#else
    if (t >= n) return val;
    if (store) { arr.data[t] = val; return val; }
    return arr.data[t];
#endif
"""
)
def coop_mat33(arr: wp.array(dtype=wp.mat33), t: int, n: int, store: int, val: wp.mat33) -> wp.mat33:
    """``coop_vec3`` for mat33 records (36 bytes each)."""
    ...


@wp.func_native(
    """
#if defined(__CUDA_ARCH__)
    // every lane of the warp calls; lanes with has != 0 add v to arr[s]
    const unsigned FULL = 0xffffffffu;
    const unsigned any = __ballot_sync(FULL, has != 0);
    if (any == 0u) return;
    const int first = __ffs(any) - 1;
    const int s0 = __shfl_sync(FULL, s, first);
    if (__all_sync(FULL, has == 0 || s == s0)) {
        float a = has ? v.c[0] : 0.0f;
        float b = has ? v.c[1] : 0.0f;
        float c = has ? v.c[2] : 0.0f;
        for (int o = 16; o > 0; o >>= 1) {
            a += __shfl_xor_sync(FULL, a, o);
            b += __shfl_xor_sync(FULL, b, o);
            c += __shfl_xor_sync(FULL, c, o);
        }
        if ((int)(threadIdx.x & 31) == first) {
            float* p = reinterpret_cast<float*>(&arr.data[s0]);
            atomicAdd(p, a); atomicAdd(p + 1, b); atomicAdd(p + 2, c);
        }
    } else if (has) {
        float* p = reinterpret_cast<float*>(&arr.data[s]);
        atomicAdd(p, v.c[0]); atomicAdd(p + 1, v.c[1]); atomicAdd(p + 2, v.c[2]);
    }
#else
    if (has) arr.data[s] = arr.data[s] + v;
#endif
"""
)
def warp_add_vec3(arr: wp.array(dtype=wp.vec3), s: int, v: wp.vec3, has: int):
    """arr[s] += v for the lanes with has != 0, summed over the warp first when those lanes share s (one atomic
    per warp instead of one per lane: same-address atomics serialise). Every lane of the warp must call."""
    ...


@wp.func
def is_finite(a: float) -> bool:
    """True unless a is NaN or +-inf. A comparison, not wp.isfinite: on CPU that is an out-of-line call, and every
    call in a hot loop forces the compiler to spill all live float registers around it."""
    return wp.abs(a) <= 3.4028234e38


@wp.func
def state_sum(x: wp.vec3, v: wp.vec3, F: wp.mat33, C: wp.mat33) -> float:
    """Sum of all entries of a particle's state as a shallow add tree (short dependency chain): non-finite iff an
    entry is non-finite (or the state is absurdly large, ~1e38)."""
    r = (x + v) + ((F[0] + F[1]) + (F[2] + C[0])) + (C[1] + C[2])
    return (r[0] + r[1]) + r[2]


@wp.func
def quadratic_weights(f: float) -> wp.vec3:
    """Quadratic B-spline weights of the 3 stencil nodes for a particle at offset f in [0.5, 1.5) from the base."""
    a = 1.5 - f
    b = f - 1.0
    c = f - 0.5
    return wp.vec3(0.5 * a * a, 0.75 - b * b, 0.5 * c * c)


@wp.func
def flag_failure(
    fail_step: wp.array(dtype=wp.int32),
    fail_particle: wp.array(dtype=wp.int32),
    scene: int,
    code: int,
    step: int,
    particle_local: int,
):
    """Record a health failure: earliest step, and the lowest particle index failing at that step."""
    slot = scene * 4 + code
    first = wp.atomic_min(fail_step, slot, step)
    if step <= first:  # only particles failing at the earliest step compete for the reported index
        wp.atomic_min(fail_particle, slot, particle_local)


@wp.func
def contact_velocity(v: wp.vec3, vb: wp.vec3, n: wp.vec3, mu: float, bonded: int) -> wp.vec3:
    """Coulomb contact on a velocity: v+ = vb + alpha u_t if u_n < 0 (separation allowed); bonded -> vb."""
    if bonded != 0:
        return vb
    u = v - vb
    un = wp.dot(u, n)
    if un >= 0.0:
        return v
    ut = u - un * n
    ut_len = wp.length(ut)
    alpha = wp.max(0.0, 1.0 - mu * (-un) / wp.max(ut_len, EPS_V))
    return vb + alpha * ut


@wp.func
def convex_sdf(planes: wp.array(dtype=wp.vec4), first: int, count: int, p_local: wp.vec3) -> wp.vec4:
    """Convex polytope {x : n_i . x <= d_i}: phi = max_i (n_i . x - d_i) and that plane's normal. Exact inside and
    on the faces (so the contact test phi <= 0 is exact); outside near edges and corners it is a lower bound of the
    distance, which only matters for how far away a node counts as near."""
    best = wp.vec4(0.0, 0.0, 1.0, -BIG)
    for i in range(first, first + count):
        pl = planes[i]
        d = pl[0] * p_local[0] + pl[1] * p_local[1] + pl[2] * p_local[2] - pl[3]
        if d > best[3]:
            best = wp.vec4(pl[0], pl[1], pl[2], d)
    return best


@wp.func
def collider_sdf(kind: int, params: wp.vec3, p_local: wp.vec3, planes: wp.array(dtype=wp.vec4)) -> wp.vec4:
    """Signed distance [m] (w) and outward unit normal (xyz, local frame) of a collider at a local point."""
    if kind == COLLIDER_CONVEX:
        return convex_sdf(planes, int(params[0]), int(params[1]), p_local)
    if kind == COLLIDER_BOX or kind >= COLLIDER_PAD:
        q = wp.vec3(wp.abs(p_local[0]), wp.abs(p_local[1]), wp.abs(p_local[2])) - params
        qmax = wp.max(q[0], wp.max(q[1], q[2]))
        if qmax > 0.0:
            qo = wp.vec3(wp.max(q[0], 0.0), wp.max(q[1], 0.0), wp.max(q[2], 0.0))
            dist = wp.length(qo)
            nb = wp.vec3(wp.sign(p_local[0]) * qo[0], wp.sign(p_local[1]) * qo[1], wp.sign(p_local[2]) * qo[2]) / dist
            return wp.vec4(nb[0], nb[1], nb[2], dist)
        if kind >= COLLIDER_PAD:
            # a finger pad: inside, the material leaves through the gripping face only (a node near the pad's rim
            # would otherwise take a side face's normal and let the material flow into the pad unresisted)
            a = (kind - COLLIDER_PAD) // 2
            sgn = float(2 * ((kind - COLLIDER_PAD) % 2) - 1)
            nrm = wp.vec3(0.0, 0.0, 0.0)
            nrm[a] = sgn
            return wp.vec4(nrm[0], nrm[1], nrm[2], -(params[a] - sgn * p_local[a]))
        # inside: leave through the nearest face
        if q[0] >= q[1] and q[0] >= q[2]:
            return wp.vec4(wp.sign(p_local[0]), 0.0, 0.0, qmax)
        if q[1] >= q[2]:
            return wp.vec4(0.0, wp.sign(p_local[1]), 0.0, qmax)
        return wp.vec4(0.0, 0.0, wp.sign(p_local[2]), qmax)
    if kind == COLLIDER_CAPSULE:
        # params: (radius, half_length along local z, unused)
        c = wp.vec3(0.0, 0.0, wp.clamp(p_local[2], -params[1], params[1]))
        d = p_local - c
        dl = wp.length(d)
        if dl > 1.0e-12:
            n = d / dl
            return wp.vec4(n[0], n[1], n[2], dl - params[0])
        return wp.vec4(1.0, 0.0, 0.0, -params[0])
    # half-space: solid below the local z = 0 plane
    return wp.vec4(0.0, 0.0, 1.0, p_local[2])


@wp.func
def collider_contact(
    kind: int,
    params: wp.vec3,
    pos: wp.vec3,
    rot: wp.quat,
    lin_vel: wp.vec3,
    ang_vel: wp.vec3,
    x: wp.vec3,
    planes: wp.array(dtype=wp.vec4),
) -> wp.mat33:
    """World-frame query at x: rows = (normal, collider velocity at x, (phi, 0, 0))."""
    r = x - pos
    sd = collider_sdf(kind, params, wp.quat_rotate_inv(rot, r), planes)
    n = wp.quat_rotate(rot, wp.vec3(sd[0], sd[1], sd[2]))
    vb = lin_vel + wp.cross(ang_vel, r)
    return wp.mat33(n[0], n[1], n[2], vb[0], vb[1], vb[2], sd[3], 0.0, 0.0)


@wp.func
def gather_row(grid_v: wp.array(dtype=wp.vec4), row: int, wz: wp.vec3) -> wp.mat33:
    """Weighted sums along z of 3 nodes: rows (sum_k w_k v_k, sum_k k w_k v_k, unused)."""
    g0 = grid_v[row]
    g1 = grid_v[row + 1]
    g2 = grid_v[row + 2]
    a1 = wz[1] * wp.vec3(g1[0], g1[1], g1[2])
    a2 = wz[2] * wp.vec3(g2[0], g2[1], g2[2])
    s0 = wz[0] * wp.vec3(g0[0], g0[1], g0[2]) + a1 + a2
    s1 = a1 + 2.0 * a2
    return wp.mat33(s0[0], s0[1], s0[2], s1[0], s1[1], s1[2], 0.0, 0.0, 0.0)


# -- argument bundles of the step kernels ----------------------------------------------------------------------------
@wp.struct
class Ground:
    """The ground plane of each scene: enabled (0/1), height [m] (z), Coulomb friction [-]."""

    enabled: wp.array(dtype=wp.int32)
    height: wp.array(dtype=float)
    mu: wp.array(dtype=float)


@wp.struct
class Colliders:
    """The kinematic colliders' shapes: scene s owns [start[s], start[s] + count[s]); kind (COLLIDER_*), params
    (box half extents [m] / capsule radius and half length [m] / convex polytope planes), the planes of the convex
    ones, bounding sphere radius^2 [m^2] around the pose, friction [-], bonded (0/1)."""

    start: wp.array(dtype=wp.int32)
    count: wp.array(dtype=wp.int32)
    kind: wp.array(dtype=wp.int32)
    params: wp.array(dtype=wp.vec3)
    planes: wp.array(dtype=wp.vec4)
    radius2: wp.array(dtype=float)
    mu: wp.array(dtype=float)
    bonded: wp.array(dtype=wp.int32)


@wp.struct
class ColliderMotion:
    """The colliders' poses at one instant of the step (position [m], rotation) and velocities [m/s], [rad/s]."""

    pos: wp.array(dtype=wp.vec3)
    rot: wp.array(dtype=wp.quat)
    lin_vel: wp.array(dtype=wp.vec3)
    ang_vel: wp.array(dtype=wp.vec3)


@wp.struct
class HealthLimits:
    """What a healthy particle keeps to: each scene's domain box [m] and det(F) in [j_min, j_max]."""

    domain_lo: wp.array(dtype=wp.vec3)
    domain_hi: wp.array(dtype=wp.vec3)
    j_min: float
    j_max: float


@wp.kernel
def update_collider_poses(
    ref_pos: wp.array(dtype=wp.vec3),
    ref_rot: wp.array(dtype=wp.quat),
    ref_time: wp.array(dtype=wp.float64),
    lin_vel: wp.array(dtype=wp.vec3),
    ang_vel: wp.array(dtype=wp.vec3),
    clock_time: wp.array(dtype=wp.float64),
    dt_arr: wp.array(dtype=float),
    pos_start: wp.array(dtype=wp.vec3),
    rot_start: wp.array(dtype=wp.quat),
    pos_end: wp.array(dtype=wp.vec3),
    rot_end: wp.array(dtype=wp.quat),
):
    """Poses of kinematic colliders at the start and end of this step from reference pose + constant velocity."""
    c = wp.tid()
    t0 = float(clock_time[0] - ref_time[c])
    for e in range(2):
        t = t0 + float(e) * dt_arr[0]
        w = ang_vel[c]
        wl = wp.length(w)
        q = ref_rot[c]
        if wl > 0.0:
            q = wp.normalize(wp.quat_from_axis_angle(w / wl, wl * t) * q)
        p = ref_pos[c] + lin_vel[c] * t
        if e == 0:
            pos_start[c] = p
            rot_start[c] = q
        else:
            pos_end[c] = p
            rot_end[c] = q


@wp.func
def apic_momentum(Fp: wp.mat33, Cp: wp.mat33, vp: wp.vec3, m: float, vol: float, mu: float, lam: float,
                  eta: float, dt: float, dx: float, fx: wp.vec3) -> wp.mat44:
    """What a particle scatters (MLS-MPM, APIC, neo-Hookean + Kelvin-Voigt viscosity eta [Pa s]): rows (q0, a0, a1,
    a2) such that the momentum + mass it gives the node at stencil offset (i, j, k) is w_ijk (q0 + i a0 + j a1 + k
    a2); fx = position in cells from the stencil base."""
    inv_dx = 1.0 / dx
    J = wp.determinant(Fp)
    # Kirchhoff stress tau = mu (F F^T - I) + lambda ln(J) I  (neo-Hookean)
    tau = mu * (Fp * wp.transpose(Fp) - wp.identity(n=3, dtype=float)) + lam * wp.log(
        wp.max(J, 1.0e-6)
    ) * wp.identity(n=3, dtype=float)
    if eta > 0.0:
        # Kelvin-Voigt: Cauchy sigma_v = eta (C + C^T), C the APIC affine velocity gradient; Kirchhoff tau_v = J sigma_v
        # (eta = 0 skips it: the neo-Hookean arithmetic bit for bit)
        tau = tau + (eta * J) * (Cp + wp.transpose(Cp))
    affine = (-dt * vol * 4.0 * inv_dx * inv_dx) * tau + m * Cp
    # momentum at node offset (i,j,k): w * (m v + A (ijk - fx) dx) = w * (q0 + i a0 + j a1 + k a2)
    q0v = m * vp - affine * (fx * dx)
    return wp.mat44(q0v[0], q0v[1], q0v[2], m,
                    affine[0, 0] * dx, affine[1, 0] * dx, affine[2, 0] * dx, 0.0,
                    affine[0, 1] * dx, affine[1, 1] * dx, affine[2, 1] * dx, 0.0,
                    affine[0, 2] * dx, affine[1, 2] * dx, affine[2, 2] * dx, 0.0)


@wp.func
def lattice_shift(s: int, grid_slide: wp.array(dtype=wp.float64), clock_time: wp.array(dtype=wp.float64)) -> wp.vec3:
    """Scene s's lattice offset now, in cells, in [0, 1): grid_slide[8 s:8 s + 8] = (offset at the reference time
    (3), reference time [s], lattice velocity [cells/s] (3), unused); all zero = the fixed world lattice."""
    b = s * 8
    t = clock_time[0] - grid_slide[b + 3]
    a0 = grid_slide[b] + grid_slide[b + 4] * t
    a1 = grid_slide[b + 1] + grid_slide[b + 5] * t
    a2 = grid_slide[b + 2] + grid_slide[b + 6] * t
    return wp.vec3(float(a0 - wp.floor(a0)), float(a1 - wp.floor(a1)), float(a2 - wp.floor(a2)))


@wp.func
def fit_window(s: int, lo: wp.vec3, hi: wp.vec3, nx: int, ny: int, nz: int, dx: float, guard_cells: int,
               shift: wp.vec3, grid_origin: wp.array(dtype=wp.vec3), grid_overflow: wp.array(dtype=wp.int32)):
    """Centre scene s's grid window on bounds [lo, hi] [m] on the lattice offset by shift [cells]; flag the scene when
    they no longer fit (no bounds: no-op). grid_origin[s] = position of node (0, 0, 0) in cells (lattice index +
    shift)."""
    if lo[0] > hi[0]:
        return
    inv_dx = 1.0 / dx
    c = 0.5 * (lo + hi) * inv_dx - shift
    grid_origin[s] = wp.vec3(
        float(int(wp.floor(c[0])) - nx // 2) + shift[0], float(int(wp.floor(c[1])) - ny // 2) + shift[1],
        float(int(wp.floor(c[2])) - nz // 2) + shift[2]
    )
    ext = (hi - lo) * inv_dx
    g = float(2 * guard_cells + 3)
    if ext[0] + g > float(nx) or ext[1] + g > float(ny) or ext[2] + g > float(nz):
        grid_overflow[s] = 1


@wp.func
def p2g_particle(
    xp: wp.vec3,
    vp: wp.vec3,
    Cp: wp.mat33,
    Fp: wp.mat33,
    m: float,
    vol: float,
    s: int,
    pl: int,
    mu: float,
    lam: float,
    eta: float,
    o: wp.vec3,
    nx: int,
    ny: int,
    nz: int,
    dx: float,
    dt: float,
    step_next: int,
    grid_mvm: wp.array(dtype=wp.vec4),
    fail_step: wp.array(dtype=wp.int32),
    fail_particle: wp.array(dtype=wp.int32),
):
    """Scatter one particle's APIC momentum, stress impulse and mass (state x, v, C, F; scene s, scene-local index
    pl, window origin o [cells]); a non-finite state is gated (g2p reports it), one outside the window is flagged as
    out of the grid at step step_next."""
    if not is_finite(state_sum(xp, vp, Fp, Cp)):
        return  # gated (never written to the grid); g2p reports it
    inv_dx = 1.0 / dx
    local = xp * inv_dx - o
    bx = int(wp.floor(local[0] - 0.5))
    by = int(wp.floor(local[1] - 0.5))
    bz = int(wp.floor(local[2] - 0.5))
    if bx < 0 or by < 0 or bz < 0 or bx > nx - 3 or by > ny - 3 or bz > nz - 3:
        flag_failure(fail_step, fail_particle, s, FLAG_OUT_OF_GRID, step_next, pl)
        return
    fx = local - wp.vec3(float(bx), float(by), float(bz))
    wx = quadratic_weights(fx[0])
    wy = quadratic_weights(fx[1])
    wz = quadratic_weights(fx[2])

    q = apic_momentum(Fp, Cp, vp, m, vol, mu, lam, eta, dt, dx, fx)
    q0 = q[0]
    a0 = q[1]
    a1 = q[2]
    a2 = q[3]
    nyz = ny * nz
    base = s * nx * nyz + bx * nyz + by * nz + bz
    qi = q0
    for i in range(3):
        qij = qi
        for j in range(3):
            wij = wx[i] * wy[j]
            row = base + i * nyz + j * nz
            scatter_add_vec4(grid_mvm, row, (wij * wz[0]) * qij)
            q1 = qij + a2
            scatter_add_vec4(grid_mvm, row + 1, (wij * wz[1]) * q1)
            scatter_add_vec4(grid_mvm, row + 2, (wij * wz[2]) * (q1 + a2))
            qij = qij + a1
        qi = qi + a0


@wp.kernel
def p2g_apic_neohookean(
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
    per_thread: int,
    n_items: int,
):
    """Particle to grid: scatter APIC momentum, neo-Hookean Kirchhoff stress impulse and mass (MLS-MPM)."""
    t = wp.tid()
    for p in range(t * per_thread, wp.min((t + 1) * per_thread, n_items)):
        s = particle_scene[p]
        p2g_particle(x[p], v[p], C[p], F[p], particle_mass[p], particle_vol[p], s, p - scene_start[s], scene_mu[s],
                     scene_lambda[s], scene_eta[s], grid_origin[s], nx, ny, nz, dx, dt_arr[0], clock_step[0] + 1,
                     grid_mvm, fail_step, fail_particle)


def make_grid_update(colliders: bool = True, agg: bool = False, module: str | None = None, lazy: bool = False,
                     merge: bool = False) -> wp.Kernel:
    """The grid update kernel. colliders=False leaves out the kinematic-collider contact (scenes with only the
    ground: no per-node collider loop, fewer registers). agg=True (CUDA only: one node per thread, whole-warp
    launches) sums a warp's ground impulses by shuffles and issues one atomic per warp instead of one per node (they
    all go to the scene's one ground_impulse entry, and same-address atomics serialise). lazy=True writes nothing for
    a node without mass: its scatter buffer is already clear, and its velocity is stale but read only with a zero
    weight (a particle's stencil nodes all get mass from it; weights are zero only on a stencil's edge), so the
    rollout is the same bit for bit. colliders=True, agg=lazy=False is the reference kernel (the CPU path,
    unchanged). merge=True (CPU, threads sharing a rollout): grid_mvm is the main scatter buffer followed by the
    chunks' (n_items nodes each); each node first adds the chunks' entries in chunk order and clears them, as
    ``cpu_threads.merge_grids`` did in a pass of its own (same sums, bit for bit)."""

    def _grid_update_body(
        grid_mvm: wp.array(dtype=wp.vec4),
        grid_v: wp.array(dtype=wp.vec4),
        grid_origin: wp.array(dtype=wp.vec3),
        nx: int,
        ny: int,
        nz: int,
        dx: float,
        dt_arr: wp.array(dtype=float),
        scene_gravity: wp.array(dtype=wp.vec3),
        scene_damping: wp.array(dtype=float),
        grid_slide: wp.array(dtype=wp.float64),
        ground: Ground,
        ground_impulse: wp.array(dtype=wp.vec3),
        cols: Colliders,
        col_start_pose: ColliderMotion,
        col_impulse: wp.array(dtype=wp.vec3),
        clock_time: wp.array(dtype=wp.float64),
        clock_step: wp.array(dtype=wp.int32),
        per_thread: int,
        n_items: int,
    ):
        """Grid: momentum -> velocity, gravity, damping rate (relative to the lattice velocity), ground + collider
        contact; clears the scatter buffer.

        Impulses accumulated in ``ground_impulse`` / ``col_impulse`` are J = m_node (v+ - v) [N s]: the momentum the
        ground/collider gives the OBJECT. The force the object exerts on the collider is -sum(J)/interval.
        """
        t = wp.tid()
        if wp.static(agg):
            g_imp = wp.vec3(0.0, 0.0, 0.0)
            g_has = int(0)
            g_scene = int(0)
        for n in range(t * per_thread, wp.min((t + 1) * per_thread, n_items)):
            if n == 0:
                clock_time[0] = clock_time[0] + wp.float64(dt_arr[0])
                clock_step[0] = clock_step[0] + 1
            mvm = grid_mvm[n]
            if wp.static(merge):
                for j in range(n + n_items, grid_mvm.shape[0], n_items):
                    mvm = mvm + grid_mvm[j]
                    grid_mvm[j] = wp.vec4(0.0, 0.0, 0.0, 0.0)
            m = mvm[3]
            if wp.static(lazy):
                if m <= 0.0:
                    if m != 0.0 or mvm[0] != 0.0 or mvm[1] != 0.0 or mvm[2] != 0.0:
                        grid_mvm[n] = wp.vec4(0.0, 0.0, 0.0, 0.0)
                    continue
                grid_mvm[n] = wp.vec4(0.0, 0.0, 0.0, 0.0)
            else:
                grid_mvm[n] = wp.vec4(0.0, 0.0, 0.0, 0.0)
                if m <= 0.0:
                    grid_v[n] = wp.vec4(0.0, 0.0, 0.0, 0.0)
                    continue
            dt = dt_arr[0]
            cells = nx * ny * nz
            s = n // cells
            r = n - s * cells
            i = r // (ny * nz)
            j = (r // nz) % ny
            k = r % nz
            v = wp.vec3(mvm[0], mvm[1], mvm[2]) / m
            if wp.static(colliders):
                # the damping rate acts relative to the scene's lattice velocity: zero, or the gripper's while it
                # carries the object (a damping at rest in the world would drag a carried object out of the hand)
                b = s * 8
                vr = wp.vec3(float(grid_slide[b + 4]), float(grid_slide[b + 5]), float(grid_slide[b + 6])) * dx
                if vr[0] != 0.0 or vr[1] != 0.0 or vr[2] != 0.0:
                    v = vr + (v + dt * scene_gravity[s] - vr) * wp.exp(-scene_damping[s] * dt)
                else:
                    v = (v + dt * scene_gravity[s]) * wp.exp(-scene_damping[s] * dt)
            else:
                v = (v + dt * scene_gravity[s]) * wp.exp(-scene_damping[s] * dt)
            o = grid_origin[s]
            xn = (o + wp.vec3(float(i), float(j), float(k))) * dx
            if ground.enabled[s] != 0:
                if xn[2] <= ground.height[s]:
                    vplus = contact_velocity(v, wp.vec3(0.0, 0.0, 0.0), wp.vec3(0.0, 0.0, 1.0), ground.mu[s], 0)
                    if wp.static(agg):
                        g_imp = m * (vplus - v)
                        g_has = 1
                        g_scene = s
                    else:
                        wp.atomic_add(ground_impulse, s, m * (vplus - v))
                    v = vplus
            if wp.static(colliders):
                c0 = cols.start[s]
                for c in range(c0, c0 + cols.count[s]):
                    rel = xn - col_start_pose.pos[c]
                    if wp.dot(rel, rel) > cols.radius2[c]:
                        continue  # outside the collider's bounding sphere
                    q = collider_contact(cols.kind[c], cols.params[c], col_start_pose.pos[c], col_start_pose.rot[c],
                                         col_start_pose.lin_vel[c], col_start_pose.ang_vel[c], xn, cols.planes)
                    if q[2, 0] <= 0.0:
                        vplus = contact_velocity(v, wp.vec3(q[1, 0], q[1, 1], q[1, 2]),
                                                 wp.vec3(q[0, 0], q[0, 1], q[0, 2]), cols.mu[c], cols.bonded[c])
                        wp.atomic_add(col_impulse, c, m * (vplus - v))
                        v = vplus
            grid_v[n] = wp.vec4(v[0], v[1], v[2], 0.0)
        if wp.static(agg):
            warp_add_vec3(ground_impulse, g_scene, g_imp, g_has)  # every lane of the warp (whole-warp launches)

    return wp.kernel(_grid_update_body, enable_backward=False, module=module,
                     module_options=None if module != "unique" else dict(_UNIQUE_OPTIONS))


grid_update = make_grid_update()
# CPU with threads sharing a rollout: the chunk grids' merge folded into the grid update (one pass over the nodes)
grid_update_merge_cpu = make_grid_update(module="unique", merge=True)


# -- the steps of a particle's grid-to-particle update (shared by g2p, the fused CPU g2p + p2g and the fused CUDA
# g2p2g of kernels_cuda.py: one body, the same arithmetic in the same order) ----------------------------------------
@wp.func
def g2p_gather(
    grid_v: wp.array(dtype=wp.vec4),
    xp: wp.vec3,
    vp: wp.vec3,
    s: int,
    o: wp.vec3,
    nx: int,
    ny: int,
    nz: int,
    dx: float,
    dt: float,
    scene_gravity: wp.array(dtype=wp.vec3),
):
    """Velocity [m/s] and APIC affine field C [1/s] at a particle at xp of scene s (window origin o [cells]) from the
    grid velocities of its 27 stencil nodes; outside the grid window ballistic (v + dt g, C = 0; flagged in p2g)."""
    inv_dx = 1.0 / dx
    local = xp * inv_dx - o
    bx = int(wp.floor(local[0] - 0.5))
    by = int(wp.floor(local[1] - 0.5))
    bz = int(wp.floor(local[2] - 0.5))
    vn = wp.vec3(0.0, 0.0, 0.0)
    Cn = wp.mat33(0.0)
    if bx < 0 or by < 0 or bz < 0 or bx > nx - 3 or by > ny - 3 or bz > nz - 3:
        vn = vp + dt * scene_gravity[s]  # outside the grid window: ballistic (flagged in p2g)
    else:
        fx = local - wp.vec3(float(bx), float(by), float(bz))
        wx = quadratic_weights(fx[0])
        wy = quadratic_weights(fx[1])
        wz = quadratic_weights(fx[2])
        nyz = ny * nz
        base = s * nx * nyz + bx * nyz + by * nz + bz
        si = wp.vec3(0.0, 0.0, 0.0)
        sj = wp.vec3(0.0, 0.0, 0.0)
        sk = wp.vec3(0.0, 0.0, 0.0)
        for i in range(3):
            bi = base + i * nyz
            r0 = gather_row(grid_v, bi, wz)
            r1 = gather_row(grid_v, bi + nz, wz)
            r2 = gather_row(grid_v, bi + 2 * nz, wz)
            # r = (sum_k w_k v_k, sum_k k w_k v_k) per row j
            p0 = wy[0] * wp.vec3(r0[0, 0], r0[0, 1], r0[0, 2])
            p1 = wy[1] * wp.vec3(r1[0, 0], r1[0, 1], r1[0, 2])
            p2 = wy[2] * wp.vec3(r2[0, 0], r2[0, 1], r2[0, 2])
            ps = p0 + p1 + p2
            pj = p1 + 2.0 * p2
            pk = (wy[0] * wp.vec3(r0[1, 0], r0[1, 1], r0[1, 2]) + wy[1] * wp.vec3(r1[1, 0], r1[1, 1], r1[1, 2])
                  + wy[2] * wp.vec3(r2[1, 0], r2[1, 1], r2[1, 2]))
            b = wx[i] * ps
            vn += b
            if i > 0:
                si += float(i) * b
            sj += wx[i] * pj
            sk += wx[i] * pk
        # B = sum w v (ijk - fx)^T dx ; C = 4 B / dx^2
        scale = 4.0 * inv_dx
        c0 = (si - fx[0] * vn) * scale
        c1 = (sj - fx[1] * vn) * scale
        c2 = (sk - fx[2] * vn) * scale
        Cn = wp.mat33(c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2])
    return vn, Cn


@wp.func
def g2p_advect(xp: wp.vec3, Fp: wp.mat33, vn: wp.vec3, Cn: wp.mat33, dt: float):
    """Position [m] and deformation gradient after dt [s] at velocity vn and velocity gradient Cn."""
    return xp + dt * vn, Fp + dt * (Cn * Fp)


@wp.func
def g2p_ground(xn: wp.vec3, vn: wp.vec3, m: float, height: float, mu: float):
    """Residual ground penetration: a particle of mass m [kg] below the ground at height [m] is put back on it and
    loses its inward velocity (Coulomb, friction mu). Returns (x, v, impulse [N s] the ground gave, 1 if in contact)."""
    x = xn
    v = vn
    imp = wp.vec3(0.0, 0.0, 0.0)
    hit = int(0)
    if xn[2] < height:
        x = wp.vec3(xn[0], xn[1], height)
        vplus = contact_velocity(vn, wp.vec3(0.0, 0.0, 0.0), wp.vec3(0.0, 0.0, 1.0), mu, 0)
        imp = m * (vplus - vn)
        hit = 1
        v = vplus
    return x, v, imp, hit


@wp.func
def g2p_colliders(
    xn: wp.vec3,
    vn: wp.vec3,
    m: float,
    s: int,
    cols: Colliders,
    motion: ColliderMotion,
    col_impulse: wp.array(dtype=wp.vec3),
):
    """Residual penetration of scene s's kinematic colliders (poses at the step's end): the particle is pushed back
    to each surface and loses its inward relative velocity; the impulses go to col_impulse. Returns (x, v)."""
    x = xn
    v = vn
    c_first = cols.start[s]
    for c in range(c_first, c_first + cols.count[s]):
        rel = x - motion.pos[c]
        if wp.dot(rel, rel) > cols.radius2[c]:
            continue
        q = collider_contact(cols.kind[c], cols.params[c], motion.pos[c], motion.rot[c], motion.lin_vel[c],
                             motion.ang_vel[c], x, cols.planes)
        phi = q[2, 0]
        if phi < 0.0:
            nrm = wp.vec3(q[0, 0], q[0, 1], q[0, 2])
            x = x - phi * nrm
            vplus = contact_velocity(v, wp.vec3(q[1, 0], q[1, 1], q[1, 2]), nrm, cols.mu[c], cols.bonded[c])
            wp.atomic_add(col_impulse, c, m * (vplus - v))
            v = vplus
    return x, v


@wp.func
def g2p_health(
    xn: wp.vec3,
    vn: wp.vec3,
    Fn: wp.mat33,
    s: int,
    pl: int,
    step: int,
    limits: HealthLimits,
    fail_step: wp.array(dtype=wp.int32),
    fail_particle: wp.array(dtype=wp.int32),
):
    """Health checks of a particle's new state: non-finite, det(F) outside [j_min, j_max], outside the domain."""
    J = wp.determinant(Fn)
    xv = xn + vn
    if not is_finite((xv[0] + xv[1]) + (xv[2] + J)):  # Cn enters Fn, so J covers it
        flag_failure(fail_step, fail_particle, s, FLAG_NONFINITE, step, pl)
    else:
        if J < limits.j_min or J > limits.j_max:
            flag_failure(fail_step, fail_particle, s, FLAG_J_OUT_OF_BOUNDS, step, pl)
        lo = limits.domain_lo[s]
        hi = limits.domain_hi[s]
        if xn[0] < lo[0] or xn[1] < lo[1] or xn[2] < lo[2] or xn[0] > hi[0] or xn[1] > hi[1] or xn[2] > hi[2]:
            flag_failure(fail_step, fail_particle, s, FLAG_LEFT_DOMAIN, step, pl)


def make_g2p(colliders: bool = True, coop: bool = False, agg: bool = False, module: str | None = None,
             scatter_next: bool = False) -> wp.Kernel:
    """The grid-to-particle kernel. colliders=False leaves out the kinematic-collider contact (scenes with only the
    ground). CUDA only, one particle per thread and whole-warp launches: coop=True moves a warp's 32 particles' x, v,
    F, C as contiguous 16-byte loads/stores through shared memory (a lane's own scalar accesses to 36-byte mat33
    records touch ~9 cache lines per warp instruction); agg=True sums a warp's ground impulses by shuffles (one
    atomic per warp). colliders=True, coop=agg=False is the reference kernel (the CPU path, unchanged: same rollout
    bit for bit). scatter_next=True (CPU, with coop=agg=False) also does the next step's p2g of each particle from
    its new state (``p2g_particle``, as ``p2g_apic_neohookean`` would after reloading it): valid when the grid update
    has cleared grid_mvm and no re-fit comes before the next step; same results bit for bit, one pass over the
    particles fewer per step. The particle's steps are the shared functions ``g2p_gather``, ``g2p_advect``,
    ``g2p_ground``, ``g2p_colliders`` and ``g2p_health`` (also the body of ``kernels_cuda.make_g2p2g``)."""

    def _g2p_body(
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
        ground: Ground,
        ground_impulse: wp.array(dtype=wp.vec3),
        cols: Colliders,
        col_end: ColliderMotion,
        col_impulse: wp.array(dtype=wp.vec3),
        limits: HealthLimits,
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
        per_thread: int,
        n_items: int,
    ):
        """Grid to particle: gather velocity and APIC affine field, advect, update F, fix penetration, check health."""
        t = wp.tid()
        if wp.static(coop):
            # one particle per thread, a warp's 32 consecutive particles moved as one contiguous span (every lane calls;
            # lanes past n_items take part and write nothing). A frozen particle stores back what it loaded.
            xo = coop_vec3(x, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            vo = coop_vec3(v, t, n_items, 0, wp.vec3(0.0, 0.0, 0.0))
            Fo = coop_mat33(F, t, n_items, 0, wp.mat33(0.0))
            Co = coop_mat33(C, t, n_items, 0, wp.mat33(0.0))
        if wp.static(agg):
            g_imp = wp.vec3(0.0, 0.0, 0.0)
            g_has = int(0)
            g_scene = int(0)
        for p in range(t * per_thread, wp.min((t + 1) * per_thread, n_items)):
            s = particle_scene[p]
            pl = p - scene_start[s]
            step = clock_step[0]
            if wp.static(coop):
                xp = xo
                vp = vo
                Fp = Fo
                Cp = Co
            else:
                xp = x[p]
                vp = v[p]
                Fp = F[p]
                Cp = C[p]
            if not is_finite(state_sum(xp, vp, Fp, Cp)):
                flag_failure(fail_step, fail_particle, s, FLAG_NONFINITE, step, pl)
                continue  # frozen: never spreads into the grid
            dt = dt_arr[0]
            o = grid_origin[s]
            vn, Cn = g2p_gather(grid_v, xp, vp, s, o, nx, ny, nz, dx, dt, scene_gravity)
            xn, Fn = g2p_advect(xp, Fp, vn, Cn, dt)
            m = particle_mass[p]
            # residual penetration: push the particle back to the surface, remove inward relative velocity
            if ground.enabled[s] != 0:
                xn, vn, g_imp_p, g_hit = g2p_ground(xn, vn, m, ground.height[s], ground.mu[s])
                if g_hit != 0:
                    if wp.static(agg):
                        g_imp = g_imp_p
                        g_has = 1
                        g_scene = s
                    else:
                        wp.atomic_add(ground_impulse, s, g_imp_p)
            if wp.static(colliders):
                xn, vn = g2p_colliders(xn, vn, m, s, cols, col_end, col_impulse)
            g2p_health(xn, vn, Fn, s, pl, step, limits, fail_step, fail_particle)
            if wp.static(coop):
                xo = xn
                vo = vn
                Co = Cn
                Fo = Fn
            else:
                x_out[p] = xn
                v_out[p] = vn
                C_out[p] = Cn
                F_out[p] = Fn
            if wp.static(scatter_next):
                p2g_particle(xn, vn, Cn, Fn, m, particle_vol[p], s, pl, scene_mu[s], scene_lambda[s], scene_eta[s], o,
                             nx, ny, nz, dx, dt, step + 1, grid_mvm, fail_step, fail_particle)
        if wp.static(agg):
            warp_add_vec3(ground_impulse, g_scene, g_imp, g_has)  # every lane of the warp (whole-warp launches)
        if wp.static(coop):
            coop_vec3(x_out, t, n_items, 1, xo)
            coop_vec3(v_out, t, n_items, 1, vo)
            coop_mat33(C_out, t, n_items, 1, Co)
            coop_mat33(F_out, t, n_items, 1, Fo)

    return wp.kernel(_g2p_body, enable_backward=False, module=module,
                     module_options=None if module != "unique" else dict(_UNIQUE_OPTIONS))


g2p_apic = make_g2p()
# CPU: the g2p of step n and the p2g of step n+1 in one pass (plan_cpu.py, fused CPU steps)
g2p_p2g_cpu = make_g2p(module="unique", scatter_next=True)


@wp.kernel
def reset_scene_stats(
    bmin: wp.array(dtype=wp.vec3),
    bmax: wp.array(dtype=wp.vec3),
    speed_max: wp.array(dtype=float),
    kinetic: wp.array(dtype=float),
):
    """Reset the per-scene reductions before ``reduce_scene_stats``."""
    s = wp.tid()
    bmin[s] = wp.vec3(BIG, BIG, BIG)
    bmax[s] = wp.vec3(-BIG, -BIG, -BIG)
    speed_max[s] = 0.0
    kinetic[s] = 0.0


@wp.kernel
def reduce_scene_stats(
    x: wp.array(dtype=wp.vec3),
    v: wp.array(dtype=wp.vec3),
    particle_mass: wp.array(dtype=float),
    chunk_scene: wp.array(dtype=wp.int32),
    chunk_begin: wp.array(dtype=wp.int32),
    chunk_end: wp.array(dtype=wp.int32),
    domain_lo: wp.array(dtype=wp.vec3),
    domain_hi: wp.array(dtype=wp.vec3),
    bmin: wp.array(dtype=wp.vec3),
    bmax: wp.array(dtype=wp.vec3),
    speed_max: wp.array(dtype=float),
    kinetic: wp.array(dtype=float),
):
    """Per scene: bounds [m] of the finite in-domain particles, max speed [m/s], kinetic energy [J] (chunked)."""
    c = wp.tid()
    s = chunk_scene[c]
    lo = wp.vec3(BIG, BIG, BIG)
    hi = wp.vec3(-BIG, -BIG, -BIG)
    vm = float(0.0)
    ke = float(0.0)
    dlo = domain_lo[s]
    dhi = domain_hi[s]
    for p in range(chunk_begin[c], chunk_end[c]):
        xp = x[p]
        vp = v[p]
        v2 = wp.dot(vp, vp)
        if is_finite((xp[0] + xp[1]) + (xp[2] + v2)):
            ke += 0.5 * particle_mass[p] * v2
            vm = wp.max(vm, v2)
            inside = xp[0] >= dlo[0] and xp[1] >= dlo[1] and xp[2] >= dlo[2]
            inside = inside and xp[0] <= dhi[0] and xp[1] <= dhi[1] and xp[2] <= dhi[2]
            if inside:
                lo = wp.min(lo, xp)
                hi = wp.max(hi, xp)
        else:
            ke += BIG
    wp.atomic_min(bmin, s, lo)
    wp.atomic_max(bmax, s, hi)
    wp.atomic_max(speed_max, s, wp.sqrt(vm))
    wp.atomic_add(kinetic, s, ke)


@wp.kernel
def fit_grid(
    bmin: wp.array(dtype=wp.vec3),
    bmax: wp.array(dtype=wp.vec3),
    nx: int,
    ny: int,
    nz: int,
    dx: float,
    guard_cells: int,
    grid_slide: wp.array(dtype=wp.float64),
    clock_time: wp.array(dtype=wp.float64),
    grid_origin: wp.array(dtype=wp.vec3),
    grid_overflow: wp.array(dtype=wp.int32),
):
    """Centre each scene's grid window on its particles' bounds; flag a scene whose bounds no longer fit."""
    s = wp.tid()
    fit_window(s, bmin[s], bmax[s], nx, ny, nz, dx, guard_cells, lattice_shift(s, grid_slide, clock_time), grid_origin,
               grid_overflow)
