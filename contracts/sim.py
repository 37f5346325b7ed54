"""Numerical settings of an MPM rollout (SI units)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_serializer, model_validator

from contracts.base import Model

Device = Literal["cpu", "cuda"]


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

    @model_validator(mode="before")
    @classmethod
    def _one_thread_on_cuda(cls, data):  # type: ignore[no-untyped-def]
        """CUDA ignores CPU threads: record 1, so a CUDA configuration has one cache key whatever was asked."""
        if isinstance(data, dict) and data.get("device") == "cuda" and data.get("cpu_threads", 1) != 1:
            data = {**data, "cpu_threads": 1}
        return data

    @model_serializer(mode="wrap")
    def _omit_single_thread(self, handler):  # type: ignore[no-untyped-def]
        """cpu_threads = 1 is left out of the dump, so the cache keys of configurations from before the field
        existed still name the same results."""
        out = handler(self)
        if isinstance(out, dict) and out.get("cpu_threads") == 1:
            out.pop("cpu_threads")
        return out
