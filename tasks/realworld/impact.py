"""The impact probe of a rule drop: the object meets the ground at the rule's impact speed (released one contact
layer above it, moving down) and the MPM says how fast its centre of mass leaves; the fall and the rise are closed
form (tasks.realworld.physics), so a 2.5 m drop costs the few milliseconds of contact, not 1.3 s of flight."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.probes.metrics import center_of_mass, compressive_strain
from tasks.probes.rollout import DeformableBody, Rollout, dx_of
from tasks.mpm import SceneSpec

SEPARATED_S = 2e-3  # the ground force stays zero this long, the COM rising: the object has left the ground
LONGEST_S = 0.25  # stop here whatever happened (a dead object never leaves) [s]


def contact_time_s(mass_kg: float, radius_m: float, modulus_pa: float, poisson_ratio: float,
                   speed_m_per_s: float) -> float:
    """Hertz contact time of an elastic sphere on a rigid plane, 2.87 (m^2 / (R E*^2 v))^(1/5) [s]."""
    e_star = modulus_pa / (1.0 - poisson_ratio ** 2)
    return 2.87 * (mass_kg ** 2 / (radius_m * e_star ** 2 * speed_m_per_s)) ** 0.2


def sample_interval_s(body: DeformableBody, material: Material, speed_m_per_s: float) -> float:
    """A fortieth of the expected contact time, within [2e-5 s, 5e-4 s]."""
    radius = 0.5 * float(np.min(body.extents_m))
    tc = contact_time_s(body.mass_kg, radius, material.wall_modulus_pa, material.poisson_ratio, speed_m_per_s)
    return float(min(5e-4, max(2e-5, tc / 40.0)))


def impact(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
           speed_m_per_s: float, sim: SimConfig,
           observe: Callable[[float, dict[str, np.ndarray]], None] | None = None) -> dict[str, float]:
    """One impact at `speed_m_per_s`, straight down onto the ground: the COM speed in and out, the restitution (out /
    in), the contact time, the largest compressive strain (95th percentile over the particles) and the engine's
    health (finite = 1 when every state stayed finite and no check stopped the run). `observe(t, state)` sees every
    sample's particle state (tasks.calibrate: the silhouette a camera would see)."""
    body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
    dx = dx_of(body, sim)
    x0 = body.positions_m
    lift = max(0.0, 1.5 * dx - (x0[:, 2].min() - sim.ground_height_m)) + 0.5 * dx  # half a cell above the contact
    vel = np.tile(np.array([0.0, 0.0, -speed_m_per_s]), (len(x0), 1))
    scene = SceneSpec(x0 + np.array([0.0, 0.0, lift]), body.volumes_m3, body.density_kg_per_m3, material,
                      velocities_m_per_s=vel, ground_friction=body.ground_friction)
    step = sample_interval_s(body, material, speed_m_per_s)
    run = Rollout([scene], sim, None, "impact", int(0.05 / step))
    m = run.masses[0]
    t, z, vz, force, strain = [], [], [], [], []
    while run.ok and run.time_s < LONGEST_S:
        rep, st = run.advance(step)
        d = st[0]
        t.append(run.time_s)
        if observe is not None:
            observe(run.time_s, d)
        z.append(float(center_of_mass(d["x"], m)[2]))
        vz.append(float((d["v"][:, 2].astype(np.float64) * m).sum() / m.sum()))
        force.append(abs(float(rep.ground_force_n[0][2])))
        strain.append(float(np.percentile(compressive_strain(d["F"]), 95)))
        if separated(np.array(t), np.array(vz), np.array(force), step):
            break
    out = {"sample_interval_s": step, "sim_time_s": run.time_s, "wall_s": run.wall_s, "particles": float(len(x0)),
           "finite": 1.0 if run.ok and np.all(np.isfinite(vz)) else 0.0}
    run.close([f"impact at {speed_m_per_s:.3f} m/s"])
    out.update(impact_metrics(np.array(t), np.array(z), np.array(vz), np.array(force), np.array(strain)))
    return out


def separated(t: np.ndarray, vz: np.ndarray, force: np.ndarray, step: float) -> bool:
    """The object touched the ground, and for SEPARATED_S since its last contact the force stayed zero while its COM
    rose."""
    touched = np.flatnonzero(force > 1e-9)
    if len(touched) == 0:
        return False
    last = touched[-1]
    return bool(t[-1] - t[last] >= SEPARATED_S - 0.5 * step and vz[-1] > 0.0)


def impact_metrics(t: np.ndarray, z: np.ndarray, vz: np.ndarray, force: np.ndarray,
                   strain: np.ndarray) -> dict[str, float]:
    """Speeds, restitution, contact time and peak strain from the sampled series (see impact()). The speed out is the
    one the COM had when it passed its height at first contact again (v^2 + 2 g (z - z_contact)), so the rise above
    the floor is speed_out^2 / 2g in vacuum; 0 when the object never left the ground."""
    touched = np.flatnonzero(force > 1e-9)
    if len(t) == 0 or len(touched) == 0:
        return {"restitution": float("nan")}
    first, last = int(touched[0]), int(touched[-1])
    speed_in = -float(vz[max(0, first - 1)])
    gone = not (last == len(t) - 1 or vz[-1] <= 0.0)
    z_contact = float(z[max(0, first - 1)])
    speed_out = math.sqrt(max(0.0, vz[-1] ** 2 + 2.0 * 9.81 * (z[-1] - z_contact))) if gone else 0.0
    return {"speed_in_m_per_s": speed_in, "speed_out_m_per_s": speed_out,
            "restitution": speed_out / speed_in if speed_in > 0 else float("nan"),
            "contact_time_s": float(t[last] - t[max(0, first - 1)]), "left_ground": 1.0 if gone else 0.0,
            "max_impact_strain": float(strain[first:last + 1].max())}
