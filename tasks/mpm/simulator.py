"""Simulator: drives a Solver over reporting intervals with CFL time steps, health checks and reaction forces."""

from __future__ import annotations

import contextvars
import functools
import math
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from tasks.mpm.control import Control
from tasks.mpm.cpu_launch import load_cpu_modules
from tasks.mpm.health import FATAL, FLAG_NAMES, HealthIssue, HealthStatus
from tasks.mpm.model import Model
from tasks.mpm.solver import INT_MAX, Solver
from tasks.mpm.state import State

T = TypeVar("T")

OUT_OF_GRID = FLAG_NAMES.index("out_of_grid")


@dataclass
class IntervalReport:
    """What one ``advance`` produced. Forces are the mean forces the OBJECT exerts ON the ground / colliders [N].

    f = -(1/dt_k) sum J_c, where J_c = m_node (v+ - v) is the impulse each contact gives the object and dt_k the
    interval's duration; a finger squeezing the object in +x reports a force along -x (into the finger).
    """

    t_start_s: float
    t_end_s: float
    steps: int
    dt_last_s: float
    ground_force_n: np.ndarray  # (B, 3)
    collider_force_n: np.ndarray  # (n_colliders, 3), global collider order (Model.collider_index)
    health: HealthStatus

    def collider_force(self, model: Model, scene: int, index: int) -> np.ndarray:
        """Mean force [N] that the object of a scene exerted on its index-th collider."""
        return self.collider_force_n[model.collider_index(scene, index)]


class Simulator:
    """A rollout of B batched scenes: ``advance(duration)`` steps with adaptive (or fixed) dt and checks health."""

    def __init__(
        self,
        model: Model,
        state: State | None = None,
        control: Control | None = None,
        health_interval_steps: int = 100,
        use_graph: bool | None = None,
    ) -> None:
        self.model = model
        self.config = model.config
        self.state = state if state is not None else model.state()
        self.control = control if control is not None else model.control()
        self.solver = Solver(model, use_graph=use_graph)
        self.health_interval_steps = max(1, int(health_interval_steps))
        self.health = HealthStatus()
        self._step_time: dict[int, float] = {}
        stats = self.solver.scene_stats(self.state)
        self._vmax = float(np.max(stats["speed_max"]))
        self._ke0 = stats["kinetic"].copy()
        self._z_top0 = stats["bmax"][:, 2].copy()
        ext = np.max(stats["bmax"] - stats["bmin"], axis=1)
        sizes = [float(np.max(np.abs(c.size_m))) for c in model.collider_specs] or [0.0]
        self._reach = float(2.0 * np.max(ext) + max(sizes))
        self._since_check = 0
        self._vcol_seen = 0.0

    @property
    def time_s(self) -> float:
        """Simulation time [s]."""
        return self.solver.time_s

    @property
    def steps(self) -> int:
        """Steps taken so far."""
        return self.solver.steps

    def stable_dt(self) -> float:
        """Time step [s]: fixed if configured, else min(dt_max, C dx / (c_p + |v|max + collider speed), the viscous
        limit k rho dx^2 / eta) / substeps."""
        cfg = self.config
        if cfg.dt_fixed_s is not None:
            return cfg.dt_fixed_s / cfg.substeps
        speed = self.model.max_wave_speed() + self._vmax + self.control.max_collider_speed(self._reach)
        return min(cfg.dt_max_s, cfg.cfl * self.model.dx / speed, self.model.viscous_dt_s) / cfg.substeps

    def advance(self, duration_s: float, max_steps: int | None = None) -> IntervalReport:
        """Advance by duration_s [s] (the last step is shortened to land on it); stops early on a fatal issue."""
        if not (duration_s >= 0.0) or not math.isfinite(duration_s):
            raise ValueError("duration must be a finite non-negative number of seconds")
        solver = self.solver
        t0 = self.time_s
        t_end = t0 + duration_s
        solver.ground_impulse.zero_()
        solver.collider_impulse.zero_()
        steps = 0
        dt = 0.0
        while self.health.ok:
            if max_steps is not None and steps >= max_steps:
                break
            dt_nom = self.stable_dt()
            remaining = t_end - self.time_s
            if remaining <= 1e-4 * dt_nom:
                break
            if remaining <= 1.001 * dt_nom:
                # land on t_end: take the remainder if it is within 0.1 % of a full step (float32 dt rounding)
                dt, n = remaining, 1
            else:
                dt = dt_nom
                dt32 = float(np.float32(dt_nom))
                n = max(1, int(remaining / dt32 - 1e-6))
                n = min(n, self.health_interval_steps - self._since_check)
                if max_steps is not None:
                    n = min(n, max_steps - steps)
            t_before, s_before = solver.time_s, solver.steps
            solver.advance_steps(self.state, self.control, dt, n)
            dt_used = (solver.time_s - t_before) / n
            for k in range(1, n + 1):
                self._step_time[s_before + k] = t_before + k * dt_used
            steps += n
            self._since_check += n
            if self._since_check >= self.health_interval_steps:
                self.check_health()
        self.check_health()
        g, c = solver.read_impulses(reset=True)
        span = self.time_s - t0
        scale = -1.0 / span if span > 0 else 0.0
        return IntervalReport(
            t_start_s=t0,
            t_end_s=self.time_s,
            steps=steps,
            dt_last_s=dt,
            ground_force_n=g * scale,
            collider_force_n=c * scale,
            health=self.health,
        )

    def check_health(self) -> HealthStatus:
        """Read the device failure flags and per-scene stats (one sync); grow the grid if the object outgrew it."""
        self._since_check = 0
        solver = self.solver
        model = self.model
        fstep, fpart, stats = solver.health_snapshot(self.state)
        self._vmax = float(np.max(np.where(np.isfinite(stats["speed_max"]), stats["speed_max"], 0.0)))
        new_issues: list[HealthIssue] = []
        for s in range(model.n_scenes):
            for code, name in enumerate(FLAG_NAMES):
                st = int(fstep[s, code])
                if st >= INT_MAX:
                    continue
                t = self._step_time.get(st, self.time_s)
                issue = HealthIssue(name, s, st, t, int(fpart[s, code]), _detail(name, model))
                if name in FATAL:
                    if not any(i.check == name and i.scene == s for i in self.health.issues):
                        new_issues.append(issue)
                else:
                    self.health.warnings.append(issue)
            ke = float(stats["kinetic"][s])
            budget = self._energy_budget(s)
            if not (ke <= self.config.energy_growth_max * budget):
                if not any(i.check == "energy_blowup" and i.scene == s for i in self.health.issues):
                    new_issues.append(
                        HealthIssue("energy_blowup", s, solver.steps, self.time_s, None,
                                    f"kinetic energy {ke:.3g} J > {self.config.energy_growth_max} x budget "
                                    f"{budget:.3g} J")
                    )
        new_issues.sort(key=lambda i: (i.step, i.scene))
        self.health.issues.extend(new_issues)
        if self.health.issues:
            self.health.ok = False
        if np.any(fstep[:, OUT_OF_GRID] < INT_MAX) or np.any(stats["overflow"]):
            if self.health.ok:
                ext = np.max(stats["bmax"] - stats["bmin"], axis=0) / model.dx
                solver.grow_grid(ext)
                solver.refit(self.state)
            solver.clear_flag(OUT_OF_GRID)
        self.health.steps = solver.steps
        self.health.sim_time_s = self.time_s
        self._step_time.clear()
        return self.health

    def _energy_budget(self, s: int) -> float:
        """Energy [J] scene s may legitimately turn into kinetic energy (generous: a blow-up exceeds it by far).

        Initial KE + M |g| (drop to the ground + reach) + M/2 (fastest collider speed seen + 0.1 c_p)^2.
        """
        model = self.model
        m = float(model.scene_mass_kg[s])
        g = max(float(np.linalg.norm(self.control.gravity[s])), float(np.linalg.norm(model.gravity_np[s])))
        z_low = float(model.ground_height_np[s]) if model.ground_enabled_np[s] else float(model.domain_lo_np[s, 2])
        drop = max(0.0, float(self._z_top0[s]) - z_low) + self._reach
        self._vcol_seen = max(self._vcol_seen, self.control.max_collider_speed(self._reach))
        # elastic energy a collider may store and release: up to ~10 % strain, i.e. a speed of 0.1 c_p
        v_ref = self._vcol_seen + 0.1 * float(model.p_wave_speed[s])
        return float(self._ke0[s]) + m * g * drop + 0.5 * m * v_ref**2

    def particles(self, scene: int | None = None) -> dict[str, np.ndarray]:
        """Host copies of x [m], v [m/s], F of all particles or of one scene."""
        return self.state.numpy(self.model, scene)


def _detail(name: str, model: Model) -> str:
    """Human-readable description of a failed check."""
    cfg = model.config
    return {
        "nonfinite": "NaN or inf in particle state",
        "left_domain": "particle left the allowed domain",
        "j_out_of_bounds": f"det(F) outside [{cfg.j_min}, {cfg.j_max}]",
        "out_of_grid": "particle stencil left the grid window (grid enlarged; particle moved ballistically)",
    }.get(name, "")


def side_by_side(jobs: Sequence[Callable[[], T]], workers: int = 1, device: str | None = "cpu") -> list[T]:
    """Run each job and return the results in order; up to `workers` at a time in threads (Warp's CPU launches release
    the GIL), each in a copy of the caller's context (a Prefect task called inside a flow run stays a task run of that
    flow). device="cpu": the jobs launch CPU kernels, so the engine's modules are loaded first (no two threads may load
    a Warp module at once: tasks.mpm.cpu_launch.load_cpu_modules). An exception in any job is raised after the others
    have finished."""
    if workers <= 1 or len(jobs) <= 1:
        return [job() for job in jobs]
    if device == "cpu":
        load_cpu_modules()
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="side-by-side") as pool:
        futures = [pool.submit(contextvars.copy_context().run, job) for job in jobs]
        return [f.result() for f in futures]


def advance_parallel(sims: Sequence[Simulator], duration_s: float) -> list[IntervalReport]:
    """Advance several independent simulators concurrently in threads (Warp CPU launches release the GIL)."""
    device = sims[0].model.device if sims else "cpu"
    return side_by_side([functools.partial(s.advance, duration_s) for s in sims], len(sims), device)
