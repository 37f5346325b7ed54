"""Numerical settings of an MPM rollout (SI units)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any, Literal

from pydantic import Field, model_serializer, model_validator

from contracts.base import Model

Device = Literal["cpu", "cuda"]


class KernelOptions(Model):
    """Which kernel variants and launch shapes the MPM engine uses (tasks/mpm/plan_cpu.py, plan_cuda.py).

    The CPU options give the same rollout bit for bit either way (they only save passes); the CUDA variants change
    only the order of float additions (CUDA atomics already do), with figures in benchmarks/engine/BENCHMARKS.md.
    Defaults are the engine's choice; the other values exist for experiments and tests.
    """

    # CPU
    cpu_fuse: bool = Field(
        default=True,
        description="CPU: inside a multi-step advance, a step's g2p also does the next step's p2g where no re-fit "
                    "comes between them (one pass over the particles fewer per step; same rollout bit for bit)",
    )
    cpu_merge: bool = Field(
        default=True,
        description="CPU with cpu_threads > 1: the grid update adds the chunks' scatter buffers itself instead of a "
                    "merge pass before it (one pass over the nodes fewer per step; same rollout bit for bit)",
    )
    # CUDA
    cuda_fast: bool = Field(
        default=True,
        description="CUDA: the block-level kernels of kernels_cuda.py with the variants below; False = the plain "
                    "one-thread-per-item kernels of kernels.py (the reference path, every option below ignored)",
    )
    cuda_block_threads: int = Field(
        default=0, ge=0, le=1024,
        description="CUDA: threads per block for every particle and node launch [threads]; 0 = fitted to the "
                    "problem size (64, 128 or 256)",
    )
    specialize: bool = Field(
        default=True,
        description="CUDA: a model without kinematic colliders runs g2p and the grid update without the collider "
                    "contact code",
    )
    agg: bool = Field(
        default=True,
        description="CUDA: a warp's ground impulses summed by shuffles, one atomic per warp",
    )
    coop: bool = Field(
        default=True,
        description="CUDA: allow warp-cooperative particle record loads/stores (16-byte accesses through shared "
                    "memory); coop_g2p / coop_p2g pick the kernels",
    )
    coop_g2p: bool = Field(default=True, description="CUDA: cooperative loads/stores in g2p (and the fused kernel)")
    coop_p2g: bool = Field(default=False, description="CUDA: cooperative loads in p2g (no gain measured)")
    coop_min_particles: int = Field(
        default=24_000, ge=0,
        description="CUDA: cooperative records only from this many particles (all scenes) [particles]",
    )
    coop_max_particles: int = Field(
        default=400_000, ge=0,
        description="CUDA: cooperative records only up to this many particles [particles]; 0 = no upper bound",
    )
    fuse: bool = Field(
        default=True,
        description="CUDA: inside multi-step graphs, a step's g2p and the next step's p2g run as one kernel "
                    "(kernels_cuda.make_g2p2g) where no re-fit comes between them",
    )
    fuse_min_particles: int = Field(
        default=0, ge=0, description="CUDA: the fused kernel only from this many particles [particles]"
    )
    fuse_max_registers: int = Field(
        default=128, ge=0, le=255,
        description="CUDA: register cap of the fused kernel [registers per thread]; 0 = the compiler's choice",
    )
    fuse_keep_c: bool = Field(
        default=False,
        description="CUDA: the fused kernel loads and stores C like the plain g2p (False: C stays in registers "
                    "between its g2p and scatter)",
    )
    grid_lazy: bool = Field(
        default=True,
        description="CUDA: the grid update writes nothing for a node without mass (same rollout, fewer stores)",
    )
    scatter: Literal["scan", "warp"] = Field(
        default="scan",
        description="CUDA, one particle per thread: scan = a warp's particles merged along stencil rows "
                    "(kernels_cuda.scatter_stencil_scan); warp = per-node shuffles among same-base lanes",
    )
    p2g_parts: Literal[0, 1, 3, 9] = Field(
        default=0,
        description="CUDA: threads per particle in the separate p2g [threads] (1, 3 or 9 stencil slabs/rows); "
                    "0 = 3 below 24,000 particles with scatter=warp, else 1",
    )

    @classmethod
    def from_assignments(cls, items: Sequence[str]) -> KernelOptions:
        """Options from ``name=value`` strings (a command line's ``--kernel scatter=warp``); values are read as JSON
        (numbers, true/false), else as text. ValueError on an unknown name or a bad value."""
        values: dict[str, Any] = {}
        for item in items:
            name, sep, text = item.partition("=")
            if not sep or not name.strip():
                raise ValueError(f"kernel option {item!r} is not name=value")
            try:
                values[name.strip()] = json.loads(text)
            except json.JSONDecodeError:
                values[name.strip()] = text
        return cls.model_validate(values)


class SimConfig(Model):
    """How the MPM integrates; the probe decides what happens (duration, colliders)."""

    device: Device = Field(default="cpu", description="Warp device: cpu or cuda")
    dx_m: float | None = Field(
        default=None, gt=0, description="grid spacing [m]; None = twice the particle spacing"
    )
    dt_max_s: float = Field(default=2e-4, gt=0, description="user cap on the time step [s]")
    dt_min_s: float = Field(
        default=1e-6, gt=0,
        description="smallest time step [s] the material's CFL step may ask for; a stiffer material (or a finer grid) "
                    "is refused before the rollout starts instead of running for hours",
    )
    dt_fixed_s: float | None = Field(
        default=None, gt=0, description="fixed time step [s] (benchmarks); None = adaptive CFL"
    )
    cfl: float = Field(default=0.4, gt=0, le=1.0, description="CFL number C in dt <= C dx / (c_p + |v|max)")
    substeps: int = Field(default=1, ge=1, description="substeps per reported step (numerical revision)")
    gravity_m_per_s2: tuple[float, float, float] = Field(
        default=(0.0, 0.0, -9.81), description="gravity vector [m/s^2], z up"
    )
    ground_height_m: float = Field(default=0.0, description="height of the ground plane z [m]")
    ground_friction: float = Field(default=0.5, ge=0, description="Coulomb friction of the ground [-]")
    grid_margin_m: float = Field(
        default=0.05, ge=0, description="free space kept around the object's bounds in the grid [m]"
    )
    j_min: float = Field(default=0.2, gt=0, description="health: smallest allowed det(F) [-]")
    j_max: float = Field(default=5.0, gt=1, description="health: largest allowed det(F) [-]")
    energy_growth_max: float = Field(
        default=10.0, gt=1, description="health: max ratio of kinetic energy to the injected energy budget [-]"
    )
    seed: int = Field(default=0, description="seed for any randomness (particle jitter)")
    cpu_threads: int = Field(
        default=1, ge=1, le=64,
        description="CPU only: threads sharing each rollout's particles (tasks/mpm/cpu_threads.py). Results depend "
                    "on this number (float sums in another order), not on the cores present; always 1 on CUDA",
    )

    kernel: KernelOptions = Field(
        default_factory=KernelOptions,
        description="kernel variants and launch shapes (engine experiments; the defaults are the engine's choice)",
    )

    @model_validator(mode="before")
    @classmethod
    def _one_thread_on_cuda(cls, data):
        """CUDA ignores CPU threads: record 1, so a CUDA configuration has one cache key whatever was asked."""
        if isinstance(data, dict) and data.get("device") == "cuda" and data.get("cpu_threads", 1) != 1:
            data = {**data, "cpu_threads": 1}
        return data

    @model_serializer(mode="wrap")
    def _omit_defaults_of_later_fields(self, handler):
        """cpu_threads = 1 and the default kernel options are left out of the dump, so the cache keys of
        configurations from before those fields existed still name the same results; any other value is in it."""
        out = handler(self)
        if isinstance(out, dict):
            if out.get("cpu_threads") == 1:
                out.pop("cpu_threads")
            if self.kernel == _DEFAULT_KERNEL:
                out.pop("kernel", None)
        return out


_DEFAULT_KERNEL = KernelOptions()
