"""CPU: one rollout's particles shared by several threads.

Warp runs a CPU launch on one core, and the launch releases the GIL. So the particle kernels (p2g, g2p) of a step run
as one launch per chunk of consecutive particles, each in its own thread. Each chunk scatters into its own grid
buffer, failure tables and impulse accumulators. Before the grid update, the chunk grids are added into the main one
in chunk order. After g2p, the tables and impulses are folded in (failures: the earliest step, then the lowest
particle). The grid update and the re-fit stay single-threaded.

Results depend on the number of chunks (float sums in another order), never on the cores present or on thread
timing: the same chunk count gives the same bits on any machine.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import warp as wp

wp.set_module_options({"enable_backward": False, "optimization_level": 3})

INT_MAX = 2**31 - 1
# below this many particles per chunk, a thread hand-off costs more than the chunk's work (2-core AMD EPYC,
# 64k cube: p2g 3.1 ms in one thread, 1.6-2.3 ms in two)
MIN_PARTICLES_PER_CHUNK = 2048


@wp.kernel
def merge_grids(dst: wp.array(dtype=wp.vec4), parts: wp.array(dtype=wp.vec4), n_parts: int, per_thread: int,
                n: int):
    """dst[i] += parts[k * n + i] for k = 0, 1, ... in order; the parts are zeroed for the next scatter."""
    t = wp.tid()
    # Warp's stub types wp.tid() as int | tuple (its 2-D+ forms); in this 1-D kernel it is an int
    for i in range(t * per_thread, wp.min((t + 1) * per_thread, n)):  # type: ignore[arg-type, operator]
        acc = dst[i]
        for k in range(n_parts):
            j = k * n + i
            acc = acc + parts[j]
            parts[j] = wp.vec4(0.0, 0.0, 0.0, 0.0)
        dst[i] = acc


@wp.kernel
def merge_tables(ground: wp.array(dtype=wp.vec3), ground_parts: wp.array(dtype=wp.vec3), n_ground: int,
                 collider: wp.array(dtype=wp.vec3), collider_parts: wp.array(dtype=wp.vec3), n_collider: int,
                 fail_step: wp.array(dtype=wp.int32), fail_particle: wp.array(dtype=wp.int32),
                 step_parts: wp.array(dtype=wp.int32), particle_parts: wp.array(dtype=wp.int32), n_slots: int,
                 n_parts: int):
    """Fold the chunks' impulses (sums, in chunk order) and failure tables (earliest step, then lowest particle, as
    kernels.flag_failure keeps them) into the main ones, and reset the chunks' (one thread: a few dozen entries)."""
    for k in range(n_parts):
        for i in range(n_ground):
            j = k * n_ground + i
            ground[i] = ground[i] + ground_parts[j]
            ground_parts[j] = wp.vec3(0.0, 0.0, 0.0)
        for i in range(n_collider):
            j = k * n_collider + i
            collider[i] = collider[i] + collider_parts[j]
            collider_parts[j] = wp.vec3(0.0, 0.0, 0.0)
        for i in range(n_slots):
            j = k * n_slots + i
            s = step_parts[j]
            p = particle_parts[j]
            if s < fail_step[i] or (s == fail_step[i] and p < fail_particle[i]):
                fail_step[i] = s
                fail_particle[i] = p
            step_parts[j] = INT_MAX
            particle_parts[j] = INT_MAX


_POOLS: dict[int, ThreadPoolExecutor] = {}
_POOLS_LOCK = threading.Lock()


def _pool(workers: int) -> ThreadPoolExecutor:
    """A process-wide pool of `workers` threads (shared by every solver: pool tasks never wait on each other)."""
    with _POOLS_LOCK:
        pool = _POOLS.get(workers)
        if pool is None:
            pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="mpm-cpu")
            _POOLS[workers] = pool
        return pool


class ParallelLaunch:
    """Recorded launches run together: the first on the calling thread, the others on the pool; returns when all
    are done (an exception in any is raised)."""

    def __init__(self, cmds: list) -> None:
        self.cmds = cmds
        self.kernel = cmds[0].kernel
        self._pool = _pool(len(cmds) - 1) if len(cmds) > 1 else None

    def launch(self) -> None:
        if self._pool is None:
            self.cmds[0].launch()
            return
        futures = [self._pool.submit(c.launch) for c in self.cmds[1:]]
        try:
            self.cmds[0].launch()
        finally:
            for f in futures:
                f.result()


def chunk_bounds(n_items: int, threads: int) -> list[tuple[int, int]]:
    """Consecutive, balanced [begin, end) ranges: `threads` of them, fewer where chunks would be too small."""
    t = max(1, min(int(threads), n_items // MIN_PARTICLES_PER_CHUNK))
    edges = [round(k * n_items / t) for k in range(t + 1)]
    return [(edges[k], edges[k + 1]) for k in range(t)]


class CpuChunks:
    """The per-chunk buffers of one solver: chunk 0 uses the solver's own, chunks 1.. their slices of stacked
    arrays (one grid buffer, failure tables and impulse accumulators each)."""

    def __init__(self, bounds: list[tuple[int, int]], scene_start: np.ndarray, n_scenes: int, n_colliders: int,
                 n_slots: int, device: str) -> None:
        self.bounds = bounds
        self.n_parts = len(bounds) - 1
        P = self.n_parts
        self.n_scenes, self.n_colliders, self.n_slots = n_scenes, n_colliders, n_slots
        d = device
        self.device = d
        # scene_start shifted per chunk: a kernel's particle index is local to its slice (failures name the
        # scene-local index p - scene_start[s], as without chunks)
        self.scene_start: list[wp.array] = [wp.array(np.asarray(scene_start, np.int64) - a, dtype=wp.int32, device=d)
                            for a, _ in bounds]
        self.ground_parts = wp.zeros(P * n_scenes, dtype=wp.vec3, device=d)
        self.collider_parts = wp.zeros(P * n_colliders, dtype=wp.vec3, device=d)
        self.step_parts = wp.full(P * n_slots, INT_MAX, dtype=wp.int32, device=d)
        self.particle_parts = wp.full(P * n_slots, INT_MAX, dtype=wp.int32, device=d)
        self.grid_parts: wp.array | None = None
        self.grid_stacked: wp.array | None = None
        self.grid_nodes = 0

    def alloc_grid(self, nodes: int) -> wp.array:
        """Zeroed scatter buffers for `nodes` nodes (called whenever the solver reallocates its grid): one array, the
        main buffer (returned, a view) followed by the chunks' (``kernels.grid_update_merge_cpu`` reads them all)."""
        self.grid_nodes = int(nodes)
        self.grid_stacked = wp.zeros((self.n_parts + 1) * self.grid_nodes, dtype=wp.vec4, device=self.device)
        self.grid_parts = self.grid_stacked[self.grid_nodes:]
        return self.grid_stacked[:self.grid_nodes]

    def part(self, k: int) -> dict[str, wp.array]:
        """Chunk k's (k >= 1) views: grid buffer, ground and collider impulses, failure tables."""
        assert self.grid_parts is not None, "alloc_grid before part"
        j = k - 1
        g, c, s = self.grid_nodes, self.n_colliders, self.n_slots
        return {"grid": self.grid_parts[j * g:(j + 1) * g],
                "ground": self.ground_parts[j * self.n_scenes:(j + 1) * self.n_scenes],
                "collider": self.collider_parts[j * c:(j + 1) * c],
                "fail_step": self.step_parts[j * s:(j + 1) * s],
                "fail_particle": self.particle_parts[j * s:(j + 1) * s]}

    def merge_grid_cmd(self, grid_mvm: wp.array, per_thread: int):
        """The recorded launch that adds the chunk grids into grid_mvm."""
        n = self.grid_nodes
        return wp.launch(merge_grids, dim=(n + per_thread - 1) // per_thread,
                         inputs=[grid_mvm, self.grid_parts, self.n_parts, per_thread, n], device=self.device,
                         record_cmd=True)

    def merge_tables_cmd(self, ground: wp.array, collider: wp.array, fail_step: wp.array, fail_particle: wp.array):
        """The recorded launch that folds the chunks' impulses and failure tables into the solver's."""
        return wp.launch(merge_tables, dim=1,
                         inputs=[ground, self.ground_parts, self.n_scenes, collider, self.collider_parts,
                                 self.n_colliders, fail_step, fail_particle, self.step_parts, self.particle_parts,
                                 self.n_slots, self.n_parts],
                         device=self.device, record_cmd=True)


__all__ = ["CpuChunks", "MIN_PARTICLES_PER_CHUNK", "ParallelLaunch", "chunk_bounds"]
