"""L2 drop of a ball of the material (tasks.probes.specimen says why a ball): the rebound the target bands are about."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.probes.deformable_probes.drop import DropMetrics, measure
from tasks.probes.mpm_probe import body_inputs, l2_parameters, run_batch
from tasks.probes.probe import ProbeContext, ProbeModule

VERSION = "2"  # bump when tasks/probes/{deformable,rollout,metrics,specimen}.py change what the probe returns


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("specimen_drop", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out,
                     schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        height_fraction: float, sim: SimConfig, held_out: bool = False) -> ProbeResult:
    """Drop probe of the material's specimen: the rebound the target bands are about."""
    return batch(positions_m, volumes_m3, physical, [material], {"height_fraction": height_fraction}, sim, held_out)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The specimen ball from the contract's drop height (held-out: its held-out height)."""
    p = l2_parameters(ctx)
    frac = p.drop_height_fraction_held_out if ctx.held_out else p.drop_height_fraction_of_height
    return {**body_inputs(ctx, "ball"), "height_fraction": frac, "held_out": ctx.held_out}


PROBE = ProbeModule(stage="L2", name="specimen_drop", version=VERSION, metrics=DropMetrics, run=run, inputs=inputs,
                    batch=batch)
