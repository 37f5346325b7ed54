"""L2's drop and compression schedules on a tet body in any simulator (MuJoCo, Drake): what is sampled when.

Same settings as L2: the drop releases the body with its lowest node height_fraction x H above the ground and samples
every sixth of a fundamental period (<= 2.5 ms) for at least 0.6 s, until the body has been quiet for 0.1 s (2 s at
most); the compression settles the body (max(0.1 s, 8 T)), lowers a frictionless plate at a constant speed over
max(0.2 s, 20 T) until e = 1 - h / h0 reaches the strain, holds (max(0.1 s, 6 T); force averaged over its last 70 %),
withdraws it in 0.1 s and watches the recovery (max(0.2 s, 10 T); heights averaged over its last 40 %). Heights are
L2's, taken along the body's own vertical (unrotated): a body that turns as a whole keeps its bottom layer.
A simulator supplies a ProbeSim (its state, stepping, ground contact, plate force and plate motion); the plate's
placement comes from plate_setup so that every simulator starts from the same geometry.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from tasks.export.crosscheck import TetKinematics, compression_metrics, drop_metrics, sample_interval_s
from tasks.export.mujoco_scene import fundamental_period_s

G = 9.81


@dataclass
class TetBody:
    """The exported body: tet-mesh nodes (asset frame, resting on z = 0), tets, density and L2's layer spacing."""

    nodes_m: np.ndarray
    tets: np.ndarray
    density_kg_per_m3: float
    spacing_m: float
    reference_young_pa: float  # the validated E: it sets the probes' time scales (as in L2), not the simulation

    @property
    def height_m(self) -> float:
        return float(np.ptp(self.nodes_m[:, 2]))

    @property
    def period_s(self) -> float:
        return fundamental_period_s(self.height_m, self.reference_young_pa, self.density_kg_per_m3)


class ProbeSim(Protocol):
    """One simulator's model of the body (and, for the compression, the plate)."""

    masses: np.ndarray  # node masses [kg]
    timestep_s: float

    @property
    def time_s(self) -> float: ...

    def x(self) -> np.ndarray: ...  # node positions [m] (N, 3)

    def v(self) -> np.ndarray: ...  # node velocities [m/s] (N, 3)

    def advance(self, duration_s: float) -> None: ...  # SimulationError on a non-finite state

    def touching_ground(self) -> bool: ...

    def plate_force_n(self) -> float: ...  # the body's push on the plate, along +z [N]

    def move_plate(self, vz_m_per_s: float, duration_s: float) -> None: ...  # at this speed, one step at a time


@dataclass(frozen=True)
class PlateSetup:
    """Where the compression's frictionless plate starts and what the heights are read on."""

    half_m: tuple[float, float, float]
    centre_m: tuple[float, float, float]  # the plate's centre at the start, over the body lifted by -min z
    gap_m: float
    bottom: np.ndarray    # the bottom layer's nodes (within 0.75 spacing of the lowest)
    measured: np.ndarray  # the nodes whose COM gives the height (below the top grid cell)


def unrotated(x: np.ndarray, x0: np.ndarray, masses: np.ndarray) -> np.ndarray:
    """x turned back about its centre of mass by its best-fit rotation from the rest nodes x0 (mass-weighted Kabsch):
    L2's heights along the body's own vertical, whatever the body does as a whole (a ball spun by the plate's release
    rolls on the frictionless table and would carry its bottom layer up its side)."""
    w = np.asarray(masses, np.float64)[:, None]
    c = (x * w).sum(axis=0) / w.sum()
    c0 = (x0 * w).sum(axis=0) / w.sum()
    u, _, vt = np.linalg.svd(((x0 - c0) * w).T @ (x - c))
    r = vt.T @ np.diag([1.0, 1.0, float(np.sign(np.linalg.det(vt.T @ u.T)))]) @ u.T  # x - c ~ R (x0 - c0)
    return (x - c) @ r + c


def drop_lift_m(body: TetBody, height_fraction: float) -> float:
    """How far to raise the resting body so that its lowest node is height_fraction x H above the ground."""
    return height_fraction * body.height_m - float(body.nodes_m[:, 2].min())


def run_drop(sim: ProbeSim, body: TetBody, height_fraction: float, duration_s: float = 2.0) -> dict[str, float]:
    """L2's drop probe on a sim built with the body lifted by drop_lift_m: rebound_ratio, max_impact_strain, ..."""
    t_wall = time.perf_counter()
    h = height_fraction * body.height_m
    kin = TetKinematics(body.nodes_m, body.tets, sim.masses)
    M = float(sim.masses.sum())
    dt_s = max(sample_interval_s(body.period_s, longest_s=2.5e-3), sim.timestep_s)
    quiet = 1e-3 * M * G * h
    t, z, vz, ke, fg, s95 = [], [], [], [], [], []
    calm = 0
    while sim.time_s < duration_s - 1e-9:
        sim.advance(dt_s)
        x, v = sim.x(), sim.v()
        t.append(float(sim.time_s))
        z.append(float(kin.com(x)[2]))
        vz.append(float((v[:, 2] * kin.m).sum() / M))
        ke.append(kin.kinetic_energy(v))
        fg.append(1.0 if sim.touching_ground() else 0.0)  # L2 uses the ground force only as contact / no contact
        s95.append(kin.strain_p95(x))
        calm = calm + 1 if (ke[-1] < quiet and fg[-1] > 0) else 0
        if t[-1] >= 0.6 and calm * dt_s >= 0.1:
            break
    out = drop_metrics(np.array(t), np.array(z), np.array(vz), np.array(ke), np.array(fg), np.array(s95), M, h, dt_s)
    out["sim_time_s"] = float(sim.time_s)
    out["wall_time_s"] = time.perf_counter() - t_wall
    return out


def plate_setup(body: TetBody) -> PlateSetup:
    """L2's plate: a grid cell (two spacings) thick at least 1 cm, overhanging the body, 1.5 cells above its top."""
    x0, s = body.nodes_m, body.spacing_m
    dx = 2.0 * s  # L2's grid cell: its plate gap and contact layer
    lo, hi = x0.min(axis=0), x0.max(axis=0)
    bottom = x0[:, 2] < lo[2] + 0.75 * s
    measured = x0[:, 2] < hi[2] - dx
    half_t = max(dx, 0.01)
    half = (0.5 * (hi[0] - lo[0]) + s + 2 * dx, 0.5 * (hi[1] - lo[1]) + s + 2 * dx, half_t)
    gap = 1.5 * dx
    cxy = 0.5 * (lo[:2] + hi[:2])
    # hi from the nodes as given (min z slightly below 0): the published MuJoCo figures were taken with this height
    centre = (float(cxy[0]), float(cxy[1]), float(hi[2] + gap + half_t))
    return PlateSetup(half, centre, gap, bottom, measured)


def run_compress(sim: ProbeSim, body: TetBody, setup: PlateSetup, strain: float, area_m2: float) -> dict[str, float]:
    """L2's compression probe on a sim of the body lifted by -min z (resting on z = 0) with the plate at
    setup.centre_m: effective_modulus_pa,
    recovery_ratio, compression_strain/force."""
    t_wall = time.perf_counter()
    x0 = body.nodes_m
    H = body.height_m
    bottom, measured = setup.bottom, setup.measured
    kin = TetKinematics(x0, body.tets, sim.masses)
    z_b0 = float(x0[bottom, 2].mean())
    if measured.sum() < 8 or kin.com(x0, measured)[2] - z_b0 < 0.3 * (kin.com(x0)[2] - z_b0):
        measured = np.ones(len(x0), bool)
    T = body.period_s
    dt_s = max(sample_interval_s(T), sim.timestep_s)
    t_settle, t_load, t_hold = max(0.1, 8 * T), max(0.2, 20 * T), max(0.1, 6 * T)
    t_release, t_recover = 0.1, max(0.2, 10 * T)
    gap = setup.gap_m
    travel_max = gap + 2.0 * strain * H
    v_load = (gap + strain * H) / t_load

    def height() -> float:
        x = unrotated(sim.x(), x0, sim.masses)
        return 2.0 * float(kin.com(x, measured)[2] - x[bottom, 2].mean())

    hs = []
    while sim.time_s < t_settle - 1e-9:
        sim.advance(dt_s)
        if sim.time_s > 0.5 * t_settle:
            hs.append(height())
    h0 = float(np.mean(hs)) if hs else H
    t0 = sim.time_s
    e = 0.0
    while sim.time_s - t0 < 2.0 * t_load:
        sim.move_plate(-v_load, dt_s)
        e = 1.0 - height() / h0
        if e >= strain or v_load * (sim.time_s - t0) >= travel_max:
            break
    forces, h_hold = [], []
    t1 = sim.time_s
    while sim.time_s - t1 < t_hold - 1e-9:
        sim.advance(dt_s)
        if sim.time_s - t1 > 0.3 * t_hold:
            forces.append(sim.plate_force_n())
            h_hold.append(height())
    sim.move_plate((travel_max + gap) / t_release, t_release)
    t2 = sim.time_s
    h_rec = []
    while sim.time_s - t2 < t_recover - 1e-9:
        sim.advance(dt_s)
        if sim.time_s - t2 > 0.6 * t_recover:
            h_rec.append(height())
    return {**compression_metrics(forces, h0, h_hold, h_rec, area_m2),
            "sim_time_s": float(sim.time_s), "wall_time_s": time.perf_counter() - t_wall}


__all__ = ["PlateSetup", "ProbeSim", "TetBody", "drop_lift_m", "plate_setup", "run_compress", "run_drop", "unrotated"]
