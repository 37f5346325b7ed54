"""L2's drop and compression probes in MuJoCo on the exported flex body (tasks.export.crosscheck's definitions).

Same settings as L2: the drop releases the body with its lowest node height_fraction x H above the table and samples
every sixth of a fundamental period (<= 2.5 ms) for at least 0.6 s, until the body has been quiet for 0.1 s (2 s at
most); the compression settles the body (max(0.1 s, 8 T)), lowers a frictionless mocap plate at a constant speed over
max(0.2 s, 20 T) until e = 1 - h / h0 reaches the strain, holds (max(0.1 s, 6 T); force averaged over its last 70 %),
withdraws it in 0.1 s and watches the recovery (max(0.2 s, 10 T); heights averaged over its last 40 %). Heights are
L2's, taken along the body's own vertical (unrotated): a body that turns as a whole keeps its bottom layer.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from contracts.errors import SimulationError
from tasks.export.crosscheck import TetKinematics, compression_metrics, drop_metrics, sample_interval_s
from tasks.export.mujoco_scene import FLEX_NAME, PLATE_NAME, TABLE_NAME, FlexParams, fundamental_period_s, scene_xml

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


MUJOCO_WARNINGS: deque[str] = deque(maxlen=20)  # MuJoCo's last warnings (not printed, nor logged to a file)


def quiet_mujoco_warnings() -> None:
    """Route MuJoCo's warnings to MUJOCO_WARNINGS instead of stderr and MUJOCO_LOG.TXT in the working directory (the
    flex solver warns of an under-converged M+K solve on sliver tets; the probes check the state for NaN instead)."""
    import mujoco

    mujoco.set_mju_user_warning(MUJOCO_WARNINGS.append)


class _Sim:
    """One MuJoCo model of the body with index maps for the flex nodes."""

    def __init__(self, xml: str):
        import mujoco

        quiet_mujoco_warnings()
        self.mj = mujoco
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        m = self.model
        f = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_FLEX, FLEX_NAME)
        adr, num = int(m.flex_vertadr[f]), int(m.flex_vertnum[f])
        self.vbody = np.asarray(m.flex_vertbodyid[adr:adr + num])
        self.masses = np.asarray(m.body_mass[self.vbody], np.float64)
        dof = np.asarray(m.body_dofadr[self.vbody])
        self.dofs = (dof[:, None] + np.arange(3)[None, :]).ravel()
        self.table = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, TABLE_NAME)
        self.plate = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, PLATE_NAME)
        self._f6 = np.zeros(6)

    def x(self) -> np.ndarray:
        return np.array(self.data.xpos[self.vbody], np.float64)

    def v(self) -> np.ndarray:
        return np.array(self.data.qvel[self.dofs], np.float64).reshape(-1, 3)

    def _contacts_of(self, geom: int) -> np.ndarray:
        g = np.asarray(self.data.contact.geom)[: self.data.ncon]
        return np.flatnonzero((g[:, 0] == geom) | (g[:, 1] == geom)) if len(g) else np.zeros(0, int)

    def touching(self, geom: int) -> bool:
        """Whether any contact involves the geom."""
        return len(self._contacts_of(geom)) > 0

    def normal_force(self, geom: int) -> float:
        """Total normal contact force on a geom [N] (frictionless contacts: their constraint force directly)."""
        d = self.data
        idx = self._contacts_of(geom)
        if len(idx) == 0:
            return 0.0
        dim = np.asarray(d.contact.dim)[idx]
        if np.all(dim == 1):
            return float(np.asarray(d.efc_force)[np.asarray(d.contact.efc_address)[idx]].sum())
        total = 0.0
        for i in idx:
            self.mj.mj_contactForce(self.model, d, int(i), self._f6)
            total += float(self._f6[0])
        return total

    def advance(self, duration_s: float) -> None:
        """Step for duration_s; SimulationError on a non-finite state."""
        m, d = self.model, self.data
        n = max(1, int(round(duration_s / m.opt.timestep)))
        self.mj.mj_step(m, d, nstep=n)
        if d.warning[self.mj.mjtWarning.mjWARN_BADQACC].number > 0 or not np.all(np.isfinite(d.qpos)):
            raise SimulationError(f"MuJoCo diverged (non-finite state) at t = {d.time:.4f} s")


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


def _scene(body: TetBody, p: FlexParams, lift_m: float, **kw: object) -> str:
    return scene_xml(body.nodes_m + np.array([0.0, 0.0, lift_m]), body.tets, p, **kw)  # type: ignore[arg-type]


def drop(body: TetBody, p: FlexParams, height_fraction: float, duration_s: float = 2.0) -> dict[str, float]:
    """L2's drop probe in MuJoCo: rebound_ratio, dissipated_energy_fraction, max_impact_strain, settle_time_s, ..."""
    t_wall = time.perf_counter()
    h = height_fraction * body.height_m
    lift = h - float(body.nodes_m[:, 2].min())
    sim = _Sim(_scene(body, p, lift))
    kin = TetKinematics(body.nodes_m, body.tets, sim.masses)
    M = float(sim.masses.sum())
    dt_s = max(sample_interval_s(body.period_s, longest_s=2.5e-3), p.timestep_s)
    quiet = 1e-3 * M * G * h
    t, z, vz, ke, fg, s95 = [], [], [], [], [], []
    calm = 0
    while sim.data.time < duration_s - 1e-9:
        sim.advance(dt_s)
        x, v = sim.x(), sim.v()
        t.append(float(sim.data.time))
        z.append(float(kin.com(x)[2]))
        vz.append(float((v[:, 2] * kin.m).sum() / M))
        ke.append(kin.kinetic_energy(v))
        fg.append(1.0 if sim.touching(sim.table) else 0.0)  # L2 uses the ground force only as contact / no contact
        s95.append(kin.strain_p95(x))
        calm = calm + 1 if (ke[-1] < quiet and fg[-1] > 0) else 0
        if t[-1] >= 0.6 and calm * dt_s >= 0.1:
            break
    out = drop_metrics(np.array(t), np.array(z), np.array(vz), np.array(ke), np.array(fg), np.array(s95), M, h, dt_s)
    out["sim_time_s"] = float(sim.data.time)
    out["wall_time_s"] = time.perf_counter() - t_wall
    return out


def compress(body: TetBody, p: FlexParams, strain: float, area_m2: float) -> dict[str, float]:
    """L2's compression probe in MuJoCo: effective_modulus_pa, recovery_ratio, compression_strain/force."""
    t_wall = time.perf_counter()
    x0, s = body.nodes_m, body.spacing_m
    dx = 2.0 * s  # L2's grid cell: its plate gap and contact layer
    H = body.height_m
    lo, hi = x0.min(axis=0), x0.max(axis=0)
    bottom = x0[:, 2] < lo[2] + 0.75 * s
    measured = x0[:, 2] < hi[2] - dx
    half_t = max(dx, 0.01)
    half = (0.5 * (hi[0] - lo[0]) + s + 2 * dx, 0.5 * (hi[1] - lo[1]) + s + 2 * dx, half_t)
    gap = 1.5 * dx
    z_plate0 = hi[2] + gap + half_t
    cxy = 0.5 * (lo[:2] + hi[:2])
    sim = _Sim(_scene(body, p, -float(lo[2]), frictionless=True, plate_half_m=half,
                      plate_pos_m=(float(cxy[0]), float(cxy[1]), z_plate0)))
    kin = TetKinematics(x0, body.tets, sim.masses)
    z_b0 = float(x0[bottom, 2].mean())
    if measured.sum() < 8 or kin.com(x0, measured)[2] - z_b0 < 0.3 * (kin.com(x0)[2] - z_b0):
        measured = np.ones(len(x0), bool)
    T = body.period_s
    dt_s = max(sample_interval_s(T), p.timestep_s)
    t_settle, t_load, t_hold = max(0.1, 8 * T), max(0.2, 20 * T), max(0.1, 6 * T)
    t_release, t_recover = 0.1, max(0.2, 10 * T)
    travel_max = gap + 2.0 * strain * H
    v_load = (gap + strain * H) / t_load
    d = sim.data

    def height() -> float:
        x = unrotated(sim.x(), x0, sim.masses)
        return 2.0 * float(kin.com(x, measured)[2] - x[bottom, 2].mean())

    def move_plate(v: float, duration: float) -> None:
        n = max(1, int(round(duration / p.timestep_s)))
        for _ in range(n):
            d.mocap_pos[0, 2] += v * p.timestep_s
            sim.advance(p.timestep_s)

    hs = []
    while d.time < t_settle - 1e-9:
        sim.advance(dt_s)
        if d.time > 0.5 * t_settle:
            hs.append(height())
    h0 = float(np.mean(hs)) if hs else H
    t0 = d.time
    e = 0.0
    while d.time - t0 < 2.0 * t_load:
        move_plate(-v_load, dt_s)
        e = 1.0 - height() / h0
        if e >= strain or v_load * (d.time - t0) >= travel_max:
            break
    forces, h_hold = [], []
    t1 = d.time
    while d.time - t1 < t_hold - 1e-9:
        sim.advance(dt_s)
        if d.time - t1 > 0.3 * t_hold:
            forces.append(sim.normal_force(sim.plate))
            h_hold.append(height())
    move_plate((travel_max + gap) / t_release, t_release)
    t2 = d.time
    h_rec = []
    while d.time - t2 < t_recover - 1e-9:
        sim.advance(dt_s)
        if d.time - t2 > 0.6 * t_recover:
            h_rec.append(height())
    return {**compression_metrics(forces, h0, h_hold, h_rec, area_m2),
            "sim_time_s": float(d.time), "wall_time_s": time.perf_counter() - t_wall}


def with_values(p: FlexParams, young_pa: float | None = None, damping_s: float | None = None) -> FlexParams:
    """A copy of p with another Young's modulus and/or damping time."""
    return replace(p, young_pa=p.young_pa if young_pa is None else young_pa,
                   damping_s=p.damping_s if damping_s is None else damping_s)


__all__ = ["TetBody", "compress", "drop", "unrotated", "with_values"]
