"""What the deformable (MPM) probe modules share: their gate metrics, their inputs, running a batch of materials with
one recording each (tasks/probes/deformable.py measures)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from cache import cache_relative, content_key
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeMetrics, ProbeResult
from contracts.sim import SimConfig
from contracts.stage import L2Parameters, StageContract
from tasks.probes.probe import ProbeContext, cache_recording_path
from tasks.probes.rollout import DeformableBody
from tasks.probes.specimen import specimen_particles

Measure = Callable[..., list[ProbeResult]]  # (body, materials, sim=, record_paths=, held_out=, schedule=, **params)


class MpmGateMetrics(ProbeMetrics):
    """The gate metrics every MPM probe reports (tasks/probes/metrics.py defines them)."""

    finite: float | None = None
    in_domain: float | None = None
    j_min: float | None = None
    j_max: float | None = None
    ground_tunnelling_m: float | None = None
    engine_health_ok: float | None = None


def l2_parameters(ctx: ProbeContext) -> L2Parameters:
    """The stage's probe settings, typed."""
    return L2Parameters.of(ctx.contract)


def specimen_arrays(physical: PhysicalModel, contract: StageContract, shape: str) -> tuple[np.ndarray, np.ndarray]:
    """A specimen's rest positions [m] and volumes [m^3] at the object's particle spacing (tasks.probes.specimen)."""
    n = int(L2Parameters.of(contract).specimen_particles_per_axis)
    return specimen_particles(float(physical.particle_spacing_m), n, shape)


def body_inputs(ctx: ProbeContext, specimen: str | None = None) -> dict[str, Any]:
    """The inputs every deformable probe takes: the particles (the object's, or a specimen of this shape), the
    physical model, the material (a specimen's without a pressurised shell's gas: Material.specimen), the numerics."""
    material = ctx.material
    if specimen is None:
        pos = np.asarray(ctx.asset.particles_m, np.float64)
        vol = np.asarray(ctx.asset.volumes_m3, np.float64)
    else:
        pos, vol = specimen_arrays(ctx.physical, ctx.contract, specimen)
        material = material.specimen() if material is not None else None
    return {"positions_m": pos, "volumes_m3": vol, "physical": ctx.physical, "material": material,
            "sim": ctx.sim or SimConfig()}


def run_batch(kind: str, measure: Measure, positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel,
              materials: list[Material], params: dict[str, float], sim: SimConfig, held_out: bool,
              schedule: str = "auto") -> list[ProbeResult]:
    """Measure a batch of materials (scheduled by tasks.probes.rollout.plan_batches), recording each scene under the
    cache's recordings folder; the results carry `kind` and their recording's cache-relative path."""
    body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
    keys = [content_key("l2", kind, positions_m, volumes_m3, physical, m, params, sim, held_out) for m in materials]
    paths: list[Path | None] = [cache_recording_path("L2", kind, k) for k in keys]
    results = measure(body, materials, sim=sim, record_paths=paths, held_out=held_out, schedule=schedule, **params)
    out = []
    for r, p in zip(results, paths):
        upd: dict[str, Any] = {"recording": cache_relative(p) if p is not None and p.is_file() else None}
        if r.spec.kind != kind:
            upd["spec"] = r.spec.model_copy(update={"kind": kind})
        out.append(r.model_copy(update=upd))
    return out


__all__ = ["MpmGateMetrics", "body_inputs", "l2_parameters", "run_batch", "specimen_arrays"]
