"""L2 deformable probes on the MPM engine: compression, drop, lift/pinch, stability (plain functions, SI units).

Every probe takes a DeformableBody (L0 particles + L1 density/friction) and a list of candidate materials, runs the
candidates as planned by `schedule` (tasks.probes.rollout.plan_batches: by default candidates with the same time step,
i.e. the same E and nu, share one lock-step rollout and the others run one after another; each rollout is one
simulation call), and returns one ProbeResult per material. Every
result also carries the gate metrics of tasks/probes/metrics.py (finite, in_domain, j_min, j_max,
ground_tunnelling_m, engine_health_ok). Metric definitions are in each probe's docstring and in the README.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from contracts.material import Material
from contracts.probes import ProbeResult
from contracts.sim import SimConfig
from tasks.mpm import ColliderSpec, IntervalReport, SceneSpec, box_collider
from tasks.probes.metrics import (
    center_of_mass, compressive_strain, cross_section_area, det_f, kinetic_energy, top_bottom_layers,
)
from tasks.probes.rollout import (
    DeformableBody, Rollout, dx_of, fundamental_period_s, make_result, quasi_static_mass_scale, run_scheduled,
    sample_interval_s, scaled_gravity,
)

G = 9.81  # m/s^2

# stability thresholds (documented in stability())
KE_DECAY_MAX = 0.1
LATE_DRIFT_MAX = 0.01
DEFORMATION_MAX = 0.25
VOLUME_CHANGE_MAX = 0.05
# A body whose mean kinetic energy is below KE_AT_REST * M g H is at rest: an RMS speed of sqrt(2e-7 g H) (0.13 mm/s
# for H = 8.5 cm) moves it by < 1e-3 H over the last 0.5 s. Float32 round-off keeps a stiff body at rest at
# ~2e-9 M g H (draft turtle, E = 2.4 MPa, nu = 0.48); its peak kinetic energy is that same noise, so the ratio test
# alone would call a body that never moved unstable.
KE_AT_REST = 1e-7

# Quasi-static probes run a stiff body mass-scaled (rollout.quasi_static_mass_scale: density x k, gravity / k) up to a
# fundamental period; a body already as slow (the plush turtle, 36 ms) runs as it is.
# The rest: 3 s is still >= 150 periods of 0.02 s, sampled every 0.02 s.
STABILITY_QS_PERIOD_S = 0.02
# The compression: each phase lasts max(floor, periods x T); up to T = 0.01 s every phase keeps its floor. The plate
# first crosses its 1.5 dx gap, so the squeeze itself is only the share strain H / (gap + strain H) of the loading
# time: the bound is also that squeeze over COMPRESS_QS_SQUEEZE_PERIODS. At 5 periods the tennis ball's specimen
# cube (k = 23) held the unscaled modulus within 0.3 %; a 3 cm cube squeezed over 1.8 periods held a strain 14 %
# short (0.040 against 0.046; benchmarks/quasi_static_scaling.py, tasks/probes/BENCHMARKS.md).
COMPRESS_PHASES = {"settle": (0.1, 8.0), "load": (0.2, 20.0), "hold": (0.1, 6.0), "recover": (0.2, 10.0)}
COMPRESS_QS_PERIOD_S = min(floor / periods for floor, periods in COMPRESS_PHASES.values())
COMPRESS_QS_SQUEEZE_PERIODS = 5.0


def compress_qs_period_s(gap_m: float, squeeze_m: float) -> float:
    """The compression's mass-scaling bound [s]: COMPRESS_QS_PERIOD_S, or less where the squeeze (squeeze_m after a
    gap_m approach, in the loading's shortest time) would last under COMPRESS_QS_SQUEEZE_PERIODS periods."""
    load_s = COMPRESS_PHASES["load"][0]
    return min(COMPRESS_QS_PERIOD_S, load_s * squeeze_m / (gap_m + squeeze_m) / COMPRESS_QS_SQUEEZE_PERIODS)


def kinetic_energy_settles(late_j: float, peak_j: float, mass_kg: float, height_m: float) -> bool:
    """The stability probe's 'kinetic energy decays': the late mean is <= KE_DECAY_MAX of the peak, or the body is at
    rest (late mean <= KE_AT_REST M g H, where a ratio of round-off noise to round-off noise means nothing)."""
    ratio = late_j / peak_j if peak_j > 0 else 0.0
    return ratio <= KE_DECAY_MAX or late_j <= KE_AT_REST * mass_kg * G * height_m


def _as_list(materials: Material | Sequence[Material]) -> list[Material]:
    return [materials] if isinstance(materials, Material) else list(materials)


# -- compression ---------------------------------------------------------------------------------------------------
def compress(body: DeformableBody, materials: Material | Sequence[Material], strain: float = 0.1,
             sim: SimConfig | None = None, record_paths: Sequence[Path | None] | None = None,
             held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Quasi-static compression between a kinematic top plate and the ground, then release.

    Both contacts are frictionless (the probe measures the material, not friction). Heights are equivalent prism
    heights h = 2 (z_c - z_bottom), z_bottom the mean z of the bottom particle layer and z_c the centre of mass of the
    particles below the plate's contact layer (rest z more than one grid cell dx below the top; all particles if the
    body is too thin for that to leave a height of 0.3 of the whole body's): a uniform strain e
    scales every height above the bottom layer by 1 - e, so e = 1 - h/h0 is exact for a prism and, on other shapes, a
    whole-body strain that local indentation under the plate cannot dominate. The contact layer is left out because
    the engine pushes particles that cross a kinematic collider back to its surface without a matching deformation
    gradient: in that layer the plate leaves a permanent set that is an artefact of the contact, not of the material
    (draft turtle, E = 2.4 MPa: recovery 0.92 with the layer, 0.98 without it, 0.98 with that push switched off).
    The body first settles under gravity (h0); the plate then
    descends at a slow constant speed (loading time >= 20 fundamental periods 4H/c, c = sqrt(E/rho)) until the
    measured strain e = 1 - h/h0 reaches `strain`, and holds. A body whose period is under compress_qs_period_s() (a
    stiff rubber) is mass-scaled to it (density x k, gravity / k: the same weight, forces and stresses; k in the params
    as mass_scale): its phases keep their shortest durations and their periods, at sqrt(k) x the time step.
      effective_modulus_pa   secant stress / strain at the held strain: (F / A) / e, with F the mean vertical force the
                             body exerts on the plate during the hold [N] and A the cross-section at mid height [m^2]
                             (particle volume in a two-layer slab / its thickness; the contact area for a prism)
      compression_strain     e measured during the hold [-];  compression_force_n  F [N];  cross_section_m2  A
      recovery_ratio         recovered / applied displacement after the plate is withdrawn: (h_r - h_l)/(h0 - h_l),
                             h_l the loaded height, h_r the mean height over the end of the recovery window; capped
                             at 1 (residual vibration is not extra recovery) [-]
    The force-displacement curve (plate_displacement_m, compression_strain, plate_force_n) is in the recording.
    """
    sim = sim or SimConfig()
    mats = _as_list(materials)
    return run_scheduled(lambda m, p: _compress(body, m, strain, sim, p, held_out), mats, record_paths, body, sim,
                         schedule)


def _compress(body: DeformableBody, mats: Sequence[Material], strain: float, sim: SimConfig,
              paths: Sequence[Path | None], held_out: bool) -> list[ProbeResult]:
    x0, s = body.positions_m, body.spacing_m
    dx = dx_of(body, sim)
    H = body.height_m
    _, bottom = top_bottom_layers(x0, s)
    measured = x0[:, 2] < x0[:, 2].max() - dx  # below the plate's contact layer (see the docstring)
    m0 = body.masses_kg
    z_b0 = x0[bottom, 2].mean()
    if measured.sum() < 8 or (center_of_mass(x0[measured], m0[measured])[2] - z_b0
                              < 0.3 * (center_of_mass(x0, m0)[2] - z_b0)):
        measured = np.ones(len(x0), bool)  # a body about two grid cells tall: no layer can be left out
    area = cross_section_area(x0, body.volumes_m3, s, 0.5 * (x0[:, 2].min() + x0[:, 2].max()))
    lo, hi = x0.min(axis=0), x0.max(axis=0)
    half_t = max(dx, 0.01)
    half = (0.5 * (hi[0] - lo[0]) + s + 2 * dx, 0.5 * (hi[1] - lo[1]) + s + 2 * dx, half_t)
    gap = 1.5 * dx
    z_plate0 = hi[2] + 0.5 * s + gap + half_t
    cxy = 0.5 * (lo[:2] + hi[:2])
    bound = compress_qs_period_s(gap, strain * H)
    ks = [quasi_static_mass_scale(body, m, bound) for m in mats]
    scenes = [SceneSpec(x0, body.volumes_m3, body.density_kg_per_m3 * k, m, ground=True, ground_friction=0.0,
                        colliders=[box_collider(half, friction=0.0, position_m=(cxy[0], cxy[1], z_plate0), name="plate")],
                        gravity_m_per_s2=scaled_gravity(sim, k))
              for m, k in zip(mats, ks)]
    T = max(fundamental_period_s(body, m, k) for m, k in zip(mats, ks))
    dt_s = sample_interval_s(body, mats, mass_scales=ks)
    t_settle, t_load, t_hold, t_recover = (max(floor, periods * T) for floor, periods in COMPRESS_PHASES.values())
    t_release = 0.1
    travel_max = gap + 2.0 * strain * H
    v_load = (gap + strain * H) / t_load
    n_est = int((t_settle + 1.5 * t_load + t_hold + t_release + t_recover) / dt_s)
    run = Rollout(scenes, sim, paths, "compress", n_est)
    B = len(mats)
    bots = [bottom] * B

    def heights(states: list[dict[str, np.ndarray]]) -> np.ndarray:
        """Equivalent height 2 (z_c - z_bottom_layer), z_c the centre of mass below the plate's contact layer."""
        return np.array([2.0 * (center_of_mass(st["x"][measured], run.masses[i][measured])[2]
                                - st["x"][bots[i], 2].mean()) for i, st in enumerate(states)])

    # settle under gravity
    h_settle: list[np.ndarray] = []
    while run.ok and run.time_s < t_settle - 1e-9:
        _, st = run.advance(dt_s)
        if run.time_s > 0.5 * t_settle:
            h_settle.append(heights(st))
    h0 = np.mean(h_settle, axis=0) if h_settle else np.full(B, H - s)
    # load: each plate stops when its body reaches the target strain
    moving = np.ones(B, bool)
    for i in range(B):
        run.sim.control.set_collider(i, 0, linear_velocity_m_per_s=(0.0, 0.0, -v_load))
    t0 = run.time_s
    while run.ok and moving.any() and run.time_s - t0 < 2.0 * t_load:
        rep, st = run.advance(dt_s)
        e = 1.0 - heights(st) / h0
        for i in range(B):
            f = float(rep.collider_force(run.model, i, 0)[2])
            z_plate = run.sim.control.collider_pose(run.model.collider_index(i, 0), run.time_s)[0][2]
            run.scalar(i, "compression_strain", float(e[i]))
            run.scalar(i, "plate_force_n", f)
            run.scalar(i, "plate_displacement_m", float(z_plate0 - z_plate))
            if moving[i] and (e[i] >= strain or v_load * (run.time_s - t0) >= travel_max):
                moving[i] = False
                run.sim.control.set_collider(i, 0, linear_velocity_m_per_s=(0.0, 0.0, 0.0))
    # hold: mean force and strain
    forces, h_hold = [], []
    t1 = run.time_s
    while run.ok and run.time_s - t1 < t_hold - 1e-9:
        rep, st = run.advance(dt_s)
        if run.time_s - t1 > 0.3 * t_hold:
            forces.append([float(rep.collider_force(run.model, i, 0)[2]) for i in range(B)])
            h_hold.append(heights(st))
    # release and recover
    for i in range(B):
        run.sim.control.set_collider(i, 0, linear_velocity_m_per_s=(0.0, 0.0, (travel_max + gap) / t_release))
    t2 = run.time_s
    h_rec: list[np.ndarray] = []
    while run.ok and run.time_s - t2 < t_release + t_recover - 1e-9:
        _, st = run.advance(dt_s)
        if run.time_s - t2 > t_release + 0.6 * t_recover:
            h_rec.append(heights(st))
        if run.time_s - t2 >= t_release:
            for i in range(B):
                run.sim.control.set_collider(i, 0, linear_velocity_m_per_s=(0.0, 0.0, 0.0))
    out = []
    for i in range(len(mats)):
        params = {"strain": strain, "area_m2": area, **_mass_scale_param(ks[i])}
        metrics = run.gate_metrics(i)
        if run.ok and forces and h_rec:
            F = float(np.mean([f[i] for f in forces]))
            h_l = float(np.mean([h[i] for h in h_hold]))
            e_h = 1.0 - h_l / h0[i]
            h_r = float(np.mean([h[i] for h in h_rec]))
            applied = h0[i] - h_l
            metrics.update({
                "effective_modulus_pa": (max(F, 0.0) / area) / e_h if e_h > 0 and area > 0 else math.nan,
                "compression_strain": e_h, "compression_force_n": F, "cross_section_m2": area,
                "recovery_ratio": min(1.0, (h_r - h_l) / applied) if applied > 0 else math.nan,
            })
        out.append(make_result("compress", params, metrics, run.health(i), run.wall_s, held_out, run.time_s))
    run.close([f"compress to strain {strain}: E={m.youngs_modulus_pa:.4g} Pa{_mass_scale_note(k)}"
               for m, k in zip(mats[:1], ks)])
    return out


def _mass_scale_param(k: float) -> dict[str, float]:
    """A quasi-static rollout's mass scale as a probe parameter (none when the body ran unscaled)."""
    return {"mass_scale": k} if k > 1.0 else {}


def _mass_scale_note(k: float) -> str:
    """The recording's note of a mass-scaled rollout."""
    return f", mass-scaled x{k:.3g} (density x k, gravity / k)" if k > 1.0 else ""


# -- drop ----------------------------------------------------------------------------------------------------------
def drop(body: DeformableBody, materials: Material | Sequence[Material], height_fraction: float = 0.25,
         duration_s: float = 2.0, sim: SimConfig | None = None, record_paths: Sequence[Path | None] | None = None,
         held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Drop from rest with the lowest point at h = height_fraction * H above the ground; watch the impact.

    The grid ground reaches particles within 1.5 dx of it, so the body is released that contact layer higher: its
    free fall before the first contact is h. On a grid the body can come to rest anywhere in that layer, so the rest
    height z_rest is where this body settles: its mean COM height over the last 0.1 s. The rollout lasts at least
    0.6 s and goes on (up to duration_s) until every body has settled.
      rebound_ratio              (z_apex - z_rest) / (z_release - z_rest): COM apex height above rest over the COM
                                 fall height, z_apex the COM height at the first maximum after the COM starts
                                 rising after the first ground contact (0 if it never rises) [-]
      dissipated_energy_fraction 1 - E(apex) / E(release), E = kinetic energy + M g (z_com - z_rest) [-]
      max_impact_strain          largest compressive principal strain 1 - sigma_min(F), 95th percentile over the
                                 particles, maximum over the samples from first ground contact to the apex [-]
      settle_time_s              time from release after which the kinetic energy stays below 1e-3 M g h; the
                                 rollout's duration if it never does (then settled = 0) [s]
    """
    sim = sim or SimConfig()
    mats = _as_list(materials)
    return run_scheduled(lambda m, p: _drop(body, m, height_fraction, duration_s, sim, p, held_out), mats, record_paths,
                         body, sim, schedule)


def _drop(body: DeformableBody, mats: Sequence[Material], frac: float, duration: float, sim: SimConfig,
          paths: Sequence[Path | None], held_out: bool) -> list[ProbeResult]:
    x0 = body.positions_m
    h = frac * body.height_m
    layer = max(0.0, 1.5 * dx_of(body, sim) - (x0[:, 2].min() - sim.ground_height_m))
    lift = np.array([0.0, 0.0, h + layer])
    scenes = [SceneSpec(x0 + lift, body.volumes_m3, body.density_kg_per_m3, m, ground_friction=body.ground_friction)
              for m in mats]
    dt_s = sample_interval_s(body, mats, longest_s=2.5e-3)
    run = Rollout(scenes, sim, paths, "drop", int(0.6 / dt_s))
    B = len(mats)
    M = body.mass_kg
    quiet_ke = 1e-3 * M * G * h
    t, z, vz, ke, fg, strain95 = [], [], [], [], [], []
    calm = np.zeros(B, int)  # consecutive quiet samples per scene
    while run.ok and run.time_s < duration - 1e-9:
        rep, st = run.advance(dt_s)
        t.append(run.time_s)
        zs, vs, ks, fs, ss = [], [], [], [], []
        for i, d in enumerate(st):
            m_i = run.masses[i]
            zs.append(center_of_mass(d["x"], m_i)[2])
            vs.append(float((d["v"][:, 2].astype(np.float64) * m_i).sum() / m_i.sum()))
            ks.append(kinetic_energy(d["v"], m_i))
            fs.append(abs(float(rep.ground_force_n[i][2])))
            ss.append(float(np.percentile(compressive_strain(d["F"]), 95)))
            run.scalar(i, "impact_strain_p95", ss[-1])
            calm[i] = calm[i] + 1 if (ks[-1] < quiet_ke and fs[-1] > 0) else 0
        z.append(zs)
        vz.append(vs)
        ke.append(ks)
        fg.append(fs)
        strain95.append(ss)
        if run.time_s >= 0.6 and np.all(calm * dt_s >= 0.1):
            break
    out = []
    params = {"height_fraction": frac, "height_m": h}
    for i in range(len(mats)):
        metrics = run.gate_metrics(i)
        if run.ok and len(t) > 4:
            metrics.update(_drop_metrics(np.array(t), np.array(z)[:, i], np.array(vz)[:, i], np.array(ke)[:, i],
                                         np.array(fg)[:, i], np.array(strain95)[:, i], M, h, dt_s))
        out.append(make_result("drop", params, metrics, run.health(i), run.wall_s, held_out, run.time_s))
    run.close([f"drop from {h:.4f} m"])
    return out


def _drop_metrics(t: np.ndarray, z: np.ndarray, vz: np.ndarray, ke: np.ndarray, fg: np.ndarray, s95: np.ndarray,
                  M: float, h: float, dt_s: float) -> dict[str, float]:
    """Rebound, dissipation, impact strain and settle time from the sampled series (see drop())."""
    z_rest = float(z[t > t[-1] - 0.1 - 0.5 * dt_s].mean())
    energy = ke + M * G * (z - z_rest)
    e0 = M * G * (z[0] - z_rest) + ke[0]
    fall = e0 / (M * G)  # COM height above rest at release (h plus the contact layer) [m]
    contact = np.flatnonzero(fg > 1e-9)
    out: dict[str, float] = {"drop_height_m": h, "rest_com_z_m": z_rest}
    if len(contact) == 0 or fall <= 0:
        return out
    c = int(contact[0])
    rising = np.flatnonzero(vz[c:] > 0)
    if len(rising) == 0:
        apex = None
    else:
        r = c + int(rising[0])
        falling = np.flatnonzero(vz[r:] <= 0)
        apex = r + int(falling[0]) if len(falling) else r + int(np.argmax(z[r:]))
    end = apex if apex is not None else len(t) - 1
    out["rebound_ratio"] = max(0.0, float(z[apex] - z_rest)) / fall if apex is not None else 0.0
    out["fall_height_m"] = fall
    out["dissipated_energy_fraction"] = float(1.0 - energy[end] / e0)
    out["max_impact_strain"] = float(s95[c:end + 1].max())
    quiet = ke < 1e-3 * M * G * h
    loud = np.flatnonzero(~quiet)
    settled = bool(quiet[-1])
    out["settle_time_s"] = float(t[loud[-1] + 1]) if settled and len(loud) else (float(t[0]) if settled else float(t[-1]))
    out["settled"] = 1.0 if settled else 0.0
    out["first_contact_time_s"] = float(t[c])
    return out


# -- lift / pinch --------------------------------------------------------------------------------------------------
def lift(body: DeformableBody, materials: Material | Sequence[Material], max_squeeze_fraction: float = 0.75,
         safety: float = 2.5, sim: SimConfig | None = None, record_paths: Sequence[Path | None] | None = None,
         held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Two box fingers pinch the body across its narrow horizontal axis at the centre of its long axis, at the height
    of the centre of mass (Coulomb friction mu = the L1 gripper friction). They close slowly while the mean normal
    force per finger is below safety * M g / (2 mu) and the squeeze below max_squeeze_fraction of the local width
    (force control, re-closing if the grip relaxes), then rise by max(L/2, H) and hold.
      sag_m          rise of the pinched particles minus the mean rise of the end particles (outer 10 % of the
                     length on each side), from before the lift to the end of the hold [m]
      sag_ratio      sag_m / L, L the length of the long horizontal axis [-] (reported only if the grasp held;
                     contracts.probes.not_measured_reason says why when it is missing)
      lift_held      1 if the pinched particles rose by >= 70 % of the finger travel [-]
      pinch_force_n  mean normal force on one finger before lifting [N]
    The squeeze limit is 75 % of the width (was 50 %, #36): a soft body thins as it is lifted, and the fingers must be
    able to close on it again; at 50 % the default plush turtle (E = 10 kPa, mu = 0.7) used up its travel before the
    lift and slipped out (the pinched part rose 16 mm of 120 mm), so sag_ratio went unmeasured.
    """
    sim = sim or SimConfig()
    mats = _as_list(materials)
    return run_scheduled(lambda m, p: _lift(body, m, max_squeeze_fraction, safety, sim, p, held_out), mats,
                         record_paths, body, sim, schedule)


def _lift(body: DeformableBody, mats: Sequence[Material], squeeze: float, safety: float, sim: SimConfig,
          paths: Sequence[Path | None], held_out: bool) -> list[ProbeResult]:
    x0, s = body.positions_m, body.spacing_m
    dx = dx_of(body, sim)
    ext = body.extents_m
    a = 0 if ext[0] >= ext[1] else 1
    b = 1 - a
    L, H = float(ext[a]), body.height_m
    com = center_of_mass(x0, body.masses_kg)
    lo, hi = x0.min(axis=0), x0.max(axis=0)
    c_a = 0.5 * (lo[a] + hi[a])
    half_t = 0.5 * dx  # thin in b, wide in a and z: grid nodes inside leave through the gripping face
    pad_a = max(0.12 * L, 2.0 * dx)
    pad_z = min(max(0.3 * H, 1.5 * dx), 0.8 * float(com[2]))
    pinch = (np.abs(x0[:, a] - c_a) < pad_a) & (np.abs(x0[:, 2] - com[2]) < pad_z)
    span = hi[a] - lo[a]
    ends = (x0[:, a] < lo[a] + 0.1 * span) | (x0[:, a] > hi[a] - 0.1 * span)
    b_lo, b_hi = x0[pinch, b].min() - 0.5 * s, x0[pinch, b].max() + 0.5 * s
    width = b_hi - b_lo
    gap = dx
    half = [0.0, 0.0, pad_z]
    half[a], half[b] = pad_a, half_t

    def finger(side: int) -> ColliderSpec:
        pos = [0.0, 0.0, float(com[2])]
        pos[a] = c_a
        pos[b] = (b_hi + gap + half_t) if side > 0 else (b_lo - gap - half_t)
        return box_collider(half, friction=body.gripper_friction, position_m=(pos[0], pos[1], pos[2]),
                            name=f"finger_{side:+d}")

    scenes = [SceneSpec(x0, body.volumes_m3, body.density_kg_per_m3, m, ground_friction=body.ground_friction,
                        colliders=[finger(+1), finger(-1)]) for m in mats]
    B = len(mats)
    dt_s = sample_interval_s(body, mats)
    rise = max(0.5 * L, H)
    t_close, t_pre, t_lift, t_hold = 0.4, 0.15, max(0.3, rise / 0.3), 0.4
    run = Rollout(scenes, sim, paths, "lift", int((t_close + t_pre + t_lift + t_hold) / dt_s))
    v_close = (gap + 0.5 * squeeze * width) / t_close
    n_target = safety * body.mass_kg * G / (2.0 * max(body.gripper_friction, 1e-6))

    def set_v(i: int, vb: float, vz: float) -> None:
        for j, sign in ((0, -1.0), (1, 1.0)):
            v = [0.0, 0.0, vz]
            v[b] = sign * vb
            run.sim.control.set_collider(i, j, linear_velocity_m_per_s=tuple(v))

    def normal(rep: IntervalReport, i: int) -> float:
        return 0.5 * (abs(float(rep.collider_force(run.model, i, 0)[b]))
                      + abs(float(rep.collider_force(run.model, i, 1)[b])))

    def zs(states: list[dict[str, np.ndarray]], mask: np.ndarray) -> np.ndarray:
        return np.array([float(st["x"][mask, 2].mean()) for st in states])

    travel = np.zeros(B)
    travel_max = gap + 0.5 * squeeze * width
    st: list[dict[str, np.ndarray]] = []
    n_forces = []
    closing = np.zeros(B, bool)

    def grip(rep: IntervalReport, v_z: float) -> None:
        """Force control: squeeze while the grip is below target and the squeeze below its limit."""
        for i in range(B):
            closing[i] = normal(rep, i) < n_target and travel[i] < travel_max
            set_v(i, v_close if closing[i] else 0.0, v_z)
            travel[i] += v_close * dt_s if closing[i] else 0.0

    while run.ok and run.time_s < t_close + t_pre - 1e-9:
        rep, st = run.advance(dt_s)
        grip(rep, 0.0)
        if run.time_s > t_close:
            n_forces.append([normal(rep, i) for i in range(B)])
    z_p0, z_e0 = (zs(st, pinch), zs(st, ends)) if st else (np.zeros(B), np.zeros(B))
    t_ramp = 0.25 * t_lift  # trapezoidal speed profile: the grip need not jerk the body off the ground
    v_max = rise / (t_lift - t_ramp)
    t1 = run.time_s
    while run.ok and run.time_s - t1 < t_lift - 1e-9:
        tau = run.time_s - t1 + 0.5 * dt_s
        grip(rep, v_max * min(1.0, tau / t_ramp, max(0.0, (t_lift - tau) / t_ramp)))
        rep, _ = run.advance(dt_s)
    t2 = run.time_s
    zp, ze = [], []
    while run.ok and run.time_s - t2 < t_hold - 1e-9:
        grip(rep, 0.0)
        rep, st = run.advance(dt_s)
        if run.time_s - t2 > 0.6 * t_hold:
            zp.append(zs(st, pinch))
            ze.append(zs(st, ends))
    out = []
    params = {"max_squeeze_fraction": squeeze, "safety": safety, "rise_m": rise, "length_m": L}
    for i in range(len(mats)):
        metrics = run.gate_metrics(i)
        if run.ok and zp:
            dp = float(np.mean([z[i] for z in zp]) - z_p0[i])
            de = float(np.mean([z[i] for z in ze]) - z_e0[i])
            held = dp >= 0.7 * rise
            metrics.update({"lift_held": 1.0 if held else 0.0, "pinch_rise_m": dp, "sag_m": dp - de,
                            "pinch_force_n": float(np.mean([f[i] for f in n_forces])) if n_forces else math.nan})
            if held:
                metrics["sag_ratio"] = (dp - de) / L
        out.append(make_result("lift", params, metrics, run.health(i), run.wall_s, held_out, run.time_s))
    run.close([f"pinch across axis {b} at the centre, lift {rise:.3f} m"])
    return out


# -- stability -----------------------------------------------------------------------------------------------------
def stability(body: DeformableBody, materials: Material | Sequence[Material], duration_s: float = 3.0,
              sim: SimConfig | None = None, record_paths: Sequence[Path | None] | None = None,
              held_out: bool = False, schedule: str = "auto") -> list[ProbeResult]:
    """Rest on the ground for duration_s (>= 3 s) from the rest pose under gravity.
      ke_decay_ratio       mean kinetic energy over the last 0.5 s / peak kinetic energy [-]
      late_drift_ratio     RMS particle displacement between t = T/2 and T, translation removed, / H [-]
      deformation_ratio    RMS particle displacement from the rest pose at T, translation removed, / H [-]
      volume_change        |sum J V / sum V - 1| at T [-]
      stable_long_rollout  1 if the engine stayed healthy, ke_decay_ratio <= 0.1 (or the late kinetic energy is
                           below 1e-7 M g H: at rest, see KE_AT_REST), late_drift_ratio <= 0.01, deformation_ratio <= 0.25 and
                           volume_change <= 0.05; else 0
    A body whose fundamental period is under STABILITY_QS_PERIOD_S (a stiff rubber) rests mass-scaled to it (density
    x k, gravity / k: the same weight and stresses; its kinetic energy is still compared with M g H, which k leaves as
    it was; k in the params as mass_scale).
    """
    sim = sim or SimConfig()
    mats = _as_list(materials)
    return run_scheduled(lambda m, p: _stability(body, m, duration_s, sim, p, held_out), mats, record_paths, body, sim,
                         schedule)


def _stability(body: DeformableBody, mats: Sequence[Material], duration: float, sim: SimConfig,
               paths: Sequence[Path | None], held_out: bool) -> list[ProbeResult]:
    x0, H = body.positions_m, body.height_m
    ks = [quasi_static_mass_scale(body, m, STABILITY_QS_PERIOD_S) for m in mats]
    scenes = [SceneSpec(x0, body.volumes_m3, body.density_kg_per_m3 * k, m, ground_friction=body.ground_friction,
                        gravity_m_per_s2=scaled_gravity(sim, k)) for m, k in zip(mats, ks)]
    dt_s = 0.02
    run = Rollout(scenes, sim, paths, "stability", int(duration / dt_s))
    M = body.mass_kg
    t, ke = [], []
    x_mid: list[np.ndarray] | None = None
    st: list[dict[str, np.ndarray]] = []
    while run.ok and run.time_s < duration - 1e-9:
        _, st = run.advance(dt_s)
        t.append(run.time_s)
        ke.append([kinetic_energy(s_["v"], run.masses[i]) for i, s_ in enumerate(st)])
        if x_mid is None and run.time_s >= 0.5 * duration - 1e-9:
            x_mid = [s_["x"].astype(np.float64) for s_ in st]
    out = []
    vol = body.volumes_m3
    for i in range(len(mats)):
        metrics = run.gate_metrics(i)
        ok = run.ok and x_mid is not None and bool(st) and metrics["finite"] == 1.0
        if ok and x_mid is not None:  # (ok implies it; the test narrows its type)
            k = np.array(ke)[:, i]
            tt = np.array(t)
            late = float(k[tt > tt[-1] - 0.5].mean())
            peak = float(k.max())
            x_end = st[i]["x"].astype(np.float64)

            def rms(a: np.ndarray, b_: np.ndarray) -> float:
                d = (a - a.mean(axis=0)) - (b_ - b_.mean(axis=0))
                return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))

            ke_ratio = late / peak if peak > 0 else 0.0
            drift = rms(x_end, x_mid[i]) / H
            deform = rms(x_end, x0) / H
            dvol = abs(float(np.sum(det_f(st[i]["F"]) * vol) / vol.sum()) - 1.0)
            decays = kinetic_energy_settles(late, peak, M, H)
            stable = (decays and drift <= LATE_DRIFT_MAX and deform <= DEFORMATION_MAX
                      and dvol <= VOLUME_CHANGE_MAX and metrics["engine_health_ok"] == 1.0)
            metrics.update({"ke_decay_ratio": ke_ratio, "late_drift_ratio": drift, "deformation_ratio": deform,
                            "volume_change": dvol, "stable_long_rollout": 1.0 if stable else 0.0})
        else:
            metrics["stable_long_rollout"] = 0.0
        out.append(make_result("stability", {"duration_s": duration, **_mass_scale_param(ks[i])}, metrics,
                               run.health(i), run.wall_s, held_out, run.time_s))
    run.close([f"rest rollout {duration} s{_mass_scale_note(ks[0])}"])
    return out


# each takes (body, materials, sim=, record_paths=, held_out=, schedule=) and its own keyword parameters
PROBES: dict[str, Callable[..., list[ProbeResult]]] = {"compress": compress, "drop": drop, "lift": lift,
                                                       "stability": stability}

__all__ = ["DeformableBody", "PROBES", "compress", "drop", "kinetic_energy_settles", "lift", "stability"]
