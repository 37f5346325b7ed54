"""Shared machinery of the MPM probes: the body under test, a batched rollout with sampling, recordings, retries."""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import HealthStatus, ProbeResult, ProbeSpec
from contracts.sim import SimConfig
from tasks.mpm import IntervalReport, SceneSpec, Simulator, build_model, side_by_side
from tasks.probes.metrics import GateTracker, center_of_mass, kinetic_energy
from tasks.probes.workers import probe_workers
from tasks.record import ProbeRecording

RECORDED_FRAMES = 60  # particle frames kept per recording (scalars are logged every sample)


@dataclass(frozen=True)
class DeformableBody:
    """The object under test: rest particles (asset frame: z up, resting on z = 0) and its L1 physical model (SI)."""

    positions_m: np.ndarray  # (N, 3) rest positions [m]
    volumes_m3: np.ndarray  # (N,) rest volumes [m^3]
    spacing_m: float  # particle lattice spacing [m]
    density_kg_per_m3: float
    ground_friction: float = 0.5
    gripper_friction: float = 0.8

    @classmethod
    def from_physical(cls, positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel) -> DeformableBody:
        """A body from L0 particles and the frozen L1 model (density, friction, spacing)."""
        return cls(np.asarray(positions_m, np.float64), np.asarray(volumes_m3, np.float64),
                   float(physical.particle_spacing_m), float(physical.density_kg_per_m3),
                   float(physical.ground_friction), float(physical.gripper_friction))

    @property
    def masses_kg(self) -> np.ndarray:
        """Particle masses m_i = rho V_i [kg]."""
        return self.volumes_m3 * self.density_kg_per_m3

    @property
    def mass_kg(self) -> float:
        """Total mass [kg]."""
        return float(self.masses_kg.sum())

    @property
    def extents_m(self) -> np.ndarray:
        """Bounding-box extents of the body's volume (particle range + one spacing) [m]."""
        return self.positions_m.max(axis=0) - self.positions_m.min(axis=0) + self.spacing_m

    @property
    def height_m(self) -> float:
        """Vertical extent H [m]."""
        return float(self.extents_m[2])


def dx_of(body: DeformableBody, sim: SimConfig) -> float:
    """Grid spacing the engine will use [m] (SimConfig.dx_m, else twice the particle spacing)."""
    return float(sim.dx_m) if sim.dx_m is not None else 2.0 * float(np.mean(body.volumes_m3) ** (1.0 / 3.0))


def fundamental_period_s(body: DeformableBody, material: Material, mass_scale: float = 1.0) -> float:
    """Longest elastic period across the height, 4 H / c with the bar speed c = sqrt(E / (k rho)) [s] (k: the
    rollout's mass scale, 1 unless quasi_static_mass_scale() set one)."""
    return 4.0 * body.height_m / math.sqrt(material.youngs_modulus_pa / (mass_scale * body.density_kg_per_m3))


def sample_interval_s(body: DeformableBody, materials: Sequence[Material], longest_s: float = 5e-3,
                      mass_scales: Sequence[float] | None = None) -> float:
    """Sampling interval: a sixth of the shortest fundamental period, within [1 ms, longest_s]."""
    ks = list(mass_scales) if mass_scales is not None else [1.0] * len(materials)
    t = min(fundamental_period_s(body, m, k) for m, k in zip(materials, ks)) / 6.0
    return float(min(longest_s, max(1e-3, t)))


def quasi_static_mass_scale(body: DeformableBody, material: Material, period_s: float) -> float:
    """Mass scaling of a quasi-static rollout (explicit FEM's classic device for slow loading): the factor k >= 1 that
    makes the body's fundamental period 4H/c at least period_s. The rollout multiplies the density by k and divides
    gravity by k, so every static load (the weight M g, a plate's force, the friction it allows) and the material's
    stresses at a given strain stay as they were, while the elastic waves slow by sqrt(k) and the CFL step grows by
    sqrt(k) (the Kelvin-Voigt viscous step by k). Valid only where inertia plays no part: loading at least ~20 periods
    long, and rests; never for a drop or an accelerated lift. 1 for a body already that slow (a plush toy)."""
    return max(1.0, (period_s / fundamental_period_s(body, material)) ** 2)


def scaled_gravity(sim: SimConfig, mass_scale: float) -> tuple[float, float, float] | None:
    """A scene's gravity under mass scale k: SimConfig's gravity / k (None, SimConfig's own, when k = 1)."""
    if mass_scale == 1.0:
        return None
    gx, gy, gz = sim.gravity_m_per_s2
    return (gx / mass_scale, gy / mass_scale, gz / mass_scale)


@dataclass
class SceneLog:
    """What one scene of a rollout recorded: per-sample time series and its gate tracker."""

    gates: GateTracker
    series: dict[str, list[float]] = field(default_factory=dict)

    def add(self, **values: float) -> None:
        """Append one sample of named scalars."""
        for k, v in values.items():
            self.series.setdefault(k, []).append(float(v))

    def array(self, name: str) -> np.ndarray:
        """One series as an array."""
        return np.asarray(self.series.get(name, []), dtype=np.float64)


class Rollout:
    """A batched MPM rollout of several scenes, sampled at a fixed interval, optionally recorded per scene."""

    def __init__(self, scenes: Sequence[SceneSpec], sim: SimConfig, record_paths: Sequence[Path | None] | None = None,
                 recording_prefix: str = "probe", expected_samples: int = 200) -> None:
        self.model = build_model(list(scenes), sim)
        self.sim = Simulator(self.model)
        self.n = self.model.n_scenes
        self.logs = [SceneLog(GateTracker(ground_z_m=float(self.model.ground_height_np[s]))) for s in range(self.n)]
        self.masses = [self.model.particle_mass_np[self.model.scene_slice(s)].astype(np.float64) for s in range(self.n)]
        paths = list(record_paths or [None] * self.n)
        self.recordings: list[ProbeRecording | None] = []
        for s, p in enumerate(paths):
            rec = ProbeRecording(p, f"{recording_prefix}-{s}-{time.time_ns()}") if p is not None else None
            if rec is not None:
                rec.__enter__()
            self.recordings.append(rec)
        self.frame = 0
        self.every = max(1, expected_samples // RECORDED_FRAMES)
        self.wall_start = time.perf_counter()
        self.last: IntervalReport | None = None

    @property
    def time_s(self) -> float:
        """Simulation time [s]."""
        return self.sim.time_s

    @property
    def ok(self) -> bool:
        """False once the engine stopped on a fatal health issue."""
        return self.sim.health.ok

    def advance(self, interval_s: float) -> tuple[IntervalReport, list[dict[str, np.ndarray]]]:
        """Advance one interval, sample every scene (gates, recording) and return the report and particle states."""
        rep = self.sim.advance(interval_s)
        self.last = rep
        states = [self.sim.particles(s) for s in range(self.n)]
        self.frame += 1
        for s, st in enumerate(states):
            self.logs[s].gates.sample(st["x"], st["F"], on_ground=bool(self.model.ground_enabled_np[s]))
            rec = self.recordings[s]
            if rec is not None:
                rec.set_time(self.frame, self.time_s)
                if self.frame % self.every == 0:
                    rec.particles(st["x"], radius_m=0.25 * self.model.dx)
                    for i in range(int(self.model.col_count_np[s])):
                        c = self.model.collider_index(s, i)
                        spec = self.model.collider_specs[c]
                        pos, q = self.sim.control.collider_pose(c, self.time_s)
                        if spec.kind == "box":
                            rec.box_collider(spec.name or f"collider_{i}", pos, np.asarray(spec.size_m), q)
                rec.scalar("kinetic_energy_j", kinetic_energy(st["v"], self.masses[s]))
                rec.scalar("com_z_m", float(center_of_mass(st["x"], self.masses[s])[2]))
                rec.scalar("ground_force_z_n", float(rep.ground_force_n[s][2]))
        return rep, states

    def scalar(self, scene: int, name: str, value: float) -> None:
        """Log a probe-specific scalar into a scene's recording (if it has one)."""
        rec = self.recordings[scene]
        if rec is not None:
            rec.scalar(name, value)

    def failed_checks(self, scene: int) -> list[str]:
        """Names of the fatal engine checks that concern a scene."""
        return [i.check for i in self.sim.health.issues if i.scene == scene]

    def health(self, scene: int) -> HealthStatus:
        """The scene's health in the contract's form."""
        issue = self.sim.health.first(scene)
        if issue is None:
            return HealthStatus(ok=True)
        return HealthStatus(ok=False, check=issue.check, step=issue.step, sim_time_s=issue.sim_time_s, scene=scene,
                            particle=issue.particle, detail=issue.detail)

    def gate_metrics(self, scene: int) -> dict[str, float]:
        """Gate metrics of a scene (its samples + the engine checks that concern it)."""
        return self.logs[scene].gates.metrics(self.sim.health.scene_ok(scene), self.failed_checks(scene))

    def close(self, messages: Sequence[str] | None = None) -> None:
        """Write the harness log lines and close every recording."""
        for s, rec in enumerate(self.recordings):
            if rec is None:
                continue
            for line in messages or []:
                rec.log(line)
            h = self.health(s)
            rec.log(f"health ok={h.ok} check={h.check} t={h.sim_time_s}", level="INFO" if h.ok else "WARN")
            rec.__exit__(None, None, None)

    @property
    def wall_s(self) -> float:
        """Wall time since the rollout started [s]."""
        return time.perf_counter() - self.wall_start


ProbeImpl = Callable[[Sequence[Material], Sequence[Path | None]], list[ProbeResult]]


def run_batched(impl: ProbeImpl, materials: Sequence[Material], record_paths: Sequence[Path | None] | None) -> list[ProbeResult]:
    """Run a probe over a batch of materials (one batched rollout = one simulation call). The engine stops a batch at
    the first failed scene, so the scenes cut short by another's failure run again without it (their sim_calls and
    wall time include the aborted batch)."""
    paths = list(record_paths or [None] * len(materials))
    results = impl(list(materials), paths)
    failed = [i for i, r in enumerate(results) if not r.health.ok]
    if not failed or len(failed) == len(results):
        return results
    rest = [i for i in range(len(results)) if i not in failed]
    again = run_batched(impl, [materials[i] for i in rest], [paths[i] for i in rest])
    out = list(results)
    for i, r in zip(rest, again):
        out[i] = r.model_copy(update={"sim_calls": r.sim_calls + 1, "wall_time_s": r.wall_time_s + results[i].wall_time_s})
    return out


# -- candidate scheduling ---------------------------------------------------------------------------------------------
# A lock-step batch advances every scene at the smallest stable time step of the batch (the stiffest candidate's CFL dt)
# for the longest duration any scene needs (the softest candidate's periods, the slowest to settle). Candidates with
# the same time step (a damping sweep) share launches and sampling and gain from a batch; a stiffness sweep does not
# (turtle, draft, firm rubber, 2-core CPU: E x 1/3, 1, 3 batched 50.0 s, one after another 39.3 s; three damping rates
# batched 35.6 s, one after another 41.0 s: `python -m benchmarks.l2_schedule`, tasks/probes/BENCHMARKS.md). Threads do not help
# on the CPU (two probes in two threads took 6.1 s against 4.6 s one after another); threads sharing one rollout's
# particles do (SimConfig.cpu_threads, tasks/mpm/cpu_threads.py: 1.4-1.8x on 2 cores at 64k particles).
SCHEDULES = ("auto", "batch", "grouped", "sequential")
BATCH_DT_REL_TOL = 0.02  # candidates whose stable dt and fundamental period agree within 2 % may share a rollout


def _signature(body: DeformableBody, material: Material) -> tuple[float, float]:
    """(dilatational wave speed c_p [m/s], fundamental period [s]): what sets a candidate's time step and durations."""
    return material.p_wave_speed_m_per_s(body.density_kg_per_m3), fundamental_period_s(body, material)


def plan_batches(body: DeformableBody, materials: Sequence[Material], sim: SimConfig | None = None,
                 schedule: str = "auto") -> list[list[int]]:
    """Which candidates share one lock-step rollout (lists of indices into materials, in a deterministic order).

    batch       one rollout of all candidates (the stiffest dt, the longest duration for every scene)
    grouped     one rollout per set of candidates with the same time step and periods (within BATCH_DT_REL_TOL,
                i.e. the same E and nu; e.g. a damping sweep), the sets one after another
    sequential  one rollout per candidate, one after another
    auto        grouped (the fastest measured on the CPU; on CUDA it keeps equal-dt candidates together)
    """
    if schedule not in SCHEDULES:
        raise ValueError(f"unknown schedule '{schedule}'; choose one of {', '.join(SCHEDULES)}")
    n = len(materials)
    if schedule == "auto":
        schedule = "grouped"
    if schedule == "batch" or n <= 1:
        return [list(range(n))] if n else []
    if schedule == "sequential":
        return [[i] for i in range(n)]
    groups: list[list[int]] = []
    sigs: list[tuple[float, float]] = []
    for i, m in enumerate(materials):
        sig = _signature(body, m)
        for g, ref in zip(groups, sigs):
            if all(abs(a - b) <= BATCH_DT_REL_TOL * max(abs(a), abs(b)) for a, b in zip(sig, ref)):
                g.append(i)
                break
        else:
            groups.append([i])
            sigs.append(sig)
    return groups


def run_scheduled(impl: ProbeImpl, materials: Sequence[Material], record_paths: Sequence[Path | None] | None,
                  body: DeformableBody, sim: SimConfig | None = None, schedule: str = "auto") -> list[ProbeResult]:
    """Run a probe over candidates as planned by plan_batches: each group one batched rollout (run_batched), the groups
    side by side on the CPU (tasks.probes.workers; a group's result is the same as alone: deterministic). Results come
    back in the order of `materials`; each result's sim_calls counts the rollouts it took part in (a batch of 3 is one
    simulation call: see rollouts())."""
    mats = list(materials)
    paths = list(record_paths or [None] * len(mats))
    out: list[ProbeResult | None] = [None] * len(mats)
    groups = plan_batches(body, mats, sim, schedule)
    jobs = [functools.partial(run_batched, impl, [mats[i] for i in g], [paths[i] for i in g]) for g in groups]
    device = sim.device if sim is not None else "cpu"
    for group, results in zip(groups, side_by_side(jobs, probe_workers(len(jobs), device), device)):
        for i, r in zip(group, results):
            out[i] = r
    return [r for r in out if r is not None]


def rollouts(groups: Sequence[Sequence[int]], results: Sequence[ProbeResult]) -> int:
    """Simulation calls a scheduled run made: per group, its first rollout plus the reruns without failed scenes (the
    scenes of the deepest rerun carry the group's count in their sim_calls)."""
    return sum(max(results[i].sim_calls for i in g) for g in groups if g)


def make_result(kind: str, params: dict[str, float], metrics: dict[str, float], health: HealthStatus, wall_s: float,
                held_out: bool = False, duration_s: float | None = None) -> ProbeResult:
    """A ProbeResult with only finite metrics (a metric that could not be measured is left out)."""
    clean = {k: float(v) for k, v in metrics.items() if v is not None and math.isfinite(float(v))}
    spec = ProbeSpec(kind=kind, params=dict(params), held_out=held_out, duration_s=duration_s)
    return ProbeResult(spec=spec, metrics=clean, health=health, sim_calls=1, wall_time_s=float(wall_s))


__all__ = ["SCHEDULES", "DeformableBody", "Rollout", "SceneLog", "dx_of", "fundamental_period_s", "make_result",
           "plan_batches", "quasi_static_mass_scale", "rollouts", "run_batched", "run_scheduled", "sample_interval_s",
           "scaled_gravity"]
