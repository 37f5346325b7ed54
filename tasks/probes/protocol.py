"""The paper's drop protocol: a 5 s gravity drop from a quarter of the object's height, sampled at 30 fps.

Returns the particle states per frame (positions and deformation gradients, to drive the Gaussians) and automated
physical-plausibility metrics. Plain engine code (no Prefect).
"""

from __future__ import annotations

import numpy as np

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import SceneSpec, Simulator, build_model
from tasks.probes.rollout import DeformableBody, dx_of

PROTOCOL_DURATION_S = 5.0
PROTOCOL_FPS = 30.0
PROTOCOL_HEIGHT_FRACTION = 0.25


def _best_rotation(rest: np.ndarray, now: np.ndarray) -> np.ndarray:
    """The rotation R of the best rigid motion (Kabsch) mapping rest onto now: (rest - mean) @ R ~ now - mean."""
    a = rest - rest.mean(axis=0)
    b = now - now.mean(axis=0)
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(u @ vt))
    return u @ np.diag([1.0, 1.0, d]) @ vt


def _rigid_residual(rest: np.ndarray, now: np.ndarray) -> np.ndarray:
    """Displacements left after the best rigid motion (Kabsch) that maps rest onto now [m]."""
    return (now - now.mean(axis=0)) - (rest - rest.mean(axis=0)) @ _best_rotation(rest, now)


def plausibility_metrics(rest_m: np.ndarray, volumes_m3: np.ndarray, x_frames: np.ndarray, F_frames: np.ndarray,
                         healthy: bool) -> dict[str, float]:
    """Shape retention, volume preservation, no collapse, no explosion, over a rollout's frames.

    shape_retention      1 - RMS(non-rigid displacement at the end) / H: 1 = the rest shape came back [-]
    volume_ratio_end     sum(J V) / sum(V) in the last frame [-]
    height_ratio_end     vertical extent in the last frame / at rest [-]
    body_height_ratio_end  extent along the body's own vertical axis (the rest z axis carried by the best rigid
                         rotation) in the last frame / at rest [-]: a tall object that tips over keeps it, one that
                         squashes loses it
    tilt_deg_end         angle between the body's own vertical axis and the world's in the last frame [deg]
    max_extent_growth    largest bounding-box extent over all frames / the largest rest extent [-]
    collapsed            1 if body_height_ratio_end < 0.5 [-] (a plush bunny lying on its side after the drop has not
                         collapsed);  exploded  1 if max_extent_growth > 2 or not finite [-]
    plausible            1 if healthy, not collapsed, not exploded, |volume_ratio_end - 1| <= 0.1 and
                         shape_retention >= 0.8 [-]
    """
    rest = np.asarray(rest_m, np.float64)
    height = float(np.ptp(rest[:, 2]))
    extent0 = float(np.ptp(rest, axis=0).max())
    last = np.asarray(x_frames[-1], np.float64)
    finite = bool(np.all(np.isfinite(x_frames)) and np.all(np.isfinite(F_frames)))
    if not finite:
        return {"shape_retention": 0.0, "volume_ratio_end": float("nan"), "height_ratio_end": float("nan"),
                "body_height_ratio_end": float("nan"), "tilt_deg_end": float("nan"),
                "max_extent_growth": float("inf"), "collapsed": 0.0, "exploded": 1.0, "plausible": 0.0}
    residual = _rigid_residual(rest, last)
    up = _best_rotation(rest, last)[2]  # the rest z axis, carried into the last frame
    body_height_ratio = float(np.ptp(last @ up)) / height
    tilt = float(np.degrees(np.arccos(np.clip(up[2], -1.0, 1.0))))
    retention = 1.0 - float(np.sqrt((residual ** 2).sum(axis=1).mean())) / height
    det = np.linalg.det(np.asarray(F_frames[-1], np.float64))
    volume_ratio = float((det * volumes_m3).sum() / volumes_m3.sum())
    height_ratio = float(np.ptp(last[:, 2])) / height
    growth = max(float(np.ptp(x, axis=0).max()) for x in x_frames) / extent0
    collapsed, exploded = body_height_ratio < 0.5, growth > 2.0
    plausible = healthy and not collapsed and not exploded and abs(volume_ratio - 1.0) <= 0.1 and retention >= 0.8
    return {"shape_retention": retention, "volume_ratio_end": volume_ratio, "height_ratio_end": height_ratio,
            "body_height_ratio_end": body_height_ratio, "tilt_deg_end": tilt, "max_extent_growth": growth, "collapsed": float(collapsed), "exploded": float(exploded),
            "plausible": float(plausible)}


def drop_protocol(body: DeformableBody, material: Material, sim: SimConfig | None = None,
                  duration_s: float = PROTOCOL_DURATION_S, fps: float = PROTOCOL_FPS,
                  height_fraction: float = PROTOCOL_HEIGHT_FRACTION) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """Drop the body (lowest point h = fraction * H above the ground's contact layer) and sample it at fps.

    Returns arrays {time_s (T,), x_m (T, N, 3) float32, F (T, N, 3, 3) float32, offset_m (3,) the release lift}
    and the plausibility metrics (plus drop_height_m and healthy).
    """
    sim = sim or SimConfig()
    x0 = np.asarray(body.positions_m, np.float64)
    h = height_fraction * body.height_m
    layer = max(0.0, 1.5 * dx_of(body, sim) - (x0[:, 2].min() - sim.ground_height_m))
    lift = np.array([0.0, 0.0, h + layer])
    scene = SceneSpec(x0 + lift, body.volumes_m3, body.density_kg_per_m3, material, ground_friction=body.ground_friction)
    simulator = Simulator(build_model([scene], sim))
    frames = int(round(duration_s * fps))
    times, xs, Fs = [0.0], [], []
    state = simulator.particles(0)
    xs.append(state["x"].astype(np.float32))
    Fs.append(state["F"].astype(np.float32))
    healthy = True
    for k in range(frames):
        report = simulator.advance(1.0 / fps)
        state = simulator.particles(0)
        times.append((k + 1) / fps)
        xs.append(state["x"].astype(np.float32))
        Fs.append(state["F"].astype(np.float32))
        if not report.health.ok:
            healthy = False
            break
    arrays = {"time_s": np.asarray(times), "x_m": np.stack(xs), "F": np.stack(Fs), "offset_m": lift}
    metrics = plausibility_metrics(x0, body.volumes_m3, arrays["x_m"], arrays["F"], healthy)
    metrics.update({"drop_height_m": h, "healthy": float(healthy), "frames": float(len(times))})
    return arrays, metrics
