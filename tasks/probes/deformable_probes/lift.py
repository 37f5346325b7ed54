"""L2 lift/pinch of the object (tasks.probes.deformable.lift): its sag when held by two fingers."""

from __future__ import annotations

from typing import Any

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.probes import deformable
from tasks.probes.mpm_probe import MpmGateMetrics, body_inputs, run_batch
from tasks.probes.probe import ProbeContext, ProbeModule

VERSION = "2.1"  # .1: the lift probe squeezes up to 75 % of the width (#36)


class LiftMetrics(MpmGateMetrics):
    """tasks.probes.deformable.lift's metrics."""

    lift_held: float | None = None
    pinch_rise_m: float | None = None
    sag_m: float | None = None
    pinch_force_n: float | None = None
    sag_ratio: float | None = None


def measure(*args: Any, **kwargs: Any) -> list[ProbeResult]:
    """The lift probe (looked up at call time)."""
    return deformable.lift(*args, **kwargs)


def batch(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, materials: list[Material],
          params: dict[str, float], sim: SimConfig, held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Several materials of this probe, one recording each."""
    return run_batch("lift", measure, positions_m, volumes_m3, physical, materials, params, sim, held_out, schedule)


def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
        sim: SimConfig) -> ProbeResult:
    """Lift/pinch probe (sag) of one material."""
    return batch(positions_m, volumes_m3, physical, [material], {}, sim, False)[0]


def inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The object's particles (no settings: no held-out variant)."""
    return body_inputs(ctx)


PROBE = ProbeModule(stage="L2", name="lift", version=VERSION, metrics=LiftMetrics, run=run, inputs=inputs, batch=batch)
