"""L2's drop and compression probes in Genesis, run on the exported scene.py (tasks.export.genesis) with its MPM.

Both build the scene with DeformSmith's velocity damping as scene.py adds it (gs.force_fields.Drag on the MPM grid,
PARAMS' damping_rate_per_s unless a calibration overrides it). The particles are Genesis's own (sampled in the
exported surface at DeformSmith's spacing, equal masses).

drop: the body is released with its lowest surface point height_fraction x H above Genesis's grid contact layer (1.5
cells above the ground plane, as L2 does on its own grid) and sampled every Genesis step (2 ms) for at least 0.6 s,
until it has been quiet for 0.1 s (2 s at most). The impact strain is L2's, from Genesis's per-particle deformation
gradients. Genesis reports no ground force, so first contact is the first sample whose centre-of-mass acceleration
exceeds -g / 2 (the ground pushing).

compress: L2's schedule (as tasks.export.mujoco_probes.compress): the body settles on a frictionless ground
(max(0.1 s, 8 T)); a frictionless rigid box plate (a free Genesis rigid body, gravity compensated, given its position
and velocity before every step so that the MPM coupling sees a moving wall) comes down at a constant speed over
max(0.2 s, 20 T) until e = 1 - h / h0 in L2's equivalent heights reaches the strain; it holds (max(0.1 s, 6 T), force
averaged over the last 70 %), withdraws in 0.1 s, and the recovery is watched (max(0.2 s, 10 T), heights averaged over
the last 40 %). Heights are taken along the body's own vertical (unrotated), as MuJoCo's and Drake's. The plate force
is the coupler's reaction on the free plate (its mass x the velocity it gained over the step / dt). A check from
Genesis's particle stresses is recorded beside it (compression_force_from_stress_n, plate_force_from_stress_n): in
equilibrium the body's volume integral of sigma_zz equals -F (z_top - z_bot) - W (z_com - z_bot), and Genesis's own
neo-Hookean Kirchhoff stress tau = mu (F F^T - I) + lambda ln(J) I (genesis/engine/materials/MPM/elastic.py) gives
integral sigma dV = sum_p V0 tau_p, V0 = particle_size^3 (the volume Genesis's p2g uses).
"""

from __future__ import annotations

import importlib.util
import math
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from contracts.errors import InputError, SimulationError
from tasks.export.crosscheck import compression_metrics, drop_metrics
from tasks.export.genesis import GENESIS_INSTALL
from tasks.export.mujoco_scene import fundamental_period_s
from tasks.export.probe_schedule import unrotated
from tasks.probes.metrics import compressive_strain

G = 9.81


def load_scene_module(scene_py: Path) -> ModuleType:
    """Import an exported scene.py (needs genesis-world)."""
    if importlib.util.find_spec("genesis") is None:
        raise InputError(f"crosscheck --sim genesis needs genesis-world: {GENESIS_INSTALL}")
    spec = importlib.util.spec_from_file_location(f"deformsmith_genesis_scene_{abs(hash(str(scene_py)))}", scene_py)
    if spec is None or spec.loader is None:
        raise InputError(f"{scene_py}: not a loadable scene file")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _numpy(t: object) -> np.ndarray:
    return np.asarray(t.detach().cpu().numpy() if hasattr(t, "detach") else t, np.float64)


def lame_pa(young_pa: float, poisson: float) -> tuple[float, float]:
    """(mu, lambda) as Genesis's MPM materials compute them."""
    return young_pa / (2.0 * (1.0 + poisson)), young_pa * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))


def kirchhoff_zz_pa(F: np.ndarray, mu: float, lam: float) -> np.ndarray:
    """tau_zz of Genesis's neo-Hookean Elastic per particle: mu ((F F^T)_zz - 1) + lambda ln J."""
    F = np.asarray(F, np.float64)
    J = np.linalg.det(F)
    return mu * (np.einsum("ij,ij->i", F[:, 2, :], F[:, 2, :]) - 1.0) + lam * np.log(np.maximum(J, 1e-12))


def plate_force_from_stress_n(F: np.ndarray, z: np.ndarray, mu: float, lam: float, v0_m3: float, mass_kg: float,
                              z_bottom_m: float, z_top_m: float) -> float:
    """The top plate's force [N] on a body in equilibrium between it (at z_top) and the ground (at z_bottom):
    -(sum_p V0 tau_zz + W (z_com - z_bottom)) / (z_top - z_bottom) (the zz virial of the body)."""
    s = float(v0_m3 * kirchhoff_zz_pa(F, mu, lam).sum())
    return -(s + mass_kg * G * (float(np.mean(z)) - z_bottom_m)) / (z_top_m - z_bottom_m)


def surface_vertices_m(obj: Path) -> np.ndarray:
    """The vertices of an exported Wavefront OBJ surface (asset frame)."""
    rows = [line.split()[1:4] for line in obj.read_text(encoding="utf-8").splitlines() if line.startswith("v ")]
    return np.array(rows, np.float64).reshape(-1, 3)


def _young(mod: ModuleType, young_pa: float | None) -> float:
    return float(young_pa or mod.PARAMS["youngs_modulus_pa"])


def _rate(mod: ModuleType, damping_rate_per_s: float | None) -> float:
    return float(mod.PARAMS["damping_rate_per_s"] if damping_rate_per_s is None else damping_rate_per_s)


def _period_s(p: dict[str, Any]) -> float:
    # the probes' time scales come from the exported (validated) E, as L2's do, not from a calibration's trial E
    return fundamental_period_s(float(p["height_m"]), float(p["youngs_modulus_pa"]), float(p["density_kg_per_m3"]))


def drop(scene_py: Path, height_fraction: float, young_pa: float | None = None,
         damping_rate_per_s: float | None = None, duration_s: float = 2.0) -> dict[str, float]:
    """rebound_ratio, dissipated_energy_fraction, max_impact_strain, settle_time_s, ... of the drop in Genesis."""
    t_wall = time.perf_counter()
    mod = load_scene_module(Path(scene_py))
    p = mod.PARAMS
    rate = _rate(mod, damping_rate_per_s)
    h = height_fraction * float(p["height_m"])
    # as L2: Genesis's grid ground reaches the particles ~1.5 cells above the plane (the MPM contact layer), so the
    # body is released that much higher and falls h before it touches
    scene, body = mod.build_scene(young_pa=young_pa, lift_m=h + 1.5 / float(p["grid_density_per_m"]),
                                  damping_rate_per_s=rate)
    dt = float(p["dt_s"])
    M = float(p["mass_kg"])
    quiet = 1e-3 * M * G * h
    t: list[float] = []
    z: list[float] = []
    vz: list[float] = []
    ke: list[float] = []
    fg: list[float] = []
    s95: list[float] = []
    calm = 0
    k = 0
    x = np.zeros((0, 3))
    while k * dt < duration_s - 1e-9:
        scene.step()
        k += 1
        st = body.get_state()
        x, v, F = _numpy(st.pos)[0], _numpy(st.vel)[0], _numpy(st.F)[0]
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            raise SimulationError(f"Genesis diverged (non-finite particles) at t = {k * dt:.3f} s")
        m = M / len(x)
        t.append(k * dt)
        z.append(float(x[:, 2].mean()))
        vz.append(float(v[:, 2].mean()))
        ke.append(float(0.5 * m * np.sum(v * v)))
        s95.append(float(np.percentile(compressive_strain(F), 95)))
        pushed = len(vz) >= 2 and (vz[-1] - vz[-2]) / dt > -0.5 * G
        fg.append(1.0 if pushed or (fg and fg[-1] > 0 and x[:, 2].min() < 2.0 * float(p["particle_size_m"])) else 0.0)
        calm = calm + 1 if (ke[-1] < quiet and fg[-1] > 0) else 0
        if t[-1] >= 0.6 and calm * dt >= 0.1:
            break
    out = drop_metrics(np.array(t), np.array(z), np.array(vz), np.array(ke), np.array(fg), np.array(s95), M, h, dt)
    out["sim_time_s"] = t[-1]
    out["wall_time_s"] = time.perf_counter() - t_wall
    out["particles"] = float(len(x))
    out["damping_rate_per_s"] = rate
    return out


def compress(scene_py: Path, strain: float, area_m2: float, young_pa: float | None = None,
             damping_rate_per_s: float | None = None, trace: list[tuple[float, ...]] | None = None) -> dict[str, float]:
    """L2's compression probe in Genesis: effective_modulus_pa, recovery_ratio, compression_strain/force, ...
    trace, when given, receives (t, scheduled plate bottom z, Genesis's plate bottom z, top particle z, height) per
    step."""
    t_wall = time.perf_counter()
    mod = load_scene_module(Path(scene_py))
    p = mod.PARAMS
    rate = _rate(mod, damping_rate_per_s)
    young = _young(mod, young_pa)
    s = float(p["particle_size_m"])
    dx = 1.0 / float(p["grid_density_per_m"])  # Genesis's grid cell (twice the particle spacing, as L2's)
    H = float(p["height_m"])
    dt = float(p["dt_s"])
    lift = 1.5 * dx  # resting on the grid contact layer (see drop)
    top = lift + H  # the surface's top once placed
    half_t = max(dx, 0.01)
    gap = 1.5 * dx
    surface = surface_vertices_m(Path(scene_py).parent / str(p["surface_file"]))
    s_lo, s_hi = surface.min(axis=0), surface.max(axis=0)
    cxy = 0.5 * (s_lo[:2] + s_hi[:2])
    half = (0.5 * float(s_hi[0] - s_lo[0]) + s + 2 * dx, 0.5 * float(s_hi[1] - s_lo[1]) + s + 2 * dx, half_t)
    z_plate = top + gap + half_t
    scene, body, plate = mod.build_plate_scene(half, (float(cxy[0]), float(cxy[1]), z_plate), young_pa=young,
                                               lift_m=lift, damping_rate_per_s=rate)
    mu, lam = lame_pa(young, float(p["poisson_ratio"]))
    v0 = s ** 3
    rho = float(p["density_kg_per_m3"])
    x0 = _numpy(body.get_particles_pos())
    n = len(x0)
    M = rho * v0 * n  # Genesis's particle masses: rho V0 each
    plate_mass = float(_numpy(plate.get_mass()).sum())
    z0 = x0[:, 2]
    bottom = z0 < z0.min() + 0.75 * s
    measured = z0 < z0.max() + 0.5 * s - dx
    if measured.sum() < 8 or z0[measured].mean() - z0[bottom].mean() < 0.3 * (z0.mean() - z0[bottom].mean()):
        measured = np.ones(n, bool)
    T = _period_s(p)
    t_settle, t_load, t_hold = max(0.1, 8 * T), max(0.2, 20 * T), max(0.1, 6 * T)
    t_release, t_recover = 0.1, max(0.2, 10 * T)
    travel_max = gap + 2.0 * strain * H + dx  # (+ a cell: the grid nodes reach up to a cell over the particles)
    v_load = (gap + strain * H) / t_load
    clock = [0.0]

    def advance(vz_plate: float) -> np.ndarray:
        nonlocal z_plate
        mod.move_plate(plate, z_plate, vz_plate)
        scene.step()
        z_plate += vz_plate * dt
        clock[0] += dt
        x = _numpy(body.get_particles_pos())
        if not np.all(np.isfinite(x)):
            raise SimulationError(f"Genesis diverged (non-finite particles) at t = {clock[0]:.3f} s")
        if trace is not None:
            trace.append((clock[0], z_plate - half_t, float(_numpy(plate.get_pos())[2]) - half_t,
                          float(x[:, 2].max()), height(x)))
        return x

    weights = np.ones(n)

    def height(x: np.ndarray) -> float:
        # along the body's own vertical (as MuJoCo's and Drake's): a ball between frictionless plates turns freely,
        # and its bottom layer would ride up its side (the rubber ball read e = 0.39 at the hold and recovery 0.16)
        x = unrotated(x, x0, weights)
        return 2.0 * float(x[measured, 2].mean() - x[bottom, 2].mean())

    def steps(duration: float) -> int:
        return max(1, int(round(duration / dt)))

    hs = []
    for i in range(steps(t_settle)):
        x = advance(0.0)
        if (i + 1) * dt > 0.5 * t_settle:
            hs.append(height(x))
    h0 = float(np.mean(hs))
    # the body settles onto Genesis's contact layer (thinner than the 1.5 cells it was placed on): the plate starts
    # its descent the gap above the settled top (it is moved while out of contact)
    z_plate = min(z_plate, float(x[:, 2].max()) + 0.5 * s + gap + half_t)
    travelled = 0.0
    e = 0.0
    for _ in range(steps(2.0 * t_load)):
        x = advance(-v_load)
        travelled += v_load * dt
        e = 1.0 - height(x) / h0
        if e >= strain or travelled >= travel_max:
            break
    forces, stress_forces, h_hold = [], [], []
    n_hold = steps(t_hold)
    for i in range(n_hold):
        x = advance(0.0)
        if (i + 1) > 0.3 * n_hold:
            st = body.get_state()
            xs, F = _numpy(st.pos)[0], _numpy(st.F)[0]
            zs = xs[:, 2]
            # the coupler's reaction accelerates the (gravity-compensated) plate from rest over the step
            forces.append(float(_numpy(plate.get_dofs_velocity())[2]) * plate_mass / dt)
            # the check: the body's zz virial between the grid nodes the walls act on: the ground plane's at z = 0,
            # the plate's lowest node inside it (Genesis's grid nodes lie at multiples of dx)
            z_top = dx * math.ceil((z_plate - half_t) / dx - 1e-6)
            stress_forces.append(plate_force_from_stress_n(F, zs, mu, lam, v0, M, 0.0, z_top))
            h_hold.append(height(xs))
    h_rec = []
    for _ in range(steps(t_release)):
        advance((travel_max + gap) / t_release)
    n_rec = steps(t_recover)
    for i in range(n_rec):
        x = advance(0.0)
        if (i + 1) > 0.6 * n_rec:
            h_rec.append(height(x))
    return {
        **compression_metrics(forces, h0, h_hold, h_rec, area_m2),
        "compression_force_from_stress_n": float(np.mean(stress_forces)),
        "sim_time_s": clock[0], "wall_time_s": time.perf_counter() - t_wall, "particles": float(n),
        "damping_rate_per_s": rate,
    }


__all__ = ["compress", "drop", "kirchhoff_zz_pa", "lame_pa", "load_scene_module", "plate_force_from_stress_n"]
