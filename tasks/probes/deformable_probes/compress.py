"""L2 compression of the object (tasks.probes.deformable.compress): its structure's stiffness and recovery."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.probes import deformable
from tasks.probes.mpm_probe import MpmGateMetrics, body_inputs, l2_parameters, run_batch
from tasks.probes.probe import ProbeContext, ProbeModule

VERSION = "3"  # 3: a stiff body is mass-scaled (deformable.compress_qs_period_s); bump when deformable.py changes it


class CompressMetrics(MpmGateMetrics):
    """tasks.probes.deformable.compress's metrics."""

    effective_modulus_pa: float | None = None
    compression_strain: float | None = None
    compression_force_n: float | None = None
    cross_section_m2: float | None = None
    recovery_ratio: float | None = None


def measure(*args: Any, **kwargs: Any) -> list[ProbeResult]:
    """The compression probe (looked up at call time)."""
    return deformable.compress(*args, **kwargs)


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("compress", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out, schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        strain: float, sim: SimConfig, held_out: bool = False) -> ProbeResult:
    """Compression probe (effective modulus, recovery) of one material."""
    return batch(positions_m, volumes_m3, physical, [material], {"strain": strain}, sim, held_out)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The object's particles at the contract's strain (held-out: its held-out strain)."""
    p = l2_parameters(ctx)
    strain = p.compression_strain_held_out if ctx.held_out else p.compression_strain
    return {**body_inputs(ctx), "strain": strain, "held_out": ctx.held_out}


PROBE = ProbeModule(stage="L2", name="compress", version=VERSION, metrics=CompressMetrics, run=run, inputs=inputs,
                    batch=batch)
