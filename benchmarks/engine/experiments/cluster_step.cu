// Feasibility prototype (issue 3, the 16 x 8k batch ratio), not part of the engine: one MLS-MPM step loop of the
// bench cube (neo-Hookean Kirchhoff stress, quadratic B-splines, gravity, ground), each scene on one thread-block
// cluster whose blocks hold the scene's grid window in distributed shared memory, many steps per launch.
// Build on the GPU machine: nvcc -O3 -arch=sm_90 -o cluster_step cluster_step.cu
// Run: ./cluster_step SCENES CLUSTER THREADS STEPS [MODE] -> one JSON line (us per step, checks). MODE 0: lattice
// order; 1: particles shuffled within each scene. Figures and conclusions: tasks/mpm/BENCHMARKS.md, last section.
#include <cooperative_groups.h>
#include <cuda_runtime.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>
namespace cg = cooperative_groups;

#define CK(x) do { cudaError_t e_ = (x); if (e_ != cudaSuccess) { \
  fprintf(stderr, "%s:%d %s: %s\n", __FILE__, __LINE__, #x, cudaGetErrorString(e_)); exit(2); } } while (0)

constexpr int NG = 22;                 // grid window nodes per axis (10-cell cube + 6 cells each side, as the engine)
constexpr int NN = NG * NG * NG;       // 10,648 nodes per scene
constexpr int NP1 = 20;                // particles per axis (8,000 per scene)

struct Params {
  int n_per_scene, steps, nodes_per_block;
  float dt, dx, inv_dx, mass, vol, mu, lam, ground_z, gz;
  float ox, oy, oz;                    // window origin [m] (same for every scene: same cube)
};

__device__ __forceinline__ void weights(float fx, float w[3]) {
  w[0] = 0.5f * (1.5f - fx) * (1.5f - fx);
  w[1] = 0.75f - (fx - 1.0f) * (fx - 1.0f);
  w[2] = 0.5f * (fx - 0.5f) * (fx - 0.5f);
}

struct Stencil {  // a particle's quadratic B-spline stencil: base node, fractional offsets, per-axis weights
  int b[3];
  float f[3], w[3][3];
};

__device__ __forceinline__ Stencil stencil(const float x[3], const Params& p) {
  Stencil s;
  const float o[3] = {p.ox, p.oy, p.oz};
#pragma unroll
  for (int a = 0; a < 3; ++a) {
    float g = (x[a] - o[a]) * p.inv_dx;
    s.b[a] = (int)floorf(g - 0.5f);
    s.f[a] = g - s.b[a];
    weights(s.f[a], s.w[a]);
  }
  return s;
}

__global__ void step_loop(float* __restrict__ X, float* __restrict__ V, float* __restrict__ Fm,
                          float* __restrict__ Cm, Params p) {
  extern __shared__ float4 grid[];
  cg::cluster_group cluster = cg::this_cluster();
  const int C = cluster.num_blocks();
  const int rank = cluster.block_rank();
  const int scene = blockIdx.x / C;
  const int per_block = (p.n_per_scene + C - 1) / C;
  const int p0 = scene * p.n_per_scene + rank * per_block;
  const int p1 = min(p0 + per_block, (scene + 1) * p.n_per_scene);
  const int npb = p.nodes_per_block;
  const float s4 = 4.0f * p.inv_dx * p.inv_dx;
  for (int step = 0; step < p.steps; ++step) {
    for (int i = threadIdx.x; i < npb; i += blockDim.x) grid[i] = make_float4(0.f, 0.f, 0.f, 0.f);
    cluster.sync();
    // p2g
    for (int q = p0 + threadIdx.x; q < p1; q += blockDim.x) {
      float x[3] = {X[3 * q], X[3 * q + 1], X[3 * q + 2]};
      float v[3] = {V[3 * q], V[3 * q + 1], V[3 * q + 2]};
      float F[9], Cq[9];
#pragma unroll
      for (int k = 0; k < 9; ++k) { F[k] = Fm[9 * q + k]; Cq[k] = Cm[9 * q + k]; }
      float J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) + F[2] * (F[3] * F[7] - F[4] * F[6]);
      float lnJ = logf(fmaxf(J, 1e-6f));
      float tau[9];  // mu (F F^T - I) + lam ln J I
#pragma unroll
      for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
          float s = F[3 * a] * F[3 * b] + F[3 * a + 1] * F[3 * b + 1] + F[3 * a + 2] * F[3 * b + 2];
          tau[3 * a + b] = p.mu * (s - (a == b)) + (a == b ? p.lam * lnJ : 0.f);
        }
      float A[9];
#pragma unroll
      for (int k = 0; k < 9; ++k) A[k] = -p.dt * p.vol * s4 * tau[k] + p.mass * Cq[k];
      const Stencil st = stencil(x, p);
      const int bx = st.b[0], by = st.b[1], bz = st.b[2];
      const float fx = st.f[0], fy = st.f[1], fz = st.f[2];
      const float *wx = st.w[0], *wy = st.w[1], *wz = st.w[2];
      float mv[3] = {p.mass * v[0], p.mass * v[1], p.mass * v[2]};
#pragma unroll
      for (int i = 0; i < 3; ++i)
#pragma unroll
        for (int j = 0; j < 3; ++j)
#pragma unroll
          for (int k = 0; k < 3; ++k) {
            float w = wx[i] * wy[j] * wz[k];
            float d0 = (i - fx) * p.dx, d1 = (j - fy) * p.dx, d2 = (k - fz) * p.dx;
            int n = ((bx + i) * NG + by + j) * NG + bz + k;
            int r = n / npb, li = n - r * npb;
            float4* g = cluster.map_shared_rank(grid, r);
            atomicAdd(&g[li].x, w * (mv[0] + A[0] * d0 + A[1] * d1 + A[2] * d2));
            atomicAdd(&g[li].y, w * (mv[1] + A[3] * d0 + A[4] * d1 + A[5] * d2));
            atomicAdd(&g[li].z, w * (mv[2] + A[6] * d0 + A[7] * d1 + A[8] * d2));
            atomicAdd(&g[li].w, w * p.mass);
          }
    }
    cluster.sync();
    // grid update (own nodes): momentum -> velocity, gravity, ground (no penetration, free slip)
    for (int i = threadIdx.x; i < npb; i += blockDim.x) {
      int n = rank * npb + i;
      if (n >= NN) break;
      float4 g = grid[i];
      if (g.w > 0.f) {
        float inv = 1.0f / g.w;
        float vx = g.x * inv, vy = g.y * inv, vz = g.z * inv + p.dt * p.gz;
        int kz = n % NG;
        if (p.oz + kz * p.dx <= p.ground_z && vz < 0.f) vz = 0.f;
        grid[i] = make_float4(vx, vy, vz, g.w);
      }
    }
    cluster.sync();
    // g2p
    for (int q = p0 + threadIdx.x; q < p1; q += blockDim.x) {
      float x[3] = {X[3 * q], X[3 * q + 1], X[3 * q + 2]};
      const Stencil st = stencil(x, p);
      const int bx = st.b[0], by = st.b[1], bz = st.b[2];
      const float fx = st.f[0], fy = st.f[1], fz = st.f[2];
      const float *wx = st.w[0], *wy = st.w[1], *wz = st.w[2];
      float nv[3] = {0.f, 0.f, 0.f}, B[9] = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
#pragma unroll
      for (int i = 0; i < 3; ++i)
#pragma unroll
        for (int j = 0; j < 3; ++j)
#pragma unroll
          for (int k = 0; k < 3; ++k) {
            float w = wx[i] * wy[j] * wz[k];
            float d[3] = {(i - fx) * p.dx, (j - fy) * p.dx, (k - fz) * p.dx};
            int n = ((bx + i) * NG + by + j) * NG + bz + k;
            int r = n / npb, li = n - r * npb;
            float4 g = cluster.map_shared_rank(grid, r)[li];
            float gv[3] = {g.x, g.y, g.z};
#pragma unroll
            for (int a = 0; a < 3; ++a) {
              nv[a] += w * gv[a];
#pragma unroll
              for (int b = 0; b < 3; ++b) B[3 * a + b] += w * gv[a] * d[b];
            }
          }
      float F[9], Fn[9];
#pragma unroll
      for (int k = 0; k < 9; ++k) F[k] = Fm[9 * q + k];
#pragma unroll
      for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b) {
          float s = F[3 * a + b];
#pragma unroll
          for (int c = 0; c < 3; ++c) s += p.dt * s4 * B[3 * a + c] * F[3 * c + b];
          Fn[3 * a + b] = s;
        }
#pragma unroll
      for (int k = 0; k < 9; ++k) { Fm[9 * q + k] = Fn[k]; Cm[9 * q + k] = s4 * B[k]; }
#pragma unroll
      for (int a = 0; a < 3; ++a) { V[3 * q + a] = nv[a]; X[3 * q + a] = x[a] + p.dt * nv[a]; }
    }
    cluster.sync();
  }
}

int main(int argc, char** argv) {
  int scenes = argc > 1 ? atoi(argv[1]) : 16, C = argc > 2 ? atoi(argv[2]) : 8;
  int tpb = argc > 3 ? atoi(argv[3]) : 256, steps = argc > 4 ? atoi(argv[4]) : 2000;
  int mode = argc > 5 ? atoi(argv[5]) : 0;
  Params p{};
  p.n_per_scene = NP1 * NP1 * NP1; p.steps = steps; p.nodes_per_block = (NN + C - 1) / C;
  p.dx = 0.4f / NP1; p.inv_dx = 1.0f / p.dx; p.dt = 1e-4f;
  float rho = 200.f, E = 1e5f, nu = 0.3f, spacing = 0.2f / NP1;
  p.vol = spacing * spacing * spacing; p.mass = rho * p.vol;
  p.mu = E / (2 * (1 + nu)); p.lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  p.ground_z = 0.f; p.gz = -9.81f;
  float lo[3] = {-0.1f, -0.1f, 0.05f};                 // cube [-0.1, 0.1]^2 x [0.05, 0.25]
  p.ox = lo[0] - 6 * p.dx; p.oy = lo[1] - 6 * p.dx; p.oz = lo[2] - 6 * p.dx;
  size_t N = (size_t)scenes * p.n_per_scene;
  std::vector<float> hx(3 * N), hv(3 * N, 0.f), hF(9 * N, 0.f), hC(9 * N, 0.f);
  for (size_t q = 0; q < N; ++q) {
    int l = q % p.n_per_scene, i = l / (NP1 * NP1), j = (l / NP1) % NP1, k = l % NP1;
    hx[3 * q] = lo[0] + (i + 0.5f) * spacing; hx[3 * q + 1] = lo[1] + (j + 0.5f) * spacing;
    hx[3 * q + 2] = lo[2] + (k + 0.5f) * spacing;
    hF[9 * q] = hF[9 * q + 4] = hF[9 * q + 8] = 1.f;
  }
  if (mode == 1) {  // shuffle each scene's particles (fixed seed)
    srand(7);
    for (size_t s0 = 0; s0 < N; s0 += p.n_per_scene)
      for (int i = p.n_per_scene - 1; i > 0; --i) {
        int j = rand() % (i + 1);
        for (int a = 0; a < 3; ++a) std::swap(hx[3 * (s0 + i) + a], hx[3 * (s0 + j) + a]);
      }
  }
  float *X, *V, *F, *Cm;
  CK(cudaMalloc(&X, 12 * N)); CK(cudaMalloc(&V, 12 * N)); CK(cudaMalloc(&F, 36 * N)); CK(cudaMalloc(&Cm, 36 * N));
  auto upload = [&]() {
    CK(cudaMemcpy(X, hx.data(), 12 * N, cudaMemcpyHostToDevice)); CK(cudaMemcpy(V, hv.data(), 12 * N, cudaMemcpyHostToDevice));
    CK(cudaMemcpy(F, hF.data(), 36 * N, cudaMemcpyHostToDevice)); CK(cudaMemcpy(Cm, hC.data(), 36 * N, cudaMemcpyHostToDevice));
  };
  size_t smem = (size_t)p.nodes_per_block * sizeof(float4);
  CK(cudaFuncSetAttribute(step_loop, cudaFuncAttributeMaxDynamicSharedMemorySize, (int)smem));
  if (C > 8) CK(cudaFuncSetAttribute(step_loop, cudaFuncAttributeNonPortableClusterSizeAllowed, 1));
  cudaLaunchConfig_t cfg = {};
  cfg.gridDim = dim3(scenes * C); cfg.blockDim = dim3(tpb); cfg.dynamicSmemBytes = smem;
  cudaLaunchAttribute attr[1];
  attr[0].id = cudaLaunchAttributeClusterDimension; attr[0].val.clusterDim.x = C;
  attr[0].val.clusterDim.y = 1; attr[0].val.clusterDim.z = 1;
  cfg.attrs = attr; cfg.numAttrs = 1;
  int active = -1;
  CK(cudaOccupancyMaxActiveClusters(&active, step_loop, &cfg));
  cudaFuncAttributes fa; CK(cudaFuncGetAttributes(&fa, step_loop));
  // warm-up, then the timed run from the initial state
  upload();
  Params pw = p; pw.steps = 10;
  CK(cudaLaunchKernelEx(&cfg, step_loop, X, V, F, Cm, pw)); CK(cudaDeviceSynchronize());
  upload();
  cudaEvent_t e0, e1; CK(cudaEventCreate(&e0)); CK(cudaEventCreate(&e1));
  CK(cudaEventRecord(e0));
  CK(cudaLaunchKernelEx(&cfg, step_loop, X, V, F, Cm, p));
  CK(cudaEventRecord(e1)); CK(cudaEventSynchronize(e1)); CK(cudaGetLastError());
  float ms; CK(cudaEventElapsedTime(&ms, e0, e1));
  // checks: centroid fall against free fall (airborne for these steps), J range, finiteness
  CK(cudaMemcpy(hx.data(), X, 12 * N, cudaMemcpyDeviceToHost)); CK(cudaMemcpy(hF.data(), F, 36 * N, cudaMemcpyDeviceToHost));
  double z0 = lo[2] + 0.1, zc = 0; double jmin = 1e9, jmax = -1e9; bool finite = true;
  for (size_t q = 0; q < N; ++q) {
    zc += hx[3 * q + 2];
    const float* f = &hF[9 * q];
    double J = f[0] * (f[4] * f[8] - f[5] * f[7]) - f[1] * (f[3] * f[8] - f[5] * f[6]) + f[2] * (f[3] * f[7] - f[4] * f[6]);
    jmin = fmin(jmin, J); jmax = fmax(jmax, J); finite = finite && std::isfinite(J) && std::isfinite(hx[3 * q + 2]);
  }
  zc /= N;
  double t = steps * (double)p.dt, drop = z0 - zc, expect = 0.5 * 9.81 * t * t;
  printf("{\"mode\": %d, \"scenes\": %d, \"cluster\": %d, \"threads\": %d, \"steps\": %d, \"particles\": %zu, \"us_per_step\": %.3f, "
         "\"particle_steps_per_s\": %.4g, \"max_active_clusters\": %d, \"regs\": %d, \"smem_per_block\": %zu, "
         "\"centroid_drop_m\": %.6g, \"free_fall_m\": %.6g, \"J_min\": %.6f, \"J_max\": %.6f, \"finite\": %s}\n",
         mode, scenes, C, tpb, steps, N, 1000.0 * ms / steps, N * (double)steps / (ms * 1e-3), active, fa.numRegs, smem,
         drop, expect, jmin, jmax, finite ? "true" : "false");
  return 0;
}
