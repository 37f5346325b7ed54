"""What the rigid (pybullet) probe modules share: their inputs from the asset and the candidate's physical model, and
running one measurement with its recording (the rigid motion of a particle subsample)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from cache import cache_relative, content_key
from contracts.probes import ProbeResult, ProbeSpec
from contracts.stage import L1Parameters
from tasks.probes import rigid
from tasks.probes.probe import ProbeContext, cache_recording_path
from tasks.record import ProbeRecording

RECORD_PARTICLES_MAX = 4000

Measure = Callable[[rigid.RigidBodySpec, dict[str, float], rigid.Trace], dict[str, float]]


def proxy_hulls(asset: Any) -> list[np.ndarray]:
    """Convex parts of the collision proxy as vertex arrays [m] (asset frame)."""
    return [np.asarray(p.vertices, dtype=np.float64) for p in asset.proxy_parts]


def record_particles(asset: Any) -> np.ndarray:
    """A deterministic subsample of the rest particles [m] to show the rigid motion in recordings."""
    stride = max(1, int(np.ceil(len(asset.particles_m) / RECORD_PARTICLES_MAX)))
    return np.asarray(asset.particles_m[::stride], dtype=np.float32)


def l1_parameters(ctx: ProbeContext) -> L1Parameters:
    """The stage's probe settings, typed."""
    return L1Parameters.of(ctx.contract)


def body_inputs(ctx: ProbeContext) -> dict[str, Any]:
    """The inputs every rigid probe takes: the proxy, the shown particles, the candidate's mass, centre of mass and
    ground friction."""
    phys = ctx.physical
    return {"hulls": proxy_hulls(ctx.asset), "particles_m": record_particles(ctx.asset), "mass_kg": phys.mass_kg,
            "center_of_mass_m": phys.center_of_mass_m, "friction": phys.ground_friction}


def quat_matrix(q: tuple[float, float, float, float]) -> np.ndarray:
    """Rotation matrix of an xyzw quaternion."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ], dtype=np.float32)


def write_recording(name: str, key: str, particles_m: np.ndarray, com_m: np.ndarray, trace: rigid.Trace,
                    metrics: dict[str, float]) -> str:
    """Rigid motion of the particles over the probe, into the cache's recordings folder; returns the path."""
    path = cache_recording_path("L1", name, key)
    if path.exists():
        return cache_relative(path)
    rest = particles_m - com_m[None, :].astype(np.float32)
    with ProbeRecording(path, recording_id=f"L1-{name}-{key[:16]}") as rec:
        for frame, (t, pos, quat) in enumerate(trace):
            rec.set_time(frame, t)
            rot = quat_matrix(quat)
            rec.particles(rest @ rot.T + np.asarray(pos, np.float32))
            rec.scalar("com_height_m", pos[2])
        rec.log(f"L1 {name} probe: " + ", ".join(f"{k}={v:.4g}" for k, v in sorted(metrics.items())))
    return cache_relative(path)


def run_rigid(name: str, kind: str, measure: Measure, hulls: list[np.ndarray], particles_m: np.ndarray,
              mass_kg: float, center_of_mass_m: tuple[float, float, float], friction: float,
              params: dict[str, float], sim_calls: int = 1) -> ProbeResult:
    """Run one rigid measurement, record it, return its result (spec kind `kind`)."""
    body = rigid.RigidBodySpec(hulls, mass_kg, np.asarray(center_of_mass_m), friction)
    trace: rigid.Trace = []
    t0 = time.perf_counter()
    metrics = measure(body, params, trace)
    wall = time.perf_counter() - t0
    key = content_key("l1-recording", name, hulls, mass_kg, center_of_mass_m, friction, params)
    rrd = write_recording(name, key, particles_m, np.asarray(center_of_mass_m), trace, metrics)
    return ProbeResult(spec=ProbeSpec(kind=kind, params=params), metrics=metrics, sim_calls=sim_calls,
                       wall_time_s=wall, recording=rrd)


__all__ = ["body_inputs", "l1_parameters", "proxy_hulls", "quat_matrix", "record_particles", "run_rigid",
           "write_recording"]
