"""Solver: the only thing that advances time — one MLS-MPM step per call, on the model's device."""

from __future__ import annotations

import os
from collections import OrderedDict

import numpy as np
import warp as wp

from tasks.mpm import kernels as K
from tasks.mpm import kernels_cuda as KC
from tasks.mpm.control import Control
from tasks.mpm.cpu_launch import pack_cpu_launches
from tasks.mpm.cpu_threads import CpuChunks, ParallelLaunch, chunk_bounds
from tasks.mpm.model import Model
from tasks.mpm.state import State

INT_MAX = 2**31 - 1

# CUDA: kernels_cuda.py (warp-aggregated p2g, the re-fit as one block-reduction launch), block sizes fitted to the
# problem size, re-fit launches recorded once. DEFORMSMITH_MPM_CUDA_FAST=0 selects the plain
# one-thread-per-item kernels of kernels.py (the reference path, as before). The CPU path never changes.
CUDA_FAST = os.environ.get("DEFORMSMITH_MPM_CUDA_FAST", "1") != "0"


def _env_flag(name: str, default: bool = True) -> bool:
    """An on/off experiment switch of the fast CUDA path (read when a Solver is built)."""
    return os.environ.get(name, "1" if default else "0") != "0"


def cuda_block_dim(n_threads: int) -> int:
    """Threads per CUDA block for a launch of n_threads: small blocks at small sizes spread the work over the SMs
    (an H100/H200 has 132), 256 once there are enough blocks to fill them."""
    forced = os.environ.get("DEFORMSMITH_MPM_CUDA_BLOCK")  # experiments: one block size for every launch
    if forced:
        return int(forced)
    if n_threads >= 256 * 132 * 4:
        return 256
    if n_threads >= 128 * 132 * 2:
        return 128
    return 64


def _coop_ok(state: State) -> bool:
    """Whether a state's arrays suit the warp-cooperative accesses (contiguous, 16-byte aligned)."""
    return all(a.is_contiguous and a.ptr is not None and a.ptr % 16 == 0 for a in (state.x, state.v, state.F, state.C))


class Solver:
    """MLS-MPM with neo-Hookean stress, grid Coulomb contact and device-side health flags.

    Owns the grid window (fitted to the particles and moved with them), the device clock (time [s], step count),
    the contact impulse accumulators and the failure tables. ``step`` issues only kernel launches (no host sync);
    on CUDA the launches of one step are captured once into a graph and replayed.
    """

    def __init__(self, model: Model, use_graph: bool | None = None) -> None:
        self.model = model
        d = model.device
        self.device = d
        self.device_is_cpu = d == "cpu"
        B = model.n_scenes
        nc = max(1, model.n_colliders)
        self.use_graph = (d == "cuda") if use_graph is None else (bool(use_graph) and d == "cuda")
        self._graphs: dict[tuple, object] = {}
        # multi-step graphs of advance_steps, least recently used first (bounded: each holds its launches)
        self._blocks: OrderedDict[tuple, tuple] = OrderedDict()
        self._host_bufs: dict[str, wp.array] = {}  # pinned host mirrors for one-sync readbacks (CUDA)
        self._refit_cmds: dict[tuple, tuple] = {}  # recorded re-fit launches per state
        # CPU: one "thread" loops over a block of items (amortises Warp's per-thread argument copy); GPU: one each
        self._per_thread = 1 if d == "cuda" else 2048
        self.dt_arr = wp.zeros(1, dtype=float, device=d)
        self._dt_host = -1.0
        self.clock_time = wp.zeros(1, dtype=wp.float64, device=d)
        self.clock_step = wp.zeros(1, dtype=wp.int32, device=d)
        self.time_s = 0.0  # host mirror of clock_time (same float32 dt summed in float64)
        self.steps = 0
        self._since_refit = 0
        self.ground_impulse = wp.zeros(B, dtype=wp.vec3, device=d)
        self.collider_impulse = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.fail_step = wp.full(B * K.N_FLAGS, INT_MAX, dtype=wp.int32, device=d)
        self.fail_particle = wp.full(B * K.N_FLAGS, INT_MAX, dtype=wp.int32, device=d)
        self.bmin = wp.zeros(B, dtype=wp.vec3, device=d)
        self.bmax = wp.zeros(B, dtype=wp.vec3, device=d)
        self.speed_max = wp.zeros(B, dtype=float, device=d)
        self.kinetic = wp.zeros(B, dtype=float, device=d)
        self.grid_overflow = wp.zeros(B, dtype=wp.int32, device=d)
        self.col_pos0 = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.col_rot0 = wp.zeros(nc, dtype=wp.quat, device=d)
        self.col_pos1 = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.col_rot1 = wp.zeros(nc, dtype=wp.quat, device=d)
        self.grid_origin = wp.zeros(B, dtype=wp.vec3, device=d)  # node (0, 0, 0) of each window [cells]
        self._no_slide = wp.zeros(8 * B, dtype=wp.float64, device=d)  # the fixed world lattice
        self._slide = self._no_slide  # the lattice motion of the last control stepped with
        self.fast_cuda = d == "cuda" and CUDA_FAST
        # CPU: the particle kernels of a step split over config.cpu_threads chunks run in threads (cpu_threads.py)
        self.cpu_threads = int(model.config.cpu_threads)  # 1 on CUDA (SimConfig)
        bounds = chunk_bounds(model.n_particles, self.cpu_threads) if self.cpu_threads > 1 else []
        self._chunks = CpuChunks(bounds, model.scene_start_np, B, nc, B * K.N_FLAGS, d) if len(bounds) > 1 else None
        # CPU_FUSE: inside advance_steps, the g2p of a step and the p2g of the next (no re-fit between them) run as one
        # pass over the particles (kernels.g2p_p2g_cpu): same results bit for bit, one thread hand-off fewer per step
        self.cpu_fuse = self.device_is_cpu and _env_flag("DEFORMSMITH_MPM_CPU_FUSE")
        # CPU_MERGE: with chunks, the grid update adds the chunk grids itself (kernels.grid_update_merge_cpu) instead
        # of a merge pass before it: one serial pass over the nodes fewer per step, same results bit for bit
        self.cpu_merge_fold = self._chunks is not None and _env_flag("DEFORMSMITH_MPM_CPU_MERGE")
        self.cuda_colliders, self.cuda_agg, self.cuda_coop_g2p, self.cuda_coop_p2g = True, False, False, False
        self.cuda_fuse, self.cuda_scatter, self.cuda_fuse_regs, self.cuda_fuse_keep_c = False, 0, 0, False
        self.cuda_grid_lazy = False
        if self.fast_cuda:
            self._init_cuda_blocks()
            # kernel variants of the fast path (switches DEFORMSMITH_MPM_<NAME>=0/1, for experiments and tests):
            # SPECIALIZE: no kinematic colliders in the model -> g2p / grid update without the collider contact code;
            # AGG: a warp's ground impulses summed by shuffles, one atomic per warp (same-address atomics serialise);
            # COOP_G2P: g2p moves a warp's 32 particle records (x, v, F, C) as contiguous 16-byte accesses through
            # shared memory instead of a scalar access per float of a 36-byte record. H200, standard cube, with vs
            # without: a gain at 64k (37.8 -> 27.9 us/step) and 16 x 8k (54.9 -> 47.8), a loss at 8k (+1 us: one
            # latency-bound wave of small blocks) and 1M (250.7 -> 260.9), so by default only for
            # COOP_MIN <= particles <= COOP_MAX (sizes in between not measured);
            # COOP_P2G: the same for p2g's loads (no gain measured: off by default)
            self.cuda_colliders = model.n_colliders > 0 or not _env_flag("DEFORMSMITH_MPM_SPECIALIZE")
            self.cuda_agg = _env_flag("DEFORMSMITH_MPM_AGG")
            coop = _env_flag("DEFORMSMITH_MPM_COOP")
            coop_min = int(os.environ.get("DEFORMSMITH_MPM_COOP_MIN", "24000"))
            coop_max = int(os.environ.get("DEFORMSMITH_MPM_COOP_MAX", "400000")) or 2**31
            sized = coop_min <= model.n_particles <= coop_max
            self.cuda_coop_g2p = coop and _env_flag("DEFORMSMITH_MPM_COOP_G2P") and sized
            self.cuda_coop_p2g = coop and _env_flag("DEFORMSMITH_MPM_COOP_P2G", False) and sized
            # FUSE: inside multi-step graphs, the g2p of a step and the p2g of the next (no re-fit between them) run
            # as one kernel (kernels_cuda.make_g2p2g): the scatter works on the new state in registers (no reload of
            # the particle records, one launch fewer per step), for FUSE_MIN <= particles; FUSE_REGS caps its
            # registers per thread (with the cooperative records and the row scan it takes 147, i.e. 3 blocks of 128
            # per SM; capped at 128 it spills 4 bytes and runs 4: H200, 16 x 8k 43.5 -> 41.3 us per step)
            fuse_min = int(os.environ.get("DEFORMSMITH_MPM_FUSE_MIN", "0"))
            self.cuda_fuse = _env_flag("DEFORMSMITH_MPM_FUSE") and model.n_particles >= fuse_min
            self.cuda_fuse_regs = int(os.environ.get("DEFORMSMITH_MPM_FUSE_REGS", "128"))
            # FUSE_C: the fused kernel loads and stores C like the plain g2p (off: C stays in registers between the
            # fused g2p and scatter, and memory gets it from the block's last plain g2p; kernels_cuda.make_g2p2g)
            self.cuda_fuse_keep_c = _env_flag("DEFORMSMITH_MPM_FUSE_C", False)
            # SCATTER, one particle per thread (the fused kernel; p2g when it runs one thread per particle): scan =
            # kernels_cuda.scatter_stencil_scan (a warp's particles merged along stencil rows: ~7 instead of 13.5
            # atomics per particle in lattice order), warp = scatter_stencil_warp (per-node shuffles, same-base lanes)
            # GRID_LAZY: the grid update writes nothing for a node without mass (its velocity is read only with a
            # zero weight, and its scatter buffer is already clear): fewer stores over the window's empty nodes
            # (H100, 16 x 8k: grid update 11.4 -> 6.0 us per launch, bench 43.7-44.6 -> 40.4-42.4 us per step;
            # 1M: 196.3 -> 174.0 us per step)
            self.cuda_grid_lazy = _env_flag("DEFORMSMITH_MPM_GRID_LAZY")
            scat = os.environ.get("DEFORMSMITH_MPM_SCATTER", "scan")
            self.cuda_scatter = {"warp": KC.SCATTER_WARP, "scan": KC.SCATTER_SCAN}[scat]
        self._alloc_grid(model.grid_dims)
        self._initial_fit = True

    def _init_cuda_blocks(self) -> None:
        """Block sizes of the CUDA kernels and the chunks (one scene each, one thread block each) of the re-fit."""
        m = self.model
        # threads per particle in p2g: with the per-node warp scatter, small sizes are latency bound and split each
        # particle's 27-node stencil over 3 threads (one slab each) to put more threads on the SMs (H200: 8k
        # particles 27.0 / 24.6 / 25.6 us per step for 1 / 3 / 9; 16 x 8k 69.5 / 76.2 / 95.8 us); the row-scan
        # scatter (default) runs one thread per particle at every size (H200, 8k: 15.1 vs 15.5-15.7 us with 3)
        parts = 3 if m.n_particles < 24_000 and os.environ.get("DEFORMSMITH_MPM_SCATTER", "scan") == "warp" else 1
        self.p2g_parts = int(os.environ.get("DEFORMSMITH_MPM_P2G_PARTS", parts))  # experiments: 1, 3 or 9
        if self.p2g_parts not in (1, 3, 9):
            raise ValueError("DEFORMSMITH_MPM_P2G_PARTS must be 1, 3 or 9")
        self.p2g_block = cuda_block_dim(m.n_particles * self.p2g_parts)
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
        d = self.device
        self.cuda_chunk_scene = wp.array(np.asarray(cs, np.int32), dtype=wp.int32, device=d)
        self.cuda_chunk_begin = wp.array(np.asarray(cb, np.int32), dtype=wp.int32, device=d)
        self.cuda_chunk_end = wp.array(np.asarray(ce, np.int32), dtype=wp.int32, device=d)
        self.cuda_n_chunks = len(cs)
        first = np.searchsorted(np.asarray(cs, np.int64), np.arange(m.n_scenes + 1)).astype(np.int32)
        self.cuda_scene_chunk_begin = wp.array(first, dtype=wp.int32, device=d)  # scene s: chunks [first[s], first[s+1])
        nc = self.cuda_n_chunks
        self.cuda_part_lo = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.cuda_part_hi = wp.zeros(nc, dtype=wp.vec3, device=d)
        self.cuda_part_v2 = wp.zeros(nc, dtype=float, device=d)
        self.cuda_part_ke = wp.zeros(nc, dtype=float, device=d)
        self.cuda_refit_counter = wp.zeros(m.n_scenes, dtype=wp.int32, device=d)  # blocks done per scene

    # -- grid ----------------------------------------------------------------------------------------------------
    def _alloc_grid(self, dims: tuple[int, int, int]) -> None:
        """Allocate (and zero) the scatter buffer and node velocities for B windows of dims nodes."""
        self.grid_dims = tuple(int(n) for n in dims)
        nodes = self.model.n_scenes * self.grid_dims[0] * self.grid_dims[1] * self.grid_dims[2]
        if self._chunks is not None:  # the main scatter buffer is the head of one array with the chunks'
            self.grid_mvm = self._chunks.alloc_grid(nodes)
        else:
            self.grid_mvm = wp.zeros(nodes, dtype=wp.vec4, device=self.device)
        self.grid_v = wp.zeros(nodes, dtype=wp.vec4, device=self.device)  # xyz velocity, 16-byte loads
        self._graphs.clear()
        self._blocks.clear()
        self._refit_cmds.clear()
        self._since_refit = self.model.refit_interval  # refit at the next step

    def grow_grid(self, needed_extent_cells: np.ndarray) -> None:
        """Reallocate larger windows so that an extent [cells] plus margins fits (called by the rollout)."""
        m = self.model
        new = []
        for a, e in enumerate(needed_extent_cells):
            want = int(np.ceil(e)) + 2 * m.margin_cells + 4
            new.append(max(self.grid_dims[a], int(np.ceil(want * 1.25))))
        self._alloc_grid(tuple(new))  # type: ignore[arg-type]
        self.grid_overflow.zero_()

    @property
    def grid_nodes(self) -> int:
        """Number of grid nodes over all scenes."""
        return int(self.grid_mvm.shape[0])

    # -- step ----------------------------------------------------------------------------------------------------
    def set_dt(self, dt: float) -> float:
        """Set the device time step [s] (float32); returns the value actually used."""
        dt32 = float(np.float32(dt))
        if dt32 != self._dt_host:
            self.dt_arr.fill_(dt32)
            self._dt_host = dt32
        return dt32

    def _begin(self, control: Control, dt: float) -> float:
        """Check dt [s], apply the control's pending changes and set the device time step; returns it (float32)."""
        if not (dt > 0.0) or not np.isfinite(dt):
            raise ValueError("dt must be a positive finite number of seconds")
        control.sync(self.time_s)
        self._slide = control.d_grid_slide
        return self.set_dt(dt)

    def step(self, state_in: State, state_out: State, control: Control, dt: float) -> None:
        """Advance all scenes by dt [s]: state_out = step(state_in); state_out may be state_in (in place)."""
        dt32 = self._begin(control, dt)
        refit = self._since_refit >= self.refit_interval(control)
        self._replay_step(state_in, state_out, control, refit)
        self._since_refit = 0 if refit else self._since_refit + 1
        self.steps += 1
        self.time_s += dt32

    def _replay_step(self, state_in: State, state_out: State, control: Control, refit: bool, skip_p2g: bool = False,
                     fuse_next: bool = False) -> None:
        """Run one step's recorded launches (recorded, and on CUDA captured into a graph, on first use)."""
        key = (id(state_in), id(state_out), id(control), refit, self.grid_dims, skip_p2g, fuse_next)
        entry = self._graphs.get(key)
        if entry is None:
            # recorded launches (arguments packed once); on CUDA captured into one graph
            cmds = self._record_step(state_in, state_out, control, refit, skip_p2g, fuse_next)
            graph = self._capture(cmds) if self.use_graph else None
            if self.device_is_cpu:
                cmds = pack_cpu_launches(cmds)  # replays skip Warp's per-call argument packing
            entry = (cmds, graph, state_in, state_out, control)  # keep the arrays alive while cached
            self._graphs[key] = entry
        cmds, graph = entry[0], entry[1]
        if graph is not None:
            self._replay(graph)
        else:
            for cmd in cmds:
                cmd.launch()

    # longest block of whole refit cycles captured into one graph, in steps, and how many graphs are kept
    MAX_BLOCK_STEPS = 256
    MAX_BLOCK_GRAPHS = 24

    def advance_steps(self, state: State, control: Control, dt: float, count: int) -> None:
        """Advance `count` in-place steps of dt [s]; on CUDA runs of steps replay as few multi-step graphs, on the CPU
        a step's g2p also does the next step's p2g where no re-fit comes between them (``cpu_fuse``).

        The steps are cut into a lead (up to the next refit), blocks of 2^b whole refit cycles and a tail; each piece
        is one CUDA graph cached by (refit phase, length), so a reporting interval costs a handful of host calls.
        """
        if count <= 0:
            return
        if self.cpu_fuse:
            self._advance_cpu_fused(state, control, dt, count)
            return
        if not self.use_graph:
            for _ in range(count):
                self.step(state, state, control, dt)
            return
        control.sync(self.time_s)
        self._slide = control.d_grid_slide
        dt32 = self.set_dt(dt)
        R = self.refit_interval(control)
        cycle = R + 1
        while count > 0:
            phase = self._since_refit
            if phase < R:
                n = min(count, R - phase)  # lead: plain steps up to the next refit
            elif count >= cycle:
                cycles = min(count // cycle, max(1, self.MAX_BLOCK_STEPS // cycle))
                n = (1 << (cycles.bit_length() - 1)) * cycle  # 2^b whole cycles (refit + R plain steps each)
            else:
                n = count  # tail: a refit and count - 1 plain steps
            self._launch_block(state, control, phase, n)
            self.steps += n
            self.time_s += n * dt32
            count -= n

    def _advance_cpu_fused(self, state: State, control: Control, dt: float, count: int) -> None:
        """CPU: `count` in-place steps of dt [s], each g2p fused with the next step's p2g where no re-fit comes
        between them and the call goes on (the last step ends with a plain g2p: the state is whole between calls)."""
        dt32 = self._begin(control, dt)
        R = self.refit_interval(control)
        fused_prev = False  # this step's p2g ran inside the previous step's g2p
        for k in range(count):
            refit = self._since_refit >= R
            self._since_refit = 0 if refit else self._since_refit + 1
            fuse = k + 1 < count and self._since_refit < R
            self._replay_step(state, state, control, refit, skip_p2g=fused_prev, fuse_next=fuse)
            fused_prev = fuse
            self.steps += 1
            self.time_s += dt32

    def _launch_block(self, state: State, control: Control, phase: int, n: int) -> None:
        """Replay (capturing it the first time) the graph of n in-place steps starting at refit phase `phase`."""
        R = self.refit_interval(control)
        key = (id(state), id(control), phase, n, R, self.grid_dims)
        entry = self._blocks.get(key)
        if entry is None:
            cmds: list = []
            since = phase
            fused_prev = False  # this step's p2g ran inside the previous step's fused g2p2g
            for k in range(n):
                refit = since >= R
                since = 0 if refit else since + 1
                # fuse this step's g2p with the next step's p2g unless the block ends or the next step re-fits
                fuse = self.cuda_fuse and k + 1 < n and since < R
                cmds += self._record_step(state, state, control, refit, skip_p2g=fused_prev, fuse_next=fuse)
                fused_prev = fuse
            entry = (self._capture(cmds), since, cmds, state, control)  # keep the arrays alive while cached
            self._blocks[key] = entry
            while len(self._blocks) > self.MAX_BLOCK_GRAPHS:
                self._blocks.popitem(last=False)
        else:
            self._blocks.move_to_end(key)
        self._replay(entry[0])
        self._since_refit = entry[1]

    def _capture(self, cmds: list):
        """A CUDA graph of the recorded launches (in order)."""
        wp.load_module(K, device=self.device)
        with wp.ScopedCapture(device=self.device, force_module_load=False) as cap:
            for cmd in cmds:
                cmd.launch()
        return cap.graph

    @staticmethod
    def _replay(graph) -> None:
        """Launch a captured graph."""
        wp.capture_launch(graph)

    def refit_interval(self, control: Control) -> int:
        """Plain steps between window re-fits: the model's, or 0 (every step) while a scene's lattice slides (the
        lattice offset is set at each re-fit)."""
        return 0 if control.grid_sliding else self.model.refit_interval

    def refit(self, state: State) -> None:
        """Move each scene's grid window onto its particles now (device only, no sync)."""
        self._launch_refit(state)
        self._since_refit = 0

    def _launch_refit(self, state: State) -> None:
        """Launch the per-scene bounds reduction and the window fit."""
        # recorded once per (state, grid size): packing the launch arguments costs ~0.1 ms of Python per call
        key = (id(state), id(self._slide), self.grid_dims)
        entry = self._refit_cmds.get(key)
        if entry is None:
            cmds = self._record_refit(state)
            entry = (pack_cpu_launches(cmds) if self.device_is_cpu else cmds, state)  # keeps the state alive
            self._refit_cmds[key] = entry
        for cmd in entry[0]:
            cmd.launch()

    def _record_refit(self, state: State) -> list:
        """Recorded launches of the per-scene bounds reduction and the window fit."""
        m = self.model
        d = self.device
        B = m.n_scenes
        cmds = []
        nx, ny, nz = self.grid_dims
        if self.fast_cuda:
            # one launch: chunk partials (one block each); the last block of each scene combines them (no reset,
            # no same-address atomics) and fits the scene's window
            cmds.append(wp.launch(
                KC.refit_fused,
                dim=self.cuda_n_chunks * self.red_block,
                inputs=[state.x, state.v, m.particle_mass, self.cuda_chunk_scene, self.cuda_chunk_begin,
                        self.cuda_chunk_end, self.cuda_scene_chunk_begin, m.domain_lo, m.domain_hi,
                        self.cuda_part_lo, self.cuda_part_hi, self.cuda_part_v2, self.cuda_part_ke,
                        self.cuda_refit_counter, self.bmin, self.bmax, self.speed_max, self.kinetic, nx, ny, nz,
                        m.dx, m.guard_cells, self._slide, self.clock_time, self.grid_origin, self.grid_overflow,
                        self.red_block],
                device=d,
                record_cmd=True,
                block_dim=self.red_block,
            ))
            return cmds
        else:
            cmds.append(wp.launch(K.reset_scene_stats, dim=B,
                                  inputs=[self.bmin, self.bmax, self.speed_max, self.kinetic], device=d,
                                  record_cmd=True))
            cmds.append(wp.launch(
                K.reduce_scene_stats,
                dim=m.n_chunks,
                inputs=[state.x, state.v, m.particle_mass, m.chunk_scene, m.chunk_begin, m.chunk_end, m.domain_lo,
                        m.domain_hi, self.bmin, self.bmax, self.speed_max, self.kinetic],
                device=d,
                record_cmd=True,
            ))
        cmds.append(wp.launch(
            K.fit_grid,
            dim=B,
            inputs=[self.bmin, self.bmax, nx, ny, nz, m.dx, m.guard_cells, self._slide, self.clock_time,
                    self.grid_origin, self.grid_overflow],
            device=d,
            record_cmd=True,
        ))
        return cmds

    def _record_step(self, state_in: State, state_out: State, control: Control, refit: bool, skip_p2g: bool = False,
                     fuse_next: bool = False) -> list:
        """Recorded launches of one step (replayed directly on CPU, captured into a graph on CUDA). Fast CUDA path,
        in-place multi-step graphs only: skip_p2g = the previous step's fused kernel did this step's p2g (no re-fit
        in between); fuse_next = end with the fused g2p2g, which also does the next step's p2g."""
        m = self.model
        d = self.device
        nx, ny, nz = self.grid_dims
        if skip_p2g or fuse_next:
            assert (self.fast_cuda or self.device_is_cpu) and state_in is state_out and not (refit and skip_p2g)
        cmds = self._record_refit(state_in) if refit else []
        if m.n_colliders:
            cmds.append(wp.launch(
                K.update_collider_poses,
                dim=m.n_colliders,
                inputs=[control.d_ref_pos, control.d_ref_rot, control.d_ref_time, control.d_lin_vel,
                        control.d_ang_vel, self.clock_time, self.dt_arr, self.col_pos0, self.col_rot0,
                        self.col_pos1, self.col_rot1],
                device=d,
                record_cmd=True,
            ))
        if skip_p2g:
            # done by the previous step's g2p, into chunk grids (added by the grid update, or merged here)
            if self._chunks is not None and not self.fast_cuda and not self.cpu_merge_fold:
                cmds.append(self._chunks.merge_grid_cmd(self.grid_mvm, self._per_thread))
        elif self.fast_cuda:
            bd = self.p2g_block
            nt = m.n_particles * self.p2g_parts
            coop = self.cuda_coop_p2g and self.p2g_parts == 1 and _coop_ok(state_in)
            cmds.append(wp.launch(
                KC.p2g_kernel(coop, self.cuda_scatter if self.p2g_parts == 1 else KC.SCATTER_WARP),
                dim=-(-nt // bd) * bd,  # whole blocks: every lane reaches the warp collectives
                inputs=[state_in.x, state_in.v, state_in.C, state_in.F, m.particle_mass, m.particle_vol,
                        m.particle_scene, m.scene_start, m.scene_mu, m.scene_lambda, self.grid_origin, nx, ny, nz,
                        m.dx, self.dt_arr, self.clock_step, self.grid_mvm, self.fail_step, self.fail_particle,
                        self.p2g_parts, m.n_particles],
                device=d,
                record_cmd=True,
                block_dim=bd,
            ))
        else:
            cmds += self._cpu_p2g(state_in)
        gu_kernel, g2p_kernel, gu_dim, g2p_dim = K.grid_update, K.g2p_apic, self._threads(self.grid_nodes), \
            self._threads(m.n_particles)
        gu_block = g2p_block = None
        scatter = self.grid_mvm
        if self.cpu_merge_fold:  # the grid update reads and clears the chunks' buffers too
            gu_kernel, scatter = K.grid_update_merge_cpu, self._chunks.grid_stacked
        if self.fast_cuda:
            coop = self.cuda_coop_g2p and _coop_ok(state_in) and _coop_ok(state_out)
            gu_block = cuda_block_dim(self.grid_nodes)
            gu_kernel = KC.grid_update_kernel(self.cuda_colliders, self.cuda_agg, self.cuda_grid_lazy)
            g2p_block = cuda_block_dim(m.n_particles)
            g2p_kernel = KC.g2p_kernel(self.cuda_colliders, coop, self.cuda_agg)
            if self.cuda_agg:  # warp collectives: whole blocks (the threads past the items take part, write nothing)
                gu_dim = -(-self.grid_nodes // gu_block) * gu_block
            if self.cuda_agg or coop:
                g2p_dim = -(-m.n_particles // g2p_block) * g2p_block
        cmds.append(wp.launch(
            gu_kernel,
            dim=gu_dim,
            inputs=[scatter, self.grid_v, self.grid_origin, nx, ny, nz, m.dx, self.dt_arr, control.d_gravity,
                    m.scene_damping, control.d_grid_slide, m.ground_enabled, m.ground_height, m.ground_mu,
                    self.ground_impulse, m.col_start, m.col_count, m.col_kind, m.col_params, m.col_planes,
                    m.col_radius2, m.col_mu, m.col_bonded, self.col_pos0,
                    self.col_rot0, control.d_lin_vel, control.d_ang_vel, self.collider_impulse, self.clock_time,
                    self.clock_step, self._per_thread, self.grid_nodes],
            device=d,
            record_cmd=True,
            block_dim=gu_block,
        ))
        if fuse_next and not self.fast_cuda:
            g2p_kernel = K.g2p_p2g_cpu  # CPU: this step's g2p and the next step's p2g in one pass
        elif fuse_next:
            coop = self.cuda_coop_g2p and _coop_ok(state_in)
            bd = cuda_block_dim(m.n_particles)
            cmds.append(wp.launch(
                KC.g2p2g_kernel(self.cuda_colliders, coop, self.cuda_agg, self.cuda_scatter, self.cuda_fuse_regs,
                                self.cuda_fuse_keep_c),
                dim=-(-m.n_particles // bd) * bd,  # whole blocks: every lane reaches the warp collectives
                inputs=[state_in.x, state_in.v, state_in.C, state_in.F, m.particle_mass, m.particle_scene,
                        m.scene_start, self.grid_v, self.grid_origin, nx, ny, nz, m.dx, self.dt_arr,
                        control.d_gravity, m.ground_enabled, m.ground_height, m.ground_mu, self.ground_impulse,
                        m.col_start, m.col_count, m.col_kind, m.col_params, m.col_planes, m.col_radius2, m.col_mu,
                        m.col_bonded, self.col_pos1, self.col_rot1, control.d_lin_vel, control.d_ang_vel,
                        self.collider_impulse, m.domain_lo, m.domain_hi, float(m.config.j_min),
                        float(m.config.j_max), self.clock_step, self.fail_step, self.fail_particle, state_out.x,
                        state_out.v, state_out.C, state_out.F, m.particle_vol, m.scene_mu, m.scene_lambda,
                        self.grid_mvm, m.n_particles],
                device=d,
                record_cmd=True,
                block_dim=bd,
            ))
            return cmds
        if self._chunks is not None and not self.fast_cuda:
            return cmds + self._cpu_g2p(g2p_kernel, state_in, state_out, control)
        cmds.append(wp.launch(
            g2p_kernel,
            dim=g2p_dim,
            inputs=self._g2p_inputs(state_in, state_out, control, 0),
            device=d,
            record_cmd=True,
            block_dim=g2p_block,
        ))
        return cmds

    # -- the particle kernels' inputs: all particles, or CPU chunk k's slice and buffers ---------------------------
    def _chunk_view(self, k: int) -> tuple:
        """(count, slice of a per-particle array, scene_start, own buffers or None) of chunk k; without chunks,
        chunk 0 is every particle with the solver's own buffers."""
        m = self.model
        if self._chunks is None:
            return m.n_particles, (lambda arr: arr), m.scene_start, None
        a, b = self._chunks.bounds[k]
        return b - a, (lambda arr: arr[a:b]), self._chunks.scene_start[k], self._chunks.part(k) if k else None

    def _p2g_inputs(self, state: State, k: int) -> list:
        m = self.model
        nx, ny, nz = self.grid_dims
        n, sl, scene_start, parts = self._chunk_view(k)
        grid, fs, fp = ((self.grid_mvm, self.fail_step, self.fail_particle) if parts is None else
                        (parts["grid"], parts["fail_step"], parts["fail_particle"]))
        return [sl(state.x), sl(state.v), sl(state.C), sl(state.F), sl(m.particle_mass), sl(m.particle_vol),
                sl(m.particle_scene), scene_start, m.scene_mu, m.scene_lambda, self.grid_origin, nx, ny, nz, m.dx,
                self.dt_arr, self.clock_step, grid, fs, fp, self._per_thread, n]

    def _g2p_inputs(self, state_in: State, state_out: State, control: Control, k: int) -> list:
        m = self.model
        nx, ny, nz = self.grid_dims
        n, sl, scene_start, parts = self._chunk_view(k)
        ground, collider, fs, fp, grid = (
            (self.ground_impulse, self.collider_impulse, self.fail_step, self.fail_particle, self.grid_mvm)
            if parts is None else
            (parts["ground"], parts["collider"], parts["fail_step"], parts["fail_particle"], parts["grid"]))
        return [sl(state_in.x), sl(state_in.v), sl(state_in.C), sl(state_in.F), sl(m.particle_mass),
                sl(m.particle_scene), scene_start, self.grid_v, self.grid_origin, nx, ny, nz, m.dx, self.dt_arr,
                control.d_gravity, m.ground_enabled, m.ground_height, m.ground_mu, ground, m.col_start, m.col_count,
                m.col_kind, m.col_params, m.col_planes, m.col_radius2, m.col_mu, m.col_bonded, self.col_pos1,
                self.col_rot1, control.d_lin_vel, control.d_ang_vel, collider, m.domain_lo, m.domain_hi,
                float(m.config.j_min), float(m.config.j_max), self.clock_step, fs, fp, sl(state_out.x),
                sl(state_out.v), sl(state_out.C), sl(state_out.F), sl(m.particle_vol), m.scene_mu, m.scene_lambda, grid,
                self._per_thread, n]

    def _cpu_p2g(self, state: State) -> list:
        """CPU p2g: one launch, or one per chunk in threads and then the chunk grids added in order."""
        ch = self._chunks
        launches = [wp.launch(K.p2g_apic_neohookean, dim=self._threads(self._chunk_view(k)[0]),
                              inputs=self._p2g_inputs(state, k), device=self.device, record_cmd=True)
                    for k in range(len(ch.bounds) if ch else 1)]
        if ch is None:
            return launches
        merge = [] if self.cpu_merge_fold else [ch.merge_grid_cmd(self.grid_mvm, self._per_thread)]
        return [ParallelLaunch(launches), *merge]

    def _cpu_g2p(self, kernel, state_in: State, state_out: State, control: Control) -> list:
        """CPU g2p, one launch per chunk in threads, then the chunks' impulses and failures folded in."""
        ch = self._chunks
        launches = [wp.launch(kernel, dim=self._threads(self._chunk_view(k)[0]),
                              inputs=self._g2p_inputs(state_in, state_out, control, k), device=self.device,
                              record_cmd=True)
                    for k in range(len(ch.bounds))]
        return [ParallelLaunch(launches),
                ch.merge_tables_cmd(self.ground_impulse, self.collider_impulse, self.fail_step, self.fail_particle)]

    def _threads(self, n: int) -> int:
        """Launch dimension covering n items at self._per_thread items per thread."""
        return (n + self._per_thread - 1) // self._per_thread

    # -- readback (host syncs: call every N steps, not every step) ------------------------------------------------
    def read_impulses(self, reset: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Accumulated impulses [N s] given TO the object: ground (B,3), colliders (n_colliders,3); then zero them."""
        g = self.ground_impulse.numpy().astype(np.float64)
        c = self.collider_impulse.numpy().astype(np.float64)[: self.model.n_colliders]
        if reset:
            self.ground_impulse.zero_()
            self.collider_impulse.zero_()
        return g, c

    def read_failures(self) -> tuple[np.ndarray, np.ndarray]:
        """Failure tables (B, N_FLAGS): earliest step (INT_MAX = none) and lowest scene-local particle index."""
        B = self.model.n_scenes
        return (
            self.fail_step.numpy().reshape(B, K.N_FLAGS),
            self.fail_particle.numpy().reshape(B, K.N_FLAGS),
        )

    def clear_flag(self, code: int) -> None:
        """Reset one check's column of the failure tables (used for the recoverable out-of-grid flag)."""
        B = self.model.n_scenes
        fs = self.fail_step.numpy().reshape(B, K.N_FLAGS)
        fp = self.fail_particle.numpy().reshape(B, K.N_FLAGS)
        fs[:, code] = INT_MAX
        fp[:, code] = INT_MAX
        self.fail_step.assign(fs.reshape(-1))
        self.fail_particle.assign(fp.reshape(-1))

    def _read(self, arrays: dict[str, wp.array]) -> dict[str, np.ndarray]:
        """Host copies of device arrays with a single synchronisation (pinned staging buffers on CUDA)."""
        if self.device == "cpu":
            return {k: a.numpy().copy() for k, a in arrays.items()}
        out = {}
        for k, a in arrays.items():
            buf = self._host_bufs.get(k)
            if buf is None or buf.shape != a.shape or buf.dtype != a.dtype:
                buf = wp.empty(a.shape, dtype=a.dtype, device="cpu", pinned=True)
                self._host_bufs[k] = buf
            wp.copy(buf, a)
        wp.synchronize_device(self.device)
        for k in arrays:
            out[k] = self._host_bufs[k].numpy().copy()
        return out

    def _snapshot_arrays(self) -> dict[str, wp.array]:
        """The device arrays a health check reads."""
        return {"fail_step": self.fail_step, "fail_particle": self.fail_particle, "bmin": self.bmin,
                "bmax": self.bmax, "speed_max": self.speed_max, "kinetic": self.kinetic,
                "overflow": self.grid_overflow}

    def health_snapshot(self, state: State) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """read_failures() and scene_stats(state) together, with one host sync."""
        self._launch_refit(state)
        self._since_refit = 0
        r = self._read(self._snapshot_arrays())
        B = self.model.n_scenes
        stats = {k: r[k].astype(np.float64) for k in ("bmin", "bmax", "speed_max", "kinetic")}
        stats["overflow"] = r["overflow"]
        return r["fail_step"].reshape(B, K.N_FLAGS), r["fail_particle"].reshape(B, K.N_FLAGS), stats

    def scene_stats(self, state: State) -> dict[str, np.ndarray]:
        """Fresh per-scene bounds [m], max speed [m/s], kinetic energy [J] and grid overflow flags (one sync)."""
        self._launch_refit(state)
        self._since_refit = 0
        return {
            "bmin": self.bmin.numpy().astype(np.float64),
            "bmax": self.bmax.numpy().astype(np.float64),
            "speed_max": self.speed_max.numpy().astype(np.float64),
            "kinetic": self.kinetic.numpy().astype(np.float64),
            "overflow": self.grid_overflow.numpy(),
        }
