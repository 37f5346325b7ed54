"""Solver: the only thing that advances time — one MLS-MPM step per call, on the model's device."""

from __future__ import annotations

import gc
import logging
import re
from collections import OrderedDict

import numpy as np
import warp as wp

from contracts.sim import KernelOptions
from tasks.mpm import kernels as K
from tasks.mpm.control import Control
from tasks.mpm.cpu_launch import pack_cpu_launches
from tasks.mpm.model import Model
from tasks.mpm.plan_common import LaunchPlan
from tasks.mpm.plan_cpu import CpuLaunchPlan
from tasks.mpm.plan_cuda import CudaLaunchPlan
from tasks.mpm.state import State

INT_MAX = 2**31 - 1
CAPTURE_ATTEMPTS = 3  # captures of one graph before its launches run uncaptured
# CUDA's stream-capture errors (900-908: unsupported, invalidated, merge, unmatched, unjoined, isolation, implicit
# dependency on the legacy stream, captured event, wrong thread) and Warp's message when ending a failed capture
_CAPTURE_ERROR = re.compile(r"CUDA error 90[0-8]\b|CUDA graph capture failed")
_log = logging.getLogger(__name__)


def capture_invalidated(err: BaseException) -> bool:
    """Whether an error raised inside a CUDA graph capture is the capture's own failure (captured again), not a bug."""
    return bool(_CAPTURE_ERROR.search(str(err)))


def make_plan(solver: Solver, options: KernelOptions) -> LaunchPlan:
    """The launch plan of a solver: the fast CUDA path (plan_cuda.py) on CUDA unless options.cuda_fast is off, else
    the plain kernels (plan_cpu.py: the CPU path; on CUDA the reference path)."""
    if solver.device != "cpu" and options.cuda_fast:
        return CudaLaunchPlan(solver, options)
    return CpuLaunchPlan(solver, options)


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
        self._graphs: dict[tuple, tuple] = {}
        self.capture_retries = 0  # CUDA graph captures invalidated and captured again (see _capture)
        # multi-step graphs of advance_steps, least recently used first (bounded: each holds its launches)
        self._blocks: OrderedDict[tuple, tuple] = OrderedDict()
        self._host_bufs: dict[str, wp.array] = {}  # pinned host mirrors for one-sync readbacks (CUDA)
        self._refit_cmds: dict[tuple, tuple] = {}  # recorded re-fit launches per state
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
        self.slide = self._no_slide  # the lattice motion of the last control stepped with
        # which kernels a step launches, over how many threads (SimConfig.kernel): plan_cpu.py / plan_cuda.py
        self.plan = make_plan(self, model.config.kernel)
        self._alloc_grid(model.grid_dims)
        self._initial_fit = True

    @property
    def fast_cuda(self) -> bool:
        """Whether the steps run the fast CUDA path (plan_cuda.py)."""
        return isinstance(self.plan, CudaLaunchPlan)

    # -- grid ----------------------------------------------------------------------------------------------------
    def _alloc_grid(self, dims: tuple[int, ...]) -> None:
        """Allocate (and zero) the scatter buffer and node velocities for B windows of dims nodes."""
        self.grid_dims: tuple[int, int, int] = (int(dims[0]), int(dims[1]), int(dims[2]))
        nodes = self.model.n_scenes * self.grid_dims[0] * self.grid_dims[1] * self.grid_dims[2]
        self.grid_mvm = self.plan.alloc_scatter(nodes)
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
        self._alloc_grid(tuple(new))
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
        self.slide = control.d_grid_slide
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
            cmds = self.plan.record_step(state_in, state_out, control, refit, skip_p2g, fuse_next)
            graph = self._capture(cmds) if self.use_graph else None
            if self.device_is_cpu:
                cmds = pack_cpu_launches(cmds)  # replays skip Warp's per-call argument packing
            entry = (cmds, graph, state_in, state_out, control)  # keep the arrays alive while cached
            self._graphs[key] = entry
        self._run(entry[1], entry[0])

    # longest block of whole refit cycles captured into one graph, in steps, and how many graphs are kept
    MAX_BLOCK_STEPS = 256
    MAX_BLOCK_GRAPHS = 24

    def advance_steps(self, state: State, control: Control, dt: float, count: int) -> None:
        """Advance `count` in-place steps of dt [s]; on CUDA runs of steps replay as few multi-step graphs, on the CPU
        a step's g2p also does the next step's p2g where no re-fit comes between them (``KernelOptions.cpu_fuse``).

        The steps are cut into a lead (up to the next refit), blocks of 2^b whole refit cycles and a tail; each piece
        is one CUDA graph cached by (refit phase, length), so a reporting interval costs a handful of host calls.
        """
        if count <= 0:
            return
        if self.device_is_cpu and self.plan.fuse:
            self._advance_cpu_fused(state, control, dt, count)
            return
        if not self.use_graph:
            for _ in range(count):
                self.step(state, state, control, dt)
            return
        control.sync(self.time_s)
        self.slide = control.d_grid_slide
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
                fuse = self.plan.fuse and k + 1 < n and since < R
                cmds += self.plan.record_step(state, state, control, refit, skip_p2g=fused_prev, fuse_next=fuse)
                fused_prev = fuse
            entry = (self._capture(cmds), since, cmds, state, control)  # keep the arrays alive while cached
            self._blocks[key] = entry
            while len(self._blocks) > self.MAX_BLOCK_GRAPHS:
                self._blocks.popitem(last=False)
        else:
            self._blocks.move_to_end(key)
        self._run(entry[0], entry[2])
        self._since_refit = entry[1]

    def _capture(self, cmds: list):
        """A CUDA graph of the recorded launches (in order), or None when CAPTURE_ATTEMPTS captures were invalidated
        (the launches then run uncaptured at every replay: the same arithmetic, more host calls).

        Python's cyclic garbage collector is held off while the stream captures: a collection there freed an
        unreachable solver's pinned host buffers (cudaFreeHost synchronises with the legacy stream) in the middle of
        the capture, and the capture failed (Warp CUDA errors 906 'operation would make the legacy stream depend on a
        capturing blocking stream' in release_now, and 901 after it: a sausage and a piece of jelly in session 40's
        throughput run, a boiled egg and a silicone baking mat before). The same error came back once in 40 assets
        with the collector off (a cat bed, session 42): Warp defers a release while any capture is open, but checks
        for one before it releases, so a release on another thread can still land inside a capture. Nothing a
        capture records has run, so an invalidated capture is simply captured again, after a device synchronisation."""
        wp.load_module(K, device=self.device)
        for attempt in range(CAPTURE_ATTEMPTS):
            collecting = gc.isenabled()
            gc.disable()
            try:
                with wp.ScopedCapture(device=self.device, force_module_load=False) as cap:
                    for cmd in cmds:
                        cmd.launch()
                return cap.graph
            except RuntimeError as err:
                if not capture_invalidated(err):
                    raise
                self.capture_retries += 1
                _log.warning("CUDA graph capture invalidated (attempt %d of %d): %s", attempt + 1, CAPTURE_ATTEMPTS,
                             err)
            finally:
                if collecting:
                    gc.enable()
            wp.synchronize_device(self.device)
        return None

    def _run(self, graph, cmds: list) -> None:
        """Replay a captured graph, or launch the recorded launches one by one when there is none."""
        if graph is not None:
            self._replay(graph)
        else:
            for cmd in cmds:
                cmd.launch()

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
        key = (id(state), id(self.slide), self.grid_dims)
        entry = self._refit_cmds.get(key)
        if entry is None:
            cmds = self.plan.record_refit(state)
            entry = (pack_cpu_launches(cmds) if self.device_is_cpu else cmds, state)  # keeps the state alive
            self._refit_cmds[key] = entry
        for cmd in entry[0]:
            cmd.launch()

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
