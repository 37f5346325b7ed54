"""The video's drop in the engine: the asset at the video's size, falling from the video's drop height onto the floor.

The fall and the rise are closed form under the material's damping (tasks.realworld.physics, as `bench realworld`
does a rule's drop); the impact between them is the engine's impact probe (tasks.realworld.impact, the probe that
calibrates L2's viscosity), so a 1 m drop costs the milliseconds of contact. Its metrics are the video's, defined
the same way: the rebound ratio (rise / drop) and the impact strain as a camera sees it: the compression of the
silhouette's second-moment height 4 sigma_z (the particles drawn from the side as anti-aliased discs of half the
spacing, each pixel weighted by its coverage, as the tracker weighs its pixels) below its height at touchdown, as the half sine fitted to the samples
(tasks.calibrate.metrics.impact_amplitude).

The settle time is the bounces that follow, one after another until the rise is under what the video can see (its
settle tolerance): each impact's restitution is the engine's at that impact speed (the impact probe at the first
impact's speed and at slower ones down to the last visible bounce's, interpolated in log speed between them), the
flights between closed form under the material's damping, the whole sampled at the video's frame times and read by
the video's own settle rule (tasks.calibrate.metrics.settle_time).
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.calibrate.metrics import impact_amplitude, settle_time
from tasks.calibrate.track import moment_height
from tasks.probes.rollout import DeformableBody, dx_of
from tasks.realworld.impact import impact
from tasks.realworld.physics import G_M_PER_S2, damped_impact_speed_m_per_s, damped_rise_height_m

SILHOUETTE_PX = 160.0  # the silhouette is drawn this many pixels tall at touchdown
SHIFT = 4


def longest_extent_m(positions_m: np.ndarray, spacing_m: float) -> float:
    """The particles' longest axis-aligned extent, each particle a cube of the spacing [m]."""
    return float(np.ptp(positions_m, axis=0).max() + spacing_m)


def scaled_body(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, size_m: float
                ) -> tuple[np.ndarray, np.ndarray, PhysicalModel]:
    """The asset scaled about its base centre so that its longest extent is `size_m` (same density: the mass scales
    with the volume)."""
    s = size_m / longest_extent_m(positions_m, physical.particle_spacing_m)
    base = np.array([positions_m[:, 0].mean(), positions_m[:, 1].mean(), 0.0])
    pos = (np.asarray(positions_m, np.float64) - base) * s
    vol = np.asarray(volumes_m3, np.float64) * s ** 3
    phys = physical.model_copy(update={
        "volume_m3": physical.volume_m3 * s ** 3, "mass_kg": physical.mass_kg * s ** 3,
        "particle_spacing_m": physical.particle_spacing_m * s,
        "center_of_mass_m": tuple(float(c) * s for c in physical.center_of_mass_m),
        "extents_m": tuple(float(e) * s for e in physical.extents_m)})
    return pos, vol, phys


def silhouette_height(x_m: np.ndarray, spacing_m: float, px_per_m: float) -> float:
    """4 sigma of the rows of the side view's silhouette (x right, z up; discs of half the spacing; coverage) [m]."""
    lo = x_m[:, [0, 2]].min(axis=0) - spacing_m
    hi = x_m[:, [0, 2]].max(axis=0) + spacing_m
    w, h = (np.ceil((hi - lo) * px_per_m)).astype(int) + 2
    mask = np.zeros((h, w), np.uint8)
    k = 1 << SHIFT
    r = max(1, int(round(0.5 * spacing_m * px_per_m * k)))
    xy = (x_m[:, [0, 2]] - lo) * px_per_m
    xy[:, 1] = h - xy[:, 1]
    for px, py in np.rint(xy * k).astype(int).tolist():
        cv2.circle(mask, (px, py), r, 255, -1, cv2.LINE_AA, SHIFT)
    return moment_height(mask.astype(np.float64) / 255.0)[1] / px_per_m


def drop_impact(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                drop_height_m: float, sim: SimConfig) -> dict[str, float]:
    """The drop from `drop_height_m` (the bottom's fall): rebound_ratio, impact_strain (as the video's), the
    impact's restitution, contact time, speeds and health (finite)."""
    d = material.damping_rate_per_s
    v_in = damped_impact_speed_m_per_s(drop_height_m, d)
    spacing = physical.particle_spacing_m
    ppm = SILHOUETTE_PX / longest_extent_m(positions_m, spacing)
    heights: list[float] = []
    bottoms: list[float] = []
    times: list[float] = []

    def observe(t: float, state: dict[str, np.ndarray]) -> None:
        times.append(t)
        heights.append(silhouette_height(state["x"], spacing, ppm))
        bottoms.append(float(state["x"][:, 2].min()))

    raw = impact(positions_m, volumes_m3, physical, material, v_in, sim, observe=observe)
    e = raw.get("restitution", math.nan)
    ok = raw.get("finite", 0.0) == 1.0 and math.isfinite(e) and len(heights) > 1
    out = {k: float(v) for k, v in raw.items() if isinstance(v, float) and math.isfinite(v)}
    out.update({"drop_height_m": drop_height_m, "speed_in_m_per_s": v_in, "finite": 1.0 if ok else 0.0})
    if ok:
        h, t = np.array(heights), np.array(times)
        out["impact_strain"] = max(0.0, impact_amplitude(t, 1.0 - h / h[0]))
        out["impact_strain_max"] = float(max(0.0, 1.0 - h.min() / h[0]))
        # the engine's ground acts across a contact layer 1.5 dx deep: the bottom goes on down into it for `sink` after
        # the contact starts; the video's heights are measured from that lowest bottom (its floor line), so the fall
        # and the rise here are too
        body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
        contact_z = sim.ground_height_m + 1.5 * dx_of(body, sim)
        sink = max(0.0, contact_z - min(bottoms))
        rise = damped_rise_height_m(e * v_in, d)
        out["contact_sink_m"] = sink
        out["rebound_ratio"] = (rise + sink) / (drop_height_m + sink)
    return out


def flight_height_m(v0: float, damping: float, tau: np.ndarray) -> np.ndarray:
    """Height above the launch point of a body thrown up at v0 under gravity and the engine's damping, tau after."""
    g, d = G_M_PER_S2, damping
    if d * max(v0, 1.0) / g < 1e-6:
        return v0 * tau - 0.5 * g * tau * tau
    return (v0 + g / d) * (1.0 - np.exp(-d * tau)) / d - g * tau / d


def flight_time_s(v0: float, damping: float) -> float:
    """How long a body thrown up at v0 takes to come back down to its launch height (damped) [s]."""
    lo, hi = 0.0, 2.0 * v0 / G_M_PER_S2 + 1e-9
    if flight_height_m(v0, damping, np.array([hi]))[0] > 0:  # damping never lengthens it; guard anyway
        hi *= 2.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if flight_height_m(v0, damping, np.array([mid]))[0] > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def landing_speed_m_per_s(v0: float, damping: float, duration_s: float) -> float:
    """Speed down at the end of a damped flight launched up at v0 [m/s]."""
    g, d = G_M_PER_S2, damping
    if d < 1e-9:
        return abs(v0 - g * duration_s)
    return abs((v0 + g / d) * np.exp(-d * duration_s) - g / d)


def fall_time_s(drop_height_m: float, damping: float) -> float:
    """How long the damped fall from rest through `drop_height_m` takes [s]."""
    g, d = G_M_PER_S2, damping
    lo, hi = 0.0, 10.0 * np.sqrt(2.0 * drop_height_m / g) + 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        fallen = 0.5 * g * mid * mid if d < 1e-9 else g / d * mid - g / d ** 2 * (1.0 - np.exp(-d * mid))
        lo, hi = (mid, hi) if fallen < drop_height_m else (lo, mid)
    return 0.5 * (lo + hi)


def bounce_settle(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                  drop_height_m: float, sim: SimConfig, tolerance_m: float, frame_times_s: np.ndarray | None = None,
                  release_t_s: float = 0.0, tail_frames: int = 5, speeds: int = 4) -> dict[str, float]:
    """The bounces after a drop from `drop_height_m` until a rise is under `tolerance_m` (see the module docstring):
    settle_time_s (the end of the last visible bounce, continuous time from the release), bounces (visible ones),
    the restitutions the engine gave at `speeds` impact speeds (restitution_at_<speed>), and, given the video's frame
    times, settle_time_frames_s: the same bounces sampled at those frames and read by the video's settle rule."""
    d = material.damping_rate_per_s
    v1 = damped_impact_speed_m_per_s(drop_height_m, d)
    v_min = max(np.sqrt(2.0 * G_M_PER_S2 * tolerance_m), 1e-3)
    probe = np.geomspace(v1, min(v1, v_min), max(2, speeds)) if v1 > v_min else np.array([v1])
    rest: list[float] = []
    out: dict[str, float] = {}
    for v in probe:
        e = impact(positions_m, volumes_m3, physical, material, float(v), sim).get("restitution", math.nan)
        rest.append(float(e) if math.isfinite(e) else 0.0)
        out[f"restitution_at_{v:.3g}_m_per_s"] = rest[-1]
    logv, es = np.log(probe[::-1]), np.array(rest[::-1])

    def e_of(v: float) -> float:
        return float(np.interp(np.log(max(v, 1e-6)), logv, es)) if len(probe) > 1 else rest[0]

    t = fall_time_s(drop_height_m, d)
    flights: list[tuple[float, float, float]] = []  # (take-off time, speed up, duration)
    v_in = v1
    while len(flights) < 200:
        v_out = e_of(v_in) * v_in
        if v_out <= 0 or damped_rise_height_m(v_out, d) < tolerance_m:
            break
        dur = flight_time_s(v_out, d)
        flights.append((t, v_out, dur))
        t += dur
        v_in = landing_speed_m_per_s(v_out, d, dur)
    out.update({"settle_time_s": t, "bounces": float(len(flights)), "fall_time_s": fall_time_s(drop_height_m, d)})
    if frame_times_s is not None and len(frame_times_s) >= 3:
        tau = np.asarray(frame_times_s, np.float64) - release_t_s
        z = np.zeros(len(tau))
        fall = tau < out["fall_time_s"]
        z[fall & (tau < 0)] = drop_height_m
        tf = np.clip(tau[fall & (tau >= 0)], 0.0, None)
        z[fall & (tau >= 0)] = drop_height_m - (0.5 * G_M_PER_S2 * tf * tf if d < 1e-9 else
                                                G_M_PER_S2 / d * tf - G_M_PER_S2 / d ** 2 * (1.0 - np.exp(-d * tf)))
        for t0, v0, dur in flights:
            inside = (tau >= t0) & (tau < t0 + dur)
            z[inside] = flight_height_m(v0, d, tau[inside] - t0)
        # image y runs down: the centroid's y is minus its height (in metres; the tolerance is in metres too)
        st = settle_time(tau, -np.maximum(z, 0.0), 0.0, tolerance_m, tail_frames)
        if st is not None:
            out["settle_time_frames_s"] = st
    return out


__all__ = ["bounce_settle", "drop_impact", "fall_time_s", "flight_height_m", "flight_time_s", "longest_extent_m",
           "scaled_body", "silhouette_height"]
