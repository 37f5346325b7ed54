"""L2 compression of a cube of the material (tasks.probes.specimen): the modulus and recovery the target bands are
about."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.probes.deformable_probes.compress import CompressMetrics, measure
from tasks.probes.mpm_probe import body_inputs, l2_parameters, run_batch
from tasks.probes.probe import ProbeContext, ProbeModule

VERSION = "3"  # 3: a stiff specimen is mass-scaled (deformable.compress_qs_period_s); bump when tasks/probes/{deformable,rollout,metrics,specimen}.py change what the probe returns


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("specimen_compress", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out,
                     schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        strain: float, sim: SimConfig, held_out: bool = False) -> ProbeResult:
    """Compression probe of the material's specimen: the modulus and recovery the target bands are about."""
    return batch(positions_m, volumes_m3, physical, [material], {"strain": strain}, sim, held_out)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The specimen cube at the contract's strain (held-out: its held-out strain)."""
    p = l2_parameters(ctx)
    strain = p.compression_strain_held_out if ctx.held_out else p.compression_strain
    return {**body_inputs(ctx, "cube"), "strain": strain, "held_out": ctx.held_out}


PROBE = ProbeModule(stage="L2", name="specimen_compress", version=VERSION, metrics=CompressMetrics, run=run,
                    inputs=inputs, batch=batch)
