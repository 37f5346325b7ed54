"""Analytic verification suite of the MPM engine (REFERENCE.md "Analytic cases"); SI units throughout.

Each case builds a scene, runs the real solver and compares a measured quantity with a closed-form expectation.
``quick=True`` runs reduced-resolution versions (what CI runs as tests).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from collections.abc import Callable

import numpy as np

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm.model import SceneSpec, box_collider, build_model
from tasks.mpm.scene import box_particles, box_scene
from tasks.mpm.simulator import Simulator

G = 9.81  # m/s^2


@dataclass
class CaseResult:
    """Outcome of one analytic case."""

    name: str
    quantity: str
    units: str
    measured: float
    expected: float
    error: float  # relative error unless error_kind says otherwise
    tolerance: float
    passed: bool
    error_kind: str = "relative"
    seconds: float = 0.0
    details: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """JSON-ready representation."""
        return asdict(self)


def _cfg(device: str, dx: float | None = None) -> SimConfig:
    """Numerics of the verification runs: adaptive CFL dt, a tight grid margin (4 cells)."""
    return SimConfig(device=device, dx_m=dx, grid_margin_m=0.0)


def _rel(measured: float, expected: float) -> float:
    """Relative error |m - e| / |e|."""
    return abs(measured - expected) / max(abs(expected), 1e-30)


def _result(name: str, quantity: str, units: str, measured: float, expected: float, tol: float, **kw) -> CaseResult:
    """A CaseResult with relative error."""
    err = _rel(measured, expected)
    return CaseResult(name, quantity, units, float(measured), float(expected), float(err), tol,
                      bool(np.isfinite(err) and err <= tol), **kw)


# -- cases -------------------------------------------------------------------------------------------------------
def case_free_fall(quick: bool, device: str) -> CaseResult:
    """Free fall: mean velocity after t equals -g t (no ground, no damping)."""
    n = 6 if quick else 12
    mat = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3)
    sc = box_scene((0, 0, 1.0), (0.1, 0.1, 1.1), 0.1 / n, mat, 500.0, ground=False)
    sim = Simulator(build_model([sc], _cfg(device)))
    t = 0.3
    rep = sim.advance(t)
    v = sim.particles(0)["v"][:, 2].astype(np.float64)
    res = _result("free_fall", "mean vertical velocity", "m/s", float(np.mean(v)), -G * t, 1e-3)
    res.passed = res.passed and rep.health.ok
    res.details = {"particles": sim.model.n_particles, "steps": rep.steps, "health_ok": rep.health.ok}
    return res


def case_momentum(quick: bool, device: str) -> CaseResult:
    """Momentum conservation: two spinning blocks collide in zero gravity; total momentum is unchanged."""
    n = 5 if quick else 8
    h = 0.05 / n
    mat = Material(youngs_modulus_pa=5e4, poisson_ratio=0.3)
    p1, v1 = box_particles((0.0, 0.0, 0.0), (0.05, 0.05, 0.05), h)
    p2, v2 = box_particles((0.07, 0.01, 0.015), (0.12, 0.06, 0.065), h)
    c1, c2 = p1.mean(axis=0), p2.mean(axis=0)
    vel1 = np.array([0.5, 0.05, 0.0]) + np.cross([0.0, 0.0, 8.0], p1 - c1)
    vel2 = np.array([-0.3, 0.0, 0.1]) + np.cross([5.0, 0.0, 0.0], p2 - c2)
    pos = np.concatenate([p1, p2])
    vel = np.concatenate([vel1, vel2])
    vol = np.concatenate([v1, v2])

    sc = SceneSpec(pos, vol, 400.0, mat, velocities_m_per_s=vel, ground=False, gravity_m_per_s2=(0.0, 0.0, 0.0))
    sim = Simulator(build_model([sc], _cfg(device)))
    m = sim.model.particle_mass_np.astype(np.float64)

    def momentum() -> np.ndarray:
        return (m[:, None] * sim.particles(0)["v"].astype(np.float64)).sum(axis=0)

    p0 = momentum()
    scale = float(np.sum(m * np.linalg.norm(vel, axis=1)))
    rep = sim.advance(0.15)
    p1v = momentum()
    err = float(np.linalg.norm(p1v - p0) / scale)
    x = sim.particles(0)["x"]
    gap_closed = bool(x[: len(p1), 0].max() > x[len(p1):, 0].min() - 2 * sim.model.dx)
    return CaseResult("momentum_conservation", "|P_end - P_start| / sum(m|v|)", "-", err, 0.0, err, 1e-4,
                      bool(err <= 1e-4 and rep.health.ok and gap_closed), error_kind="absolute",
                      details={"P_start_kg_m_per_s": p0.tolist(), "P_end_kg_m_per_s": p1v.tolist(),
                               "blocks_collided": gap_closed, "steps": rep.steps})


def _zero_crossing_times(t: np.ndarray, u: np.ndarray) -> list[float]:
    """Times where u changes sign (linear interpolation)."""
    out = []
    for i in range(1, len(u)):
        if u[i - 1] == 0.0:
            continue
        if u[i - 1] * u[i] < 0.0:
            out.append(t[i - 1] + (t[i] - t[i - 1]) * u[i - 1] / (u[i - 1] - u[i]))
    return out


def case_bar_period(quick: bool, device: str) -> CaseResult:
    """Fixed-free bar (nu = 0) in its first mode: period 4 L / c with c = sqrt(E / rho)."""
    L = 0.4
    cells = 20 if quick else 32
    dx = L / cells
    E, rho = 1e5, 100.0
    c = math.sqrt(E / rho)
    T = 4 * L / c
    mat = Material(youngs_modulus_pa=E, poisson_ratio=0.0)
    pos, vol = box_particles((0, 0, 0.5), (L, 2 * dx, 0.5 + 2 * dx), dx / 2)
    v0 = 0.005 * c
    vel = np.zeros_like(pos)
    vel[:, 0] = v0 * np.sin(0.5 * math.pi * pos[:, 0] / L)
    clamp = box_collider((0.05, 0.2, 0.2), position_m=(-0.05 + 1e-6, 0.0, 0.5), bonded=True)

    sc = SceneSpec(pos, vol, rho, mat, colliders=[clamp], velocities_m_per_s=vel, ground=False,
                   gravity_m_per_s2=(0.0, 0.0, 0.0))
    sim = Simulator(build_model([sc], _cfg(device, dx)))
    tip = pos[:, 0] > L - dx / 2
    x0 = pos[tip, 0].mean()
    ts, us = [0.0], [0.0]
    nsamp = 160
    ok = True
    for _ in range(nsamp):
        rep = sim.advance(2.0 * T / nsamp)
        ok = ok and rep.health.ok
        ts.append(sim.time_s)
        us.append(float(sim.particles(0)["x"][tip, 0].mean() - x0))
    zc = _zero_crossing_times(np.asarray(ts), np.asarray(us))
    # u = A sin(w t): zero crossings every T/2 after t = 0
    measured = 2.0 * float(np.mean(np.diff(zc))) if len(zc) >= 2 else (2.0 * zc[0] if zc else float("nan"))
    res = _result("bar_period", "first period of a fixed-free bar", "s", measured, T, 0.05)
    res.passed = res.passed and ok
    res.details = {"zero_crossings_s": zc, "amplitude_m": float(np.max(np.abs(us))), "wave_speed_m_per_s": c}
    return res


def _extrema(t: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times and absolute values of the interior local extrema of u(t), refined by a parabola through 3 samples."""
    ts, amps = [], []
    for i in range(1, len(u) - 1):
        if (u[i] - u[i - 1]) * (u[i + 1] - u[i]) < 0.0 and abs(u[i]) >= max(abs(u[i - 1]), abs(u[i + 1])):
            a = 0.5 * (u[i - 1] + u[i + 1]) - u[i]
            b = 0.5 * (u[i + 1] - u[i - 1])
            s = -b / (2.0 * a) if a != 0.0 else 0.0
            ts.append(t[i] + s * (t[i + 1] - t[i]))
            amps.append(abs(u[i] + b * s + a * s * s))
    return np.asarray(ts), np.asarray(amps)


def bar_viscous_decay(eta_pa_s: float, quick: bool, device: str, periods: float = 2.0) -> dict:
    """A fixed-free bar (nu = 0) in its first mode with Kelvin-Voigt viscosity eta: rho u_tt = E u_xx + 2 eta u_xxt
    (axial Cauchy stress E eps + 2 eta eps_dot), so the mode q(t) sin(k x), k = pi / (2 L), decays at the amplitude
    rate gamma = eta k^2 / rho. Returns the measured rate (a line through log |tip extrema|), the expected one, the
    damping ratio and the run's health and time step."""
    L = 0.4
    cells = 20 if quick else 32
    dx = L / cells
    E, rho = 1e5, 100.0
    c = math.sqrt(E / rho)
    k = 0.5 * math.pi / L
    mat = Material(youngs_modulus_pa=E, poisson_ratio=0.0, viscosity_pa_s=eta_pa_s)
    pos, vol = box_particles((0, 0, 0.5), (L, 2 * dx, 0.5 + 2 * dx), dx / 2)
    vel = np.zeros_like(pos)
    vel[:, 0] = 0.005 * c * np.sin(k * pos[:, 0])
    clamp = box_collider((0.05, 0.2, 0.2), position_m=(-0.05 + 1e-6, 0.0, 0.5), bonded=True)
    sc = SceneSpec(pos, vol, rho, mat, colliders=[clamp], velocities_m_per_s=vel, ground=False,
                   gravity_m_per_s2=(0.0, 0.0, 0.0))
    sim = Simulator(build_model([sc], _cfg(device, dx)))
    dt = sim.stable_dt()
    tip = pos[:, 0] > L - dx / 2
    x0 = pos[tip, 0].mean()
    T = 4 * L / c
    ts, us = [0.0], [0.0]
    nsamp = int(80 * periods)
    ok = True
    for _ in range(nsamp):
        ok = ok and sim.advance(periods * T / nsamp).health.ok
        ts.append(sim.time_s)
        us.append(float(sim.particles(0)["x"][tip, 0].mean() - x0))
    te, ae = _extrema(np.asarray(ts), np.asarray(us))
    rate = float(-np.polyfit(te, np.log(ae), 1)[0]) if len(te) >= 2 else float("nan")
    gamma = eta_pa_s * k * k / rho
    return {"rate_per_s": rate, "expected_rate_per_s": gamma, "damping_ratio": gamma / (k * c), "health_ok": ok,
            "dt_s": dt, "extrema_s": te.tolist(), "extrema_m": ae.tolist()}


def case_viscous_decay(quick: bool, device: str) -> CaseResult:
    """Kelvin-Voigt viscosity: a fixed-free bar's first mode decays at gamma = eta k^2 / rho (damping ratio 0.05)."""
    k, rho, c = 0.5 * math.pi / 0.4, 100.0, math.sqrt(1e3)
    eta = 0.05 * k * c * rho / (k * k)  # damping ratio gamma / omega = 0.05
    out = bar_viscous_decay(eta, quick, device)
    res = _result("viscous_decay", "amplitude decay rate of a viscous bar's first mode", "1/s", out["rate_per_s"],
                  out["expected_rate_per_s"], 0.15)
    res.passed = res.passed and out["health_ok"]
    res.details = out
    return res


def case_column_settlement(quick: bool, device: str) -> CaseResult:
    """Column under its own weight on a frictionless ground, free sides (nu = 0): settlement rho g H^2 / (2E)."""
    H, W = 0.2, 0.05
    cells = 16 if quick else 24
    dx = H / cells
    E, rho = 2e5, 1000.0
    c = math.sqrt(E / rho)
    w1 = math.pi * c / (2 * H)
    mat = Material(youngs_modulus_pa=E, poisson_ratio=0.0, damping_rate_per_s=w1)
    sc = box_scene((0, 0, 0), (W, W, H), dx / 2, mat, rho, ground_friction=0.0)
    sim = Simulator(build_model([sc], _cfg(device, dx)))
    x0 = sim.particles(0)["x"].astype(np.float64)
    top = x0[:, 2] > H - dx / 2
    bot = x0[:, 2] < dx / 2
    rep = sim.advance(8 * 2 * math.pi / w1 / 4)  # two fundamental periods, damped with zeta = 0.5
    x = sim.particles(0)["x"].astype(np.float64)
    zt0, zb0 = x0[top, 2].mean(), x0[bot, 2].mean()
    measured = (zt0 - zb0) - (x[top, 2].mean() - x[bot, 2].mean())

    def w(z: float) -> float:
        return rho * G / E * (H * z - 0.5 * z * z)

    expected = w(zt0) - w(zb0)
    res = _result("column_settlement", "self-weight shortening of the column", "m", measured, expected, 0.10)
    res.passed = res.passed and rep.health.ok
    res.details = {"closed_form_top_settlement_m": rho * G * H * H / (2 * E), "steps": rep.steps}
    return res


def case_uniaxial_compression(quick: bool, device: str) -> list[CaseResult]:
    """Small-strain compression between frictionless plates: stress = E strain, lateral strain = -nu strain."""
    a = 0.1
    cells = 10 if quick else 16
    dx = a / cells
    E, nu, rho = 1e5, 0.3, 1000.0
    mat0 = Material(youngs_modulus_pa=E, poisson_ratio=nu)
    cp = mat0.p_wave_speed_m_per_s(rho)
    mat = Material(youngs_modulus_pa=E, poisson_ratio=nu, damping_rate_per_s=0.5 * math.pi * cp / a)
    plate_h = 0.02
    z_plate0 = a + 0.5 * dx + plate_h
    plate = box_collider((a, a, plate_h), position_m=(a / 2, a / 2, z_plate0), friction=0.0)
    sc = box_scene((0, 0, 0), (a, a, a), dx / 2, mat, rho, colliders=[plate], ground_friction=0.0,
                   gravity_m_per_s2=(0.0, 0.0, 0.0))
    model = build_model([sc], _cfg(device, dx))
    sim = Simulator(model)
    x0 = sim.particles(0)["x"].astype(np.float64)
    top, bot = x0[:, 2] > a - dx / 2, x0[:, 2] < dx / 2
    t_load = 0.05
    travel = 0.5 * dx + 0.01 * a
    sim.control.set_collider(0, 0, linear_velocity_m_per_s=(0.0, 0.0, -travel / t_load))
    ok = sim.advance(t_load).health.ok
    sim.control.set_collider(0, 0, linear_velocity_m_per_s=(0.0, 0.0, 0.0))
    ok = ok and sim.advance(0.12).health.ok
    rep = sim.advance(0.03)
    ok = ok and rep.health.ok
    # strains from the deformation gradient of the interior particles (surface layers carry MPM boundary effects)
    pa = sim.particles(0)
    x, Fd = pa["x"].astype(np.float64), pa["F"].astype(np.float64)
    core = np.all((x0 > 0.2 * a) & (x0 < 0.8 * a), axis=1)
    strain = float(Fd[core, 2, 2].mean() - 1.0)
    lat = float(0.5 * (Fd[core, 0, 0].mean() + Fd[core, 1, 1].mean()) - 1.0)
    h0 = x0[top, 2].mean() - x0[bot, 2].mean()
    h = x[top, 2].mean() - x[bot, 2].mean()
    f_plate = rep.collider_force(model, 0, 0)
    area = (a * (1 + lat)) ** 2
    stress = -f_plate[2] / area  # object pushes the plate up (+z): compressive stress is negative
    r1 = _result("uniaxial_stress", "Cauchy stress under the plate vs E * strain", "Pa", stress, E * strain, 0.05)
    r1.passed = r1.passed and ok
    r1.details = {"strain": strain, "strain_from_height": float((h - h0) / h0), "plate_force_n": f_plate.tolist()}
    r2 = _result("uniaxial_lateral_strain", "lateral strain vs -nu * axial strain", "-", lat, -nu * strain, 0.05)
    r2.passed = r2.passed and ok
    r2.details = {"strain": strain}
    return [r1, r2]


def case_cantilever(quick: bool, device: str) -> CaseResult:
    """Cantilever (nu = 0) under gravity, clamped at x = 0: tip deflection 3 rho g L^4 / (2 E h^2)."""
    L, h = 0.2, 0.02
    per_h = 3 if quick else 4
    dx = h / per_h
    rho = 1000.0
    E = 3 * rho * G * L**4 / (2 * h * h * 0.02 * L)  # chosen for a 2 % of L deflection
    w1 = 3.516 * math.sqrt(E * h * h / (12 * rho * L**4))
    mat = Material(youngs_modulus_pa=E, poisson_ratio=0.0, damping_rate_per_s=2.0 * w1)
    z0 = 0.3
    clamp = box_collider((0.05, 0.1, 0.1), position_m=(-0.05 + 1e-6, h / 2, z0 + h / 2), bonded=True)
    sc = box_scene((0, 0, z0), (L, h, z0 + h), dx / 2, mat, rho, colliders=[clamp], ground=False)
    sim = Simulator(build_model([sc], _cfg(device, dx)))
    x0 = sim.particles(0)["x"].astype(np.float64)
    tip = x0[:, 0] > L - dx / 2
    rep = sim.advance(1.6 * 2 * math.pi / w1)
    x = sim.particles(0)["x"].astype(np.float64)
    measured = -(x[tip, 2].mean() - x0[tip, 2].mean())
    expected = 3 * rho * G * L**4 / (2 * E * h * h)
    res = _result("cantilever_tip_deflection", "tip deflection under self-weight", "m", measured, expected, 0.15)
    res.passed = res.passed and rep.health.ok
    res.details = {"youngs_modulus_pa": E, "steps": rep.steps, "particles": sim.model.n_particles}
    return res


def case_incline(quick: bool, device: str) -> CaseResult:
    """Block on an incline (gravity tilted by theta): sticks if tan(theta) <= mu, slides above; threshold angle."""
    mu = 0.5
    theta_c = math.degrees(math.atan(mu))
    offsets = [-4.0, -1.5, -0.5, 0.5, 1.5, 4.0] if quick else [-5.0, -3.0, -1.5, -0.5, 0.5, 1.5, 3.0, 5.0]
    a = 0.05
    n = 5 if quick else 6
    dx = a / n
    mat = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3)
    scenes = []
    for off in offsets:
        th = math.radians(theta_c + off)
        g = (G * math.sin(th), 0.0, -G * math.cos(th))
        scenes.append(box_scene((0, 0, 0), (a, a, a), dx / 2, mat, 500.0, ground_friction=mu, gravity_m_per_s2=g))
    model = build_model(scenes, _cfg(device, dx))
    sim = Simulator(model)
    T = 0.3
    ok = sim.advance(T / 2).health.ok  # first half: elastic settling of the block on the ground
    x_half = [sim.particles(s)["x"][:, 0].mean() for s in range(len(offsets))]
    rep = sim.advance(T / 2)
    # second half: a sliding block keeps accelerating (rigid: +3 mm at +0.5 deg), a sticking one stays put
    disp = [float(sim.particles(s)["x"][:, 0].mean() - x_half[s]) for s in range(len(offsets))]
    slide_min = 1e-3  # [m]
    slides = [d > slide_min for d in disp]
    angles = [theta_c + o for o in offsets]
    stick_angles = [ang for ang, s in zip(angles, slides) if not s]
    slide_angles = [ang for ang, s in zip(angles, slides) if s]
    consistent = bool(stick_angles and slide_angles and max(stick_angles) < min(slide_angles))
    measured = 0.5 * (max(stick_angles) + min(slide_angles)) if consistent else float("nan")
    err = abs(measured - theta_c) if consistent else float("inf")
    top = max(range(len(offsets)), key=lambda i: angles[i])
    th = math.radians(angles[top])
    a_exp = G * (math.sin(th) - mu * math.cos(th))
    return CaseResult("incline_threshold", "stick/slide threshold angle vs atan(mu)", "deg", measured, theta_c, err,
                      2.0, bool(consistent and err <= 2.0 and ok and rep.health.ok), error_kind="absolute",
                      details={"angles_deg": angles, "displacement_second_half_m": disp,
                               "steepest_slide_m": disp[top], "steepest_expected_rigid_m": 0.375 * a_exp * T * T})


def case_grasp(quick: bool, device: str) -> CaseResult:
    """Two-jaw grasp: the block held between two plates holds iff 2 mu N >= m g; threshold ratio 2 mu N/(m g)."""
    w = 0.06
    cells = 6 if quick else 8
    dx = w / cells
    E, nu, rho = 3e4, 0.3, 500.0
    mat = Material(youngs_modulus_pa=E, poisson_ratio=nu, damping_rate_per_s=10.0)
    ratios = [0.6, 0.8, 0.9, 1.1, 1.25, 1.5]
    jaw_half = (0.01, 0.05, 0.05)
    z0 = 0.2
    gap = 1.5 * dx
    scenes = []
    for _ in ratios:
        jl = box_collider(jaw_half, position_m=(-jaw_half[0] - gap, w / 2, z0 + w / 2), friction=0.0)
        jr = box_collider(jaw_half, position_m=(w + jaw_half[0] + gap, w / 2, z0 + w / 2), friction=0.0)
        scenes.append(box_scene((0, 0, z0), (w, w, z0 + w), dx / 2, mat, rho, colliders=[jl, jr], ground=False,
                                gravity_m_per_s2=(0.0, 0.0, 0.0)))
    model = build_model(scenes, _cfg(device, dx))
    sim = Simulator(model)
    B = len(ratios)
    squeeze = gap + 0.05 * w / 2  # per jaw: close the gap, then 5 % strain in total
    t_sq = 0.08
    for s in range(B):
        sim.control.set_collider(s, 0, linear_velocity_m_per_s=(squeeze / t_sq, 0, 0))
        sim.control.set_collider(s, 1, linear_velocity_m_per_s=(-squeeze / t_sq, 0, 0))
    ok = sim.advance(t_sq).health.ok
    for s in range(B):
        for j in range(2):
            sim.control.set_collider(s, j, linear_velocity_m_per_s=(0, 0, 0))
    ok = ok and sim.advance(0.1).health.ok
    rep = sim.advance(0.02)
    mg = model.scene_mass_kg * G
    n_squeeze = np.array([0.5 * (abs(rep.collider_force(model, s, 0)[0]) + abs(rep.collider_force(model, s, 1)[0]))
                          for s in range(B)])
    for s, r in enumerate(ratios):
        mu = r * mg[s] / (2 * n_squeeze[s])
        model.set_collider_friction(s, 0, mu)
        model.set_collider_friction(s, 1, mu)
    z_start = np.array([sim.particles(s)["x"][:, 2].mean() for s in range(B)])
    ramp = 10
    for k in range(1, ramp + 1):
        for s in range(B):
            sim.control.set_gravity(s, (0.0, 0.0, -G * k / ramp))
        rep = sim.advance(0.05 / ramp)
        ok = ok and rep.health.ok
    # normal force once the full weight is on (before a failing grasp has slid far)
    n_hold = np.array([0.5 * (abs(rep.collider_force(model, s, 0)[0]) + abs(rep.collider_force(model, s, 1)[0]))
                       for s in range(B)])
    ok = ok and sim.advance(0.2).health.ok
    slip = np.array([z_start[s] - sim.particles(s)["x"][:, 2].mean() for s in range(B)])
    mus = [float(model.col_mu_np[model.collider_index(s, 0)]) for s in range(B)]
    r_meas = [2 * mus[s] * n_hold[s] / mg[s] for s in range(B)]
    holds = [bool(slip[s] < 2e-3) for s in range(B)]  # a failing grasp slides > 1 cm in 0.2 s
    fail_r = [r for r, hd in zip(r_meas, holds) if not hd]
    hold_r = [r for r, hd in zip(r_meas, holds) if hd]
    consistent = bool(fail_r and hold_r and max(fail_r) < min(hold_r))
    measured = 0.5 * (max(fail_r) + min(hold_r)) if consistent else float("nan")
    res = _result("grasp_threshold", "hold threshold of 2 mu N / (m g)", "-", measured, 1.0, 0.10)
    res.passed = bool(res.passed and consistent and ok)
    res.details = {"ratio_2muN_over_mg": r_meas, "holds": holds, "slip_m": slip.tolist(),
                   "squeeze_force_n": n_squeeze.tolist(), "weight_n": mg.tolist()}
    return res


CASES: dict[str, Callable[[bool, str], CaseResult | list[CaseResult]]] = {
    "free_fall": case_free_fall,
    "momentum_conservation": case_momentum,
    "bar_period": case_bar_period,
    "viscous_decay": case_viscous_decay,
    "column_settlement": case_column_settlement,
    "uniaxial_compression": case_uniaxial_compression,
    "cantilever": case_cantilever,
    "incline": case_incline,
    "grasp": case_grasp,
}


def run_case(name: str, quick: bool = True, device: str = "cpu") -> list[CaseResult]:
    """Run one case by name; returns its result(s) with wall time."""
    t = time.perf_counter()
    out = CASES[name](quick, device)
    results = out if isinstance(out, list) else [out]
    el = time.perf_counter() - t
    for r in results:
        r.seconds = el / len(results)
    return results


def run_suite(quick: bool = False, device: str = "cpu", names: list[str] | None = None) -> list[CaseResult]:
    """Run the analytic suite (all cases or the named ones)."""
    results: list[CaseResult] = []
    for name in names or list(CASES):
        results.extend(run_case(name, quick, device))
    return results
