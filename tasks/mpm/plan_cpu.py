"""The CPU launch plan: the plain kernels of ``kernels.py``, a block of items per thread, optionally the particles
split over threads (``cpu_threads.py``). With one item per thread it is also the CUDA reference path
(``KernelOptions.cuda_fast=False``).

* Particle kernels over ``SimConfig.cpu_threads`` chunks: each chunk scatters into its own grid buffer, impulse
  accumulators and failure tables, folded in afterwards in chunk order (results depend on the chunk count only).
* ``KernelOptions.cpu_fuse``: inside ``Solver.advance_steps``, the g2p of a step also does the next step's p2g
  (``kernels.g2p_p2g_cpu``) where no re-fit comes between them: same results bit for bit, one pass fewer per step.
* ``KernelOptions.cpu_merge``: with chunks, the grid update adds the chunk grids itself
  (``kernels.grid_update_merge_cpu``) instead of a merge pass before it: same results bit for bit.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import warp as wp

from contracts.sim import KernelOptions
from tasks.mpm import kernels as K
from tasks.mpm.control import Control
from tasks.mpm.cpu_threads import CpuChunks, ParallelLaunch, chunk_bounds
from tasks.mpm.plan_common import LaunchPlan, whole
from tasks.mpm.state import State

if TYPE_CHECKING:
    from tasks.mpm.solver import Solver

# CPU: one thread loops over a block of items (amortises Warp's per-thread argument copy)
CPU_ITEMS_PER_THREAD = 2048


class CpuLaunchPlan(LaunchPlan):
    """Launches of the plain kernels; on the CPU in chunks of threads, fused steps and the merge fold as configured."""

    def __init__(self, solver: Solver, options: KernelOptions) -> None:
        super().__init__(solver)
        m = self.model
        is_cpu = self.device == "cpu"
        self.per_thread = CPU_ITEMS_PER_THREAD if is_cpu else 1
        threads = int(m.config.cpu_threads)  # 1 on CUDA (SimConfig)
        bounds = chunk_bounds(m.n_particles, threads) if threads > 1 else []
        self.chunks = (CpuChunks(bounds, m.scene_start_np, m.n_scenes, max(1, m.n_colliders),
                                 m.n_scenes * K.N_FLAGS, self.device) if len(bounds) > 1 else None)
        self.fuse = is_cpu and options.cpu_fuse
        self.merge_fold = self.chunks is not None and options.cpu_merge

    def alloc_scatter(self, nodes: int) -> wp.array:
        """The scatter buffer; with chunks the head of one array with the chunks' (read by the merge fold)."""
        if self.chunks is not None:
            return self.chunks.alloc_grid(nodes)
        return super().alloc_scatter(nodes)

    def threads(self, n: int) -> int:
        """Launch dimension covering n items at per_thread items per thread."""
        return (n + self.per_thread - 1) // self.per_thread

    def record_refit(self, state: State) -> list:
        s, m, d = self.solver, self.model, self.device
        nx, ny, nz = s.grid_dims
        return [
            wp.launch(K.reset_scene_stats, dim=m.n_scenes, inputs=[s.bmin, s.bmax, s.speed_max, s.kinetic], device=d,
                      record_cmd=True),
            wp.launch(K.reduce_scene_stats, dim=m.n_chunks,
                      inputs=[state.x, state.v, m.particle_mass, m.chunk_scene, m.chunk_begin, m.chunk_end,
                              m.domain_lo, m.domain_hi, s.bmin, s.bmax, s.speed_max, s.kinetic],
                      device=d, record_cmd=True),
            wp.launch(K.fit_grid, dim=m.n_scenes,
                      inputs=[s.bmin, s.bmax, nx, ny, nz, m.dx, m.guard_cells, s.slide, s.clock_time, s.grid_origin,
                              s.grid_overflow],
                      device=d, record_cmd=True),
        ]

    def record_step(self, state_in: State, state_out: State, control: Control, refit: bool, skip_p2g: bool = False,
                    fuse_next: bool = False) -> list:
        s, m = self.solver, self.model
        if skip_p2g or fuse_next:
            assert self.device == "cpu" and state_in is state_out and not (refit and skip_p2g)
        cmds = self.record_refit(state_in) if refit else []
        if m.n_colliders:
            cmds.append(self.collider_poses_cmd(control))
        if skip_p2g:  # done by the previous step's g2p, into the chunk grids (added by the grid update, or here)
            if self.chunks is not None and not self.merge_fold:
                cmds.append(self.chunks.merge_grid_cmd(s.grid_mvm, self.per_thread))
        else:
            cmds += self._p2g(state_in)
        gu_kernel, scatter = K.grid_update, s.grid_mvm
        if self.merge_fold and self.chunks is not None and self.chunks.grid_stacked is not None:
            gu_kernel, scatter = K.grid_update_merge_cpu, self.chunks.grid_stacked  # reads and clears the chunks' too
        cmds.append(wp.launch(gu_kernel, dim=self.threads(s.grid_nodes),
                              inputs=self.grid_update_inputs(control, scatter, self.per_thread), device=self.device,
                              record_cmd=True, block_dim=None))
        g2p_kernel = K.g2p_p2g_cpu if fuse_next else K.g2p_apic  # fused: this g2p and the next step's p2g
        if self.chunks is not None:
            return cmds + self._g2p_chunks(g2p_kernel, state_in, state_out, control)
        cmds.append(wp.launch(g2p_kernel, dim=self.threads(m.n_particles),
                              inputs=self._g2p_inputs(state_in, state_out, control, 0), device=self.device,
                              record_cmd=True, block_dim=None))
        return cmds

    # -- the particle kernels: all particles, or one launch per chunk in threads --------------------------------------
    def _view(self, k: int) -> tuple[int, Any, wp.array | None, dict[str, wp.array] | None]:
        """(count, slice of a per-particle array, scene_start, own buffers or None) of chunk k; without chunks,
        chunk 0 is every particle with the solver's own buffers."""
        if self.chunks is None:
            return self.model.n_particles, whole, None, None
        a, b = self.chunks.bounds[k]
        return b - a, (lambda arr: arr[a:b]), self.chunks.scene_start[k], self.chunks.part(k) if k else None

    def _g2p_inputs(self, state_in: State, state_out: State, control: Control, k: int) -> list:
        n, sl, scene_start, own = self._view(k)
        return [*self.g2p_head_inputs(state_in, control, sl, scene_start, own),
                *self.g2p_tail_inputs(state_out, sl, own), self.per_thread, n]

    def _p2g(self, state: State) -> list:
        """p2g: one launch, or one per chunk in threads and then the chunk grids added in order."""
        ch = self.chunks
        launches = []
        for k in range(len(ch.bounds) if ch else 1):
            n, sl, scene_start, own = self._view(k)
            launches.append(wp.launch(K.p2g_apic_neohookean, dim=self.threads(n),
                                      inputs=self.p2g_inputs(state, self.per_thread, n, sl, scene_start, own),
                                      device=self.device, record_cmd=True))
        if ch is None:
            return launches
        merge = [] if self.merge_fold else [ch.merge_grid_cmd(self.solver.grid_mvm, self.per_thread)]
        return [ParallelLaunch(launches), *merge]

    def _g2p_chunks(self, kernel: wp.Kernel, state_in: State, state_out: State, control: Control) -> list:
        """g2p, one launch per chunk in threads, then the chunks' impulses and failures folded in."""
        ch, s = self.chunks, self.solver
        assert ch is not None
        launches = [wp.launch(kernel, dim=self.threads(self._view(k)[0]),
                              inputs=self._g2p_inputs(state_in, state_out, control, k), device=self.device,
                              record_cmd=True)
                    for k in range(len(ch.bounds))]
        return [ParallelLaunch(launches),
                ch.merge_tables_cmd(s.ground_impulse, s.collider_impulse, s.fail_step, s.fail_particle)]
