"""L2's screening on the material's specimen (the paper's batched screening before the harness): compress three
stiffnesses (a rollout each, side by side) and drop three damping rates (one lock-step rollout), each set a cached
task, then keep a start value whose metric is already well inside its band, else interpolate the value that hits the
band's centre.

The screening task is a cached task (its key: name, version and inputs, as it was in flows/l2_material.py); the flow
calls screen() with the L0 asset, the frozen physical model, the contract and the targets.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from cache import cached_task
from contracts.agents import TargetBand, TargetBehaviour
from contracts.errors import ContractError, InputError
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from contracts.stage import EditableField, L2Parameters, StageContract
from tasks.geometry.outputs import L0Asset
from tasks.probes.probe import Probe, ProbeContext
from tasks.probes.registry import probe as find_probe
from tasks.probes.rollout import DeformableBody, plan_batches, rollouts

TASK_VERSION = "3"  # the screening task's; bump it with a screened probe's VERSION (tasks/probes/deformable_probes/): 3, compress's 3
SCREEN_SCHEDULE = "auto"  # how object candidates share rollouts (tasks.probes.rollout.plan_batches)
# the specimen's candidates as plan_batches' 'auto' groups them: the three moduli a rollout each at its own time step
# and length, side by side on the CPU (one lock-step batch ran every scene at the stiffest dt for the softest duration,
# 3x the steps on one core: 15.8 s of the cold main job's 32 s of L2 on the 2-core CPU); the damping sweep shares one
# time step, so it stays one rollout
SPECIMEN_SCREEN_SCHEDULE = "auto"
SCREEN_KEEP_MARGIN = 0.1  # a start value is kept when its metric is inside its band less 10 % of the width at each end


def l2_probe(kind: str) -> Probe:
    """The registered L2 probe `kind` (InputError naming the known ones)."""
    try:
        return find_probe("L2", kind)
    except ContractError as exc:
        raise InputError(f"unknown deformable probe '{kind}': {exc}") from None


@cached_task(version=TASK_VERSION, name="l2.screen")
def screen_task(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, kind: str,
                materials: list[Material], params: dict[str, float], sim: SimConfig,
                schedule: str = SCREEN_SCHEDULE) -> list[ProbeResult]:
    """Several candidate materials of one probe, scheduled by `schedule` (tasks.probes.rollout.plan_batches);
    screen_rollouts() counts the simulation calls."""
    batch = l2_probe(kind).batch
    if batch is None:
        raise InputError(f"the probe '{kind}' cannot screen several materials at once")
    return batch(positions_m, volumes_m3, physical, materials, params, sim, False, schedule)


def probe_parameters(contract: StageContract) -> dict[str, float]:
    """The contract's probe settings (selection and held-out)."""
    p = L2Parameters.of(contract)
    return {"strain": p.compression_strain, "strain_held_out": p.compression_strain_held_out,
            "height_fraction": p.drop_height_fraction_of_height,
            "height_fraction_held_out": p.drop_height_fraction_held_out,
            "stability_duration_s": p.stability_duration_s,
            "specimen_particles_per_axis": float(p.specimen_particles_per_axis)}


def specimen_arrays(physical: PhysicalModel, contract: StageContract,
                    kind: str = "specimen_compress") -> tuple[np.ndarray, np.ndarray]:
    """A specimen probe's rest positions [m] and volumes [m^3] at the object's particle spacing (its module's inputs:
    the cube for the compression, the ball inscribed in it for the drop)."""
    kw = l2_probe(kind).inputs(ProbeContext(asset=None, contract=contract, physical=physical))
    return kw["positions_m"], kw["volumes_m3"]


def fit_log(xs: list[float], ys: list[float], target: float, log_x: bool) -> float | None:
    """x where the least-squares line through (x or log x, log y) reaches log target (None if flat or undefined)."""
    pts = [(math.log(x) if log_x else x, math.log(y)) for x, y in zip(xs, ys) if y > 0 and (x > 0 or not log_x)]
    if len(pts) < 2:
        return None
    a, b = np.polyfit([p[0] for p in pts], [p[1] for p in pts], 1)
    if abs(a) < 1e-9:
        return None
    u = (math.log(target) - b) / a
    return math.exp(u) if log_x else u


def start_in_band(start: float, xs: list[float], results: list[ProbeResult], metric: str, band: TargetBand,
                   margin: float = SCREEN_KEEP_MARGIN) -> bool:
    """True when the start value was screened and its metric lies inside the band less `margin` at each end: the
    screening then keeps the start value instead of aiming at the band's centre (the least change that meets the
    target; a centre the solver cannot reach, e.g. a rebound of 0.6 for rubber, would otherwise drive the value to
    its bound)."""
    i = next((k for k, x in enumerate(xs) if math.isclose(x, start, rel_tol=1e-12, abs_tol=1e-15)), None)
    return i is not None and band.contains_inner(results[i].metrics.get(metric), margin)


def screen_moduli(values: dict[str, float], field: EditableField) -> list[float]:
    """Young's moduli the screening compresses: 1/3, 1 and 3 x the start value, clamped into the field [Pa]."""
    return [min(max(values["youngs_modulus_pa"] * k, field.low), field.high) for k in (1 / 3, 1.0, 3.0)]


def screen_dampings(values: dict[str, float], field: EditableField) -> list[float]:
    """Damping rates the screening drops: 0.25, 1 and 2.5 x the start value + 2, clamped, distinct, sorted [1/s]."""
    d0 = values["damping_rate_per_s"]
    return sorted({min(max(d, field.low), field.high) for d in (0.25 * d0, d0, 2.5 * d0 + 2.0)})


def screen_rollouts(physical: PhysicalModel, positions_m: np.ndarray, volumes_m3: np.ndarray,
                    materials: list[Material], sim: SimConfig, results: list[ProbeResult],
                    schedule: str = SCREEN_SCHEDULE) -> int:
    """Simulation calls of one screen_task: one per rollout (a batch of 3 is 1; 3 candidates one after another are 3)."""
    body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
    return rollouts(plan_batches(body, materials, sim, schedule), results)


def screen(asset: L0Asset, physical: PhysicalModel, contract: StageContract, targets: TargetBehaviour,
           start: dict[str, float], sim: SimConfig,
           fixed: dict[str, float] | None = None) -> tuple[dict[str, float], dict[str, Any]]:
    """Screening on the material's specimen: compress three stiffnesses, drop three damping rates (scheduled by
    SPECIMEN_SCREEN_SCHEDULE); keep a start value whose metric is already well inside its band
    (start_in_band), else interpolate the value that hits the band's centre. fixed: material fields that every
    candidate carries and the screening does not vary (the class's viscosity). Returns (initial values, summary)."""
    fixed = dict(fixed or {})
    p = probe_parameters(contract)
    fields = {f.name: f for f in contract.editable_fields}
    base = {"physical": physical, "sim": sim, "schedule": SPECIMEN_SCREEN_SCHEDULE}
    values = dict(start)
    summary: dict[str, Any] = {"sim_calls": 0}
    band = targets.band("effective_modulus_pa")
    if band is not None:
        f = fields["youngs_modulus_pa"]
        es = screen_moduli(values, f)
        mats = [Material(youngs_modulus_pa=e, poisson_ratio=values["poisson_ratio"],
                         damping_rate_per_s=values["damping_rate_per_s"], **fixed) for e in es]
        pos, vol = specimen_arrays(physical, contract, "specimen_compress")
        rs = screen_task(positions_m=pos, volumes_m3=vol, kind="specimen_compress", materials=mats,
                         params={"strain": p["strain"]}, **base)
        ok = [(e, r.metrics["effective_modulus_pa"]) for e, r in zip(es, rs) if "effective_modulus_pa" in r.metrics]
        kept = start_in_band(values["youngs_modulus_pa"], es, rs, "effective_modulus_pa", band)
        guess = None if kept else fit_log([e for e, _ in ok], [m for _, m in ok], band.center, log_x=True)
        if guess is not None:
            values["youngs_modulus_pa"] = min(max(guess, f.low), f.high)
        calls = screen_rollouts(physical, pos, vol, mats, sim, rs, SPECIMEN_SCREEN_SCHEDULE)
        summary["compress"] = {"youngs_modulus_pa": es, "effective_modulus_pa": [r.metrics.get("effective_modulus_pa")
                                                                                for r in rs], "sim_calls": calls,
                               "kept_start": kept}
        summary["sim_calls"] += calls
    band = targets.band("rebound_ratio")
    if band is not None:
        f = fields["damping_rate_per_s"]
        ds = screen_dampings(values, f)
        mats = [Material(youngs_modulus_pa=values["youngs_modulus_pa"], poisson_ratio=values["poisson_ratio"],
                         damping_rate_per_s=d, **fixed) for d in ds]
        pos, vol = specimen_arrays(physical, contract, "specimen_drop")
        rs = screen_task(positions_m=pos, volumes_m3=vol, kind="specimen_drop", materials=mats,
                         params={"height_fraction": p["height_fraction"]}, **base)
        ok = [(d, r.metrics["rebound_ratio"]) for d, r in zip(ds, rs) if "rebound_ratio" in r.metrics]
        aim = max(band.center, 1e-3)
        kept = start_in_band(values["damping_rate_per_s"], ds, rs, "rebound_ratio", band)
        guess = None if kept else fit_log([d for d, _ in ok], [max(rb, 1e-3) for _, rb in ok], aim, log_x=False)
        if guess is not None:
            values["damping_rate_per_s"] = min(max(guess, f.low), f.high)
        calls = screen_rollouts(physical, pos, vol, mats, sim, rs, SPECIMEN_SCREEN_SCHEDULE)
        summary["drop"] = {"damping_rate_per_s": ds, "rebound_ratio": [r.metrics.get("rebound_ratio") for r in rs],
                           "sim_calls": calls, "kept_start": kept}
        summary["sim_calls"] += calls
    summary["initial"] = dict(values)
    return values, summary


__all__ = ["SCREEN_KEEP_MARGIN", "SCREEN_SCHEDULE", "SPECIMEN_SCREEN_SCHEDULE", "TASK_VERSION", "fit_log", "l2_probe",
           "probe_parameters", "screen", "screen_dampings", "screen_moduli", "screen_rollouts", "screen_task",
           "specimen_arrays", "start_in_band"]
