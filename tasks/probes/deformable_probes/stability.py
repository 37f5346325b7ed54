"""L2 long rest rollout of the object (tasks.probes.deformable.stability): stable_long_rollout."""

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

VERSION = "3"  # 3: a stiff body is mass-scaled (deformable.STABILITY_QS_PERIOD_S); bump when deformable.py changes it


class StabilityMetrics(MpmGateMetrics):
    """tasks.probes.deformable.stability's metrics."""

    ke_decay_ratio: float | None = None
    late_drift_ratio: float | None = None
    deformation_ratio: float | None = None
    volume_change: float | None = None
    stable_long_rollout: float | None = None


def measure(*args: Any, **kwargs: Any) -> list[ProbeResult]:
    """The stability probe (looked up at call time)."""
    return deformable.stability(*args, **kwargs)


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("stability", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out,
                     schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        duration_s: float, sim: SimConfig) -> ProbeResult:
    """Long rest rollout (stable_long_rollout) of one material."""
    return batch(positions_m, volumes_m3, physical, [material], {"duration_s": duration_s}, sim, False)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The object's particles for the contract's rollout duration."""
    return {**body_inputs(ctx), "duration_s": l2_parameters(ctx).stability_duration_s}


PROBE = ProbeModule(stage="L2", name="stability", version=VERSION, metrics=StabilityMetrics, run=run, inputs=inputs,
                    batch=batch)
