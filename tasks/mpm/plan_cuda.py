"""The CUDA launch plan (``KernelOptions.cuda_fast``): the block-level kernels of ``kernels_cuda.py`` and the CUDA
variants of ``kernels.py``, block sizes fitted to the problem size, the re-fit as one block-reduction launch.

Variants (``KernelOptions``; figures in benchmarks/engine/BENCHMARKS.md):

* specialize: no kinematic colliders in the model -> g2p / grid update without the collider contact code;
* agg: a warp's ground impulses summed by shuffles, one atomic per warp (same-address atomics serialise);
* coop_g2p / coop_p2g: a warp's 32 particle records (x, v, F, C) moved as contiguous 16-byte accesses through shared
  memory instead of a scalar access per float of a 36-byte record. H200, standard cube, with vs without: a gain at
  64k (37.8 -> 27.9 us/step) and 16 x 8k (54.9 -> 47.8), a loss at 8k (+1 us: one latency-bound wave of small
  blocks) and 1M (250.7 -> 260.9), so by default only for coop_min_particles <= particles <= coop_max_particles;
  coop_p2g: no gain measured (off by default);
* fuse: inside multi-step graphs, the g2p of a step and the p2g of the next (no re-fit between them) run as one
  kernel (``kernels_cuda.make_g2p2g``): the scatter works on the new state in registers (no reload of the particle
  records, one launch fewer per step), for fuse_min_particles <= particles; fuse_max_registers caps its registers
  per thread (with the cooperative records and the row scan it takes 147, i.e. 3 blocks of 128 per SM; capped at
  128 it spills 4 bytes and runs 4: H200, 16 x 8k 43.5 -> 41.3 us per step); fuse_keep_c: the fused kernel loads
  and stores C like the plain g2p (off: C stays in registers between the fused g2p and scatter);
* scatter, one particle per thread (the fused kernel; p2g when it runs one thread per particle): scan =
  ``kernels_cuda.scatter_stencil_scan`` (a warp's particles merged along stencil rows: ~7 instead of 13.5 atomics
  per particle in lattice order), warp = ``scatter_stencil_warp`` (per-node shuffles, same-base lanes);
* grid_lazy: the grid update writes nothing for a node without mass (its velocity is read only with a zero weight,
  and its scatter buffer is already clear): fewer stores over the window's empty nodes (H100, 16 x 8k: grid update
  11.4 -> 6.0 us per launch, bench 43.7-44.6 -> 40.4-42.4 us per step; 1M: 196.3 -> 174.0 us per step);
* p2g_parts: threads per particle in p2g: with the per-node warp scatter, small sizes are latency bound and split
  each particle's 27-node stencil over 3 threads (one slab each) to put more threads on the SMs (H200: 8k particles
  27.0 / 24.6 / 25.6 us per step for 1 / 3 / 9; 16 x 8k 69.5 / 76.2 / 95.8 us); the row-scan scatter (default)
  runs one thread per particle at every size (H200, 8k: 15.1 vs 15.5-15.7 us with 3).

The plan also runs on the CPU (tests: the kernels' CPU branches, one particle per thread), never in production.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import warp as wp

from contracts.sim import KernelOptions
from tasks.mpm import kernels_cuda as KC
from tasks.mpm.control import Control
from tasks.mpm.plan_common import LaunchPlan
from tasks.mpm.state import State

if TYPE_CHECKING:
    from tasks.mpm.solver import Solver

SCATTERS = {"warp": KC.SCATTER_WARP, "scan": KC.SCATTER_SCAN}


def cuda_block_dim(n_threads: int, forced: int = 0) -> int:
    """Threads per CUDA block for a launch of n_threads: `forced` if set (KernelOptions.cuda_block_threads), else
    small blocks at small sizes spread the work over the SMs (an H100/H200 has 132), 256 once there are enough
    blocks to fill them."""
    if forced:
        return int(forced)
    if n_threads >= 256 * 132 * 4:
        return 256
    if n_threads >= 128 * 132 * 2:
        return 128
    return 64


def coop_ok(state: State) -> bool:
    """Whether a state's arrays suit the warp-cooperative accesses (contiguous, 16-byte aligned)."""
    return all(a.is_contiguous and a.ptr is not None and a.ptr % 16 == 0 for a in (state.x, state.v, state.F, state.C))


def whole_blocks(n: int, block: int) -> int:
    """n rounded up to whole blocks (every lane reaches the warp collectives)."""
    return -(-n // block) * block


class CudaLaunchPlan(LaunchPlan):
    """Launches of the fast CUDA path, one item per thread; the kernel variants chosen once from the options."""

    def __init__(self, solver: Solver, options: KernelOptions) -> None:
        super().__init__(solver)
        m = self.model
        o = options
        self.block_threads = int(o.cuda_block_threads)
        n = m.n_particles
        self.with_colliders = m.n_colliders > 0 or not o.specialize
        self.agg = bool(o.agg)
        sized = o.coop_min_particles <= n <= (o.coop_max_particles or 2**31)
        self.coop_g2p = o.coop and o.coop_g2p and sized
        self.coop_p2g = o.coop and o.coop_p2g and sized
        self.fuse = o.fuse and n >= o.fuse_min_particles
        self.fuse_regs = int(o.fuse_max_registers)
        self.fuse_keep_c = bool(o.fuse_keep_c)
        self.grid_lazy = bool(o.grid_lazy)
        self.scatter = SCATTERS[o.scatter]
        self.p2g_parts = int(o.p2g_parts) or (3 if n < 24_000 and o.scatter == "warp" else 1)
        self.p2g_block = cuda_block_dim(n * self.p2g_parts, self.block_threads)
        self._init_refit_chunks()

    def _init_refit_chunks(self) -> None:
        """Chunks of the re-fit (one scene each, one thread block each) and their partials."""
        m, d = self.model, self.device
        self.red_block = 128 if m.n_particles < 256 * 132 * 4 else 256
        cs, cb, ce = [], [], []
        for s in range(m.n_scenes):
            b0 = int(m.scene_start_np[s])
            b1 = b0 + int(m.scene_counts[s])
            # ~1024 blocks over the whole batch (~8 per SM); each thread strides over chunk / red_block particles
            per = max(1, -(-m.n_particles // (1024 * self.red_block)))
            chunk = self.red_block * per
            for b in range(b0, b1, chunk):
                cs.append(s)
                cb.append(b)
                ce.append(min(b + chunk, b1))
        self.chunk_scene: wp.array = wp.array(np.asarray(cs, np.int32), dtype=wp.int32, device=d)
        self.chunk_begin: wp.array = wp.array(np.asarray(cb, np.int32), dtype=wp.int32, device=d)
        self.chunk_end: wp.array = wp.array(np.asarray(ce, np.int32), dtype=wp.int32, device=d)
        self.n_chunks = len(cs)
        first = np.searchsorted(np.asarray(cs, np.int64), np.arange(m.n_scenes + 1)).astype(np.int32)
        # scene s: chunks [first[s], first[s+1])
        self.scene_chunk_begin: wp.array = wp.array(first, dtype=wp.int32, device=d)
        nc = self.n_chunks
        self.part_lo = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.part_hi = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.part_v2 = wp.zeros(nc, dtype=float, device=d)
        self.part_ke = wp.zeros(nc, dtype=float, device=d)
        self.refit_counter = wp.zeros(m.n_scenes, dtype=wp.int32, device=d)  # blocks done per scene

    def record_refit(self, state: State) -> list:
        """One launch: chunk partials (one block each); the last block of each scene combines them (no reset, no
        same-address atomics) and fits the scene's window."""
        s, m = self.solver, self.model
        nx, ny, nz = s.grid_dims
        return [wp.launch(
            KC.refit_fused,
            dim=self.n_chunks * self.red_block,
            inputs=[state.x, state.v, m.particle_mass, self.chunk_scene, self.chunk_begin, self.chunk_end,
                    self.scene_chunk_begin, m.domain_lo, m.domain_hi, self.part_lo, self.part_hi, self.part_v2,
                    self.part_ke, self.refit_counter, s.bmin, s.bmax, s.speed_max, s.kinetic, nx, ny, nz, m.dx,
                    m.guard_cells, s.slide, s.clock_time, s.grid_origin, s.grid_overflow, self.red_block],
            device=self.device,
            record_cmd=True,
            block_dim=self.red_block,
        )]

    def record_step(self, state_in: State, state_out: State, control: Control, refit: bool, skip_p2g: bool = False,
                    fuse_next: bool = False) -> list:
        s, m, d = self.solver, self.model, self.device
        if skip_p2g or fuse_next:
            assert state_in is state_out and not (refit and skip_p2g)
        cmds = self.record_refit(state_in) if refit else []
        if m.n_colliders:
            cmds.append(self.collider_poses_cmd(control))
        if not skip_p2g:  # (skipped: done by the previous step's fused kernel)
            bd = self.p2g_block
            nt = m.n_particles * self.p2g_parts
            coop = self.coop_p2g and self.p2g_parts == 1 and coop_ok(state_in)
            cmds.append(wp.launch(
                KC.p2g_kernel(coop, self.scatter if self.p2g_parts == 1 else KC.SCATTER_WARP),
                dim=whole_blocks(nt, bd),
                inputs=self.p2g_inputs(state_in, self.p2g_parts, m.n_particles),
                device=d,
                record_cmd=True,
                block_dim=bd,
            ))
        gu_block = cuda_block_dim(s.grid_nodes, self.block_threads)
        gu_dim = whole_blocks(s.grid_nodes, gu_block) if self.agg else s.grid_nodes  # agg: warp collectives
        cmds.append(wp.launch(
            KC.grid_update_kernel(self.with_colliders, self.agg, self.grid_lazy),
            dim=gu_dim,
            inputs=self.grid_update_inputs(control, s.grid_mvm, 1),
            device=d,
            record_cmd=True,
            block_dim=gu_block,
        ))
        head = self.g2p_head_inputs(state_in, control)
        bd = cuda_block_dim(m.n_particles, self.block_threads)
        if fuse_next:  # this step's g2p and the next step's p2g in one kernel
            coop = self.coop_g2p and coop_ok(state_in)
            cmds.append(wp.launch(
                KC.g2p2g_kernel(self.with_colliders, coop, self.agg, self.scatter, self.fuse_regs, self.fuse_keep_c),
                dim=whole_blocks(m.n_particles, bd),
                inputs=[*head, *self.g2p_tail_inputs(state_out), m.n_particles],
                device=d,
                record_cmd=True,
                block_dim=bd,
            ))
            return cmds
        coop = self.coop_g2p and coop_ok(state_in) and coop_ok(state_out)
        cmds.append(wp.launch(
            KC.g2p_kernel(self.with_colliders, coop, self.agg),
            dim=whole_blocks(m.n_particles, bd) if self.agg or coop else m.n_particles,
            inputs=[*head, *self.g2p_tail_inputs(state_out), 1, m.n_particles],
            device=d,
            record_cmd=True,
            block_dim=bd,
        ))
        return cmds
