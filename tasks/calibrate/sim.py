"""The video's drop in the engine: the asset at the video's size, falling from the video's drop height onto the floor.

The fall and the rise are closed form under the material's damping (tasks.realworld.physics, as `bench realworld`
does a rule's drop); the impact between them is the engine's impact probe (tasks.realworld.impact, the probe that
calibrates L2's viscosity), so a 1 m drop costs the milliseconds of contact. Its metrics are the video's, defined
the same way: the rebound ratio (rise / drop) and the impact strain as a camera sees it: the compression of the
silhouette's second-moment height 4 sigma_z (the particles drawn from the side as anti-aliased discs of half the
spacing, each pixel weighted by its coverage, as the tracker weighs its pixels) below its height at touchdown, as the half sine fitted to the samples
(tasks.calibrate.metrics.impact_amplitude).
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.calibrate.metrics import impact_amplitude
from tasks.calibrate.track import moment_height
from tasks.probes.rollout import DeformableBody, dx_of
from tasks.realworld.impact import impact
from tasks.realworld.physics import damped_impact_speed_m_per_s, damped_rise_height_m

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


__all__ = ["drop_impact", "longest_extent_m", "scaled_body", "silhouette_height"]
