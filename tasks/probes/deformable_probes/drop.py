"""L2 drop of the object (tasks.probes.deformable.drop): impact strain, rebound, dissipation, settling."""

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

VERSION = "2"  # bump when tasks/probes/{deformable,rollout,metrics}.py change what the probe returns


class DropMetrics(MpmGateMetrics):
    """tasks.probes.deformable.drop's metrics."""

    drop_height_m: float | None = None
    rest_com_z_m: float | None = None
    rebound_ratio: float | None = None
    fall_height_m: float | None = None
    dissipated_energy_fraction: float | None = None
    max_impact_strain: float | None = None
    settle_time_s: float | None = None
    settled: float | None = None
    first_contact_time_s: float | None = None


def measure(*args: Any, **kwargs: Any) -> list[ProbeResult]:
    """The drop probe (looked up at call time)."""
    return deformable.drop(*args, **kwargs)


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("drop", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out, schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        height_fraction: float, sim: SimConfig, held_out: bool = False) -> ProbeResult:
    """Drop probe (rebound, dissipation, impact strain, settle time) of one material."""
    return batch(positions_m, volumes_m3, physical, [material], {"height_fraction": height_fraction}, sim, held_out)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The object's particles from the contract's drop height (held-out: its held-out height)."""
    p = l2_parameters(ctx)
    frac = p.drop_height_fraction_held_out if ctx.held_out else p.drop_height_fraction_of_height
    return {**body_inputs(ctx), "height_fraction": frac, "held_out": ctx.held_out}


PROBE = ProbeModule(stage="L2", name="drop", version=VERSION, metrics=DropMetrics, run=run, inputs=inputs, batch=batch)
