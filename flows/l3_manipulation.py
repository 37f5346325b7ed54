"""L3 manipulation flow: grasp ranking -> plan -> pick-and-place trial in the MPM (cached task) -> gates -> revision.

Reads L0 (geometry), L1 (physical.json, frozen) and L2 (material.json, or the vocabulary prior when L2 has not run).
Action revisions (grasp rank, squeeze, timing) and numerical revisions (substeps: dt / n, same durations) are
re-evaluated here by the harness; a material revision (a gate only the material can fix: deformation bound) goes back
through L2 revalidation (``flows.l2_material.evaluate_material``: exactly the L2 probes re-execute) and is then confirmed
by the robot under the same plan, physical model and force budget. An accepted plan is tried under two robustness
conditions (other yaws, training only); when one fails, or when no plan passed at all, L3 asks L2 for a material
inside its target bands (flows.l3_material: stiffer against a slip, more damping against an object that rolls on),
revalidated by L2 on its gates and bands, and adopts it only when the robot then does better. The final plan is then
evaluated under held-out conditions (other target positions and initial yaw), recorded apart. Writes ``manipulation.json``, ``interaction/``
(one Zarr group per trial, failures kept), ``evidence/`` (harness attempt lines) and ``recordings/L3_*.rrd``.
"""

from __future__ import annotations

import functools
import math
import os
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, TypedDict, cast

import numpy as np
import trimesh

import cache
from cache import cached_task
from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig, StageOutcome, TargetBehaviour
from contracts.asset_dir import attempt_path
from contracts.manipulation import (BestAttempt, ConditionRow, ConditionSummary, GripperChoice, GripperOption,
                                    HeldOutConditions, L2Check, L3Numerics, ManipulationRecord, MaterialRevision,
                                    SqueezeSummary, TrialCondition, TrialRow)
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, ProbeSpec
from contracts.robot import ActionPlan, GraspCandidate
from contracts.shape import ShapeProgram
from contracts.sim import SimConfig
from contracts.stage import L3Parameters, StageContract, load_contract, packaged_parameters
from flows.harness import call_tasks, probe_cache_key, run_harness
from flows.l3_material import MaterialLimits, failed_gates, halfway, revalidate_in_l2, revise_material
from flows.l3_report import (L3Progress, Progress, best_attempt, failed_gate_names, planned_trials, record_no_grasp,
                             trial_reason)
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset
from tasks.manipulation.body import TrialBody, auto_trial_spacing, trial_body
from tasks.manipulation.diagnosis import MODES
from tasks.manipulation.data import attempt_indices, interaction_root, write_attempt
from tasks.manipulation.recordings import record_attempt
from tasks.manipulation.outcome import TrialTolerances, force_budget_n
from tasks.manipulation.trial import TrialSettings, plan_or_error, reachable_plan, run_trial
from tasks.probes.workers import probe_workers
from contracts.robot import DEFAULT_GRIPPER
from tasks.robot import NoGraspError, select_grasps
from tasks.robot.grasp import GraspSettings
from tasks.robot.choice import choose_gripper, grasp_settings
from tasks.robot.grasp_parts import body_first_grasps
from tasks.robot.gripper import gripper
from tasks.robot.squeeze import SqueezePlan, squeeze_plan

TASK_VERSION = "12"  # bump when tasks/manipulation/{trial,outcome,body,frame}.py change what a trial returns
# (6: settle until at rest; 7: simulated in the frame where the closing axis is at 45 degrees to the grid; 8: the
# approach is recorded; 9: grippers as data, a force-controlled closure that keeps its target while held and skips the
# rest of the closure, the time-step cap follows dx; 10: the hold's contact stiffness measured from where the force
# began to rise, what-happened metrics and failure-mode flags (tasks.manipulation.diagnosis); 11: release_rotation_deg;
# 12: a what-happened figure that does not exist is absent, not NaN)
PICK_AND_PLACE_RECORDING = "recordings/L3_pick_and_place.rrd"  # the chosen trial's recording
CORE_FIELDS = ("grasp_rank", "squeeze_depth_m", "closing_speed_m_per_s", "lift_duration_s", "transport_duration_s",
               "substeps")  # the plan's fields every L3 contract has
LABELS = ("lifted", "transported", "released_in_target", "settled", "numerically_healthy")


@dataclass(frozen=True)
class L3Options:
    """How L3 runs: trial numerics, the draft action timing, the first squeeze, place target and held-out conditions."""

    quality: str = "draft"
    # trial lattice; None = auto: a grid of at most half the Panda pad's 17 mm face (spacing <= 4 mm) and at least
    # 12 particles across the object's smallest extent (tasks.manipulation.body.auto_trial_spacing)
    particle_spacing_m: float | None = None
    settings: TrialSettings = field(default_factory=TrialSettings)
    squeeze_fraction: float = 0.12         # first squeeze depth per finger as a fraction of the grasp width
    squeeze_depth_m: float | None = None   # overrides the fraction
    closing_speed_m_per_s: float = 0.04
    lift_duration_s: float = 0.5
    transport_duration_s: float = 0.6
    release_duration_s: float = 0.2
    # the object's resting pose + this when the fingers open [m]: set down on the table, not dropped (a 1 cm drop made
    # a zero-damping rubber duck walk 70 mm and a plush penguin fall over; the revise_release route lowers it further
    # only if a contract starts higher)
    place_height_m: float = 0.0
    retreat_duration_s: float = 0.2
    settle_duration_s: float = 0.2
    target_xy_m: tuple[float, float] = (0.08, 0.06)
    held_out: tuple[tuple[float, float, float], ...] = ((0.06, -0.08, 30.0),)  # (x [m], y [m], yaw [deg])
    # training conditions the accepted plan is also tried under (a grasp that holds by a hair at one yaw slips at
    # the next); a failure asks L2 for a material with more margin; distinct from every held-out condition
    robustness: tuple[tuple[float, float, float], ...] = ((0.08, 0.06, 45.0), (0.08, 0.06, -75.0))
    material_fallback: bool = True  # when no plan passes, ask L2 for a material within its bands (flows.l3_material)
    device: str = "cpu"
    cpu_threads: int = 1  # CPU: threads sharing each trial's particles (SimConfig.cpu_threads; 1 on CUDA)
    gripper: str | None = None  # contracts/grippers/<name>.yaml; None: the Planner's choose_gripper
    # (tasks.robot.choice)

    def __post_init__(self) -> None:
        if self.device != "cpu":  # as SimConfig: CPU threads mean nothing on CUDA, and must not split cache keys
            object.__setattr__(self, "cpu_threads", 1)

    def sim(self) -> SimConfig:
        """L2's settings for a revalidation from L3: the same device and CPU threads as the trials."""
        return SimConfig(device=self.device, cpu_threads=self.cpu_threads)

    @classmethod
    def standard(cls, device: str = "cuda", cpu_threads: int = 1) -> L3Options:
        """Standard quality: finer particles, the ActionPlan's default (slower) timing, two held-out conditions."""
        return cls(quality="standard", particle_spacing_m=0.002, closing_speed_m_per_s=0.02, lift_duration_s=1.0,
                   transport_duration_s=1.5, release_duration_s=0.5, retreat_duration_s=0.5, settle_duration_s=0.5,
                   held_out=((0.06, -0.08, 30.0), (-0.02, 0.12, -45.0)), device=device, cpu_threads=cpu_threads,
                   settings=TrialSettings(device=device))


def settings_inputs(settings: TrialSettings) -> dict[str, Any]:
    """Trial settings as task inputs; one CPU thread is left out, so earlier trials' cache keys still hold."""
    out = asdict(settings)
    if out.get("cpu_threads") == 1:
        out.pop("cpu_threads")
    return out


def body_inputs(body: TrialBody) -> dict[str, Any]:
    """The trial body as hashable task inputs (arrays and numbers)."""
    return {"particles_m": body.particles_m, "volumes_m3": body.volumes_m3, "spacing_m": body.spacing_m,
            "source_spacing_m": body.source_spacing_m, "height_m": body.height_m,
            "gaussians": {k: np.asarray(v) for k, v in body.gaussians.items()}}


def _body_from(particles_m: np.ndarray, volumes_m3: np.ndarray, spacing_m: float, source_spacing_m: float,
               height_m: float, gaussians: dict[str, np.ndarray]) -> TrialBody:
    """Rebuild the TrialBody inside the task (surface samples are not needed there)."""
    empty = np.zeros((0, 3))
    return TrialBody(particles_m, volumes_m3, spacing_m, source_spacing_m, empty, empty, height_m, gaussians)


def failed_metrics(reason: str) -> dict[str, float]:
    """Metrics of a plan that could not be executed: every label failed, the force unknown."""
    return {"lifted": 0.0, "transported": 0.0, "released_in_target": 0.0, "settled": 0.0, "slipped": 1.0,
            "force_budget_violated": 0.0, "numerically_healthy": 1.0, "max_strain": 0.0, "strain_p99": 0.0,
            "max_finger_force_n": math.nan, "plan_failed": 1.0,
            **{f"mode_{m}": float(m == "plan_failed") for m in MODES}}


@cached_task(version=TASK_VERSION, name="l3.trial")
def trial_task(particles_m: np.ndarray, volumes_m3: np.ndarray, spacing_m: float, source_spacing_m: float,
               height_m: float, gaussians: dict[str, np.ndarray], physical: PhysicalModel, material: Material,
               plan: ActionPlan, settings: dict[str, Any], tolerances: dict[str, float]) -> dict[str, Any]:
    """One pick-and-place in the MPM: {'probe': ProbeResult, 'arrays': recorded arrays, 'info': numerics}."""
    body = _body_from(particles_m, volumes_m3, spacing_m, source_spacing_m, height_m, gaussians)
    s, tol = TrialSettings(**settings), TrialTolerances(**tolerances)
    spec = ProbeSpec(kind="pick_and_place", params={"squeeze_depth_m": plan.squeeze_depth_m,
                                                    "target_x_m": plan.target_xy_m[0],
                                                    "target_y_m": plan.target_xy_m[1],
                                                    "initial_yaw_deg": plan.initial_yaw_deg,
                                                    "substeps": float(s.substeps)})
    traj, why = plan_or_error(plan, body, s)
    if traj is None:
        return {"probe": ProbeResult(spec=spec, metrics=failed_metrics(why), sim_calls=0), "arrays": {},
                "info": {"plan_error": why}}
    r = run_trial(body, physical, material, plan, s, tol, traj)
    probe = ProbeResult(spec=spec, metrics=r.metrics, wall_time_s=cast(float, r.info["wall_time_s"]))
    return {"probe": probe, "arrays": r.arrays, "info": r.info}


@functools.cache
def _attempt_code() -> str:
    """The code part of an encoded attempt's cache key: the encoder's sources and the libraries that write it."""
    from cache.files import source_digest

    root = Path(__file__).resolve().parent.parent / "tasks" / "manipulation"
    return source_digest([root / "data.py", root / "particle_frames.py"], ("numcodecs", "numpy", "zarr"))


def store_attempt(asset_dir: Path, arrays: dict[str, np.ndarray], attrs: dict[str, Any]) -> int:
    """Store a trial as the asset's next interaction attempt (tasks.manipulation.data.write_attempt) through the cache:
    a rerun copies the attempt encoded before from the same arrays, attributes, index and encoder code instead of
    compressing its particle frames again (~0.3-1 s a trial on two cores). Returns the attempt's index."""
    import json

    from cache import content_key
    from cache.files import cached_file

    n = max(attempt_indices(asset_dir), default=-1) + 1
    interaction_root(asset_dir)
    attrs_json = json.dumps({**attrs, "attempt": n}, sort_keys=True,
                            default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    key = content_key("l3.interaction_attempt/1", _attempt_code(), {k: np.asarray(v) for k, v in arrays.items()},
                      attrs_json)
    cached_file(key, Path(asset_dir) / attempt_path(n), lambda _: write_attempt(asset_dir, arrays, attrs, index=n))
    return n


def tolerances_from(contract: StageContract) -> TrialTolerances:
    """Label limits from the L3 contract (parameters and the force-budget gate)."""
    p = L3Parameters.of(contract)
    return TrialTolerances(lift_height_m=p.lift_height_m, place_tolerance_m=p.place_tolerance_m,
                           slip_tolerance_m=p.slip_tolerance_m, force_budget_n=force_budget_n(contract))


@dataclass
class L3Context:
    """Everything a trial needs that L3 does not edit."""

    asset_dir: Path
    body: TrialBody
    physical: PhysicalModel
    material: Material
    material_source: str
    grasps: list[GraspCandidate]
    options: L3Options
    contract: StageContract
    attempts: list[TrialRow] = field(default_factory=list)
    recordings: bool = True  # each stored trial also gets recordings/L3_trial_NN.rrd (tasks.manipulation.recordings)
    gripper: str = DEFAULT_GRIPPER
    gripper_reason: str = ""
    grasp_reason: str = ""  # the part the grasps hold and why (tasks.robot.grasp_parts), '' when not a toy or animal
    squeeze: SqueezePlan | None = None  # the force target and stiffness-scaled squeeze range of the best grasp
    gripper_options: list[GripperOption] = field(default_factory=list)  # what choose_gripper weighed
    progress: L3Progress = field(default_factory=L3Progress)
    l0: L0Asset | None = None  # the L0 data the body was built from (L2's revalidation probes it too)

    @property
    def grip_force_limit_n(self) -> float | None:
        """The force-controlled closure's target per finger [N]: the hold force the object's mass needs
        (tasks.robot.squeeze), else the contract's cap (None: position control)."""
        if self.squeeze is not None:
            return self.squeeze.force_target_n
        return L3Parameters.of(self.contract).grip_force_limit_n or None

    def grip_force_n(self, scale: float = 1.0) -> float | None:
        """The closure's force target per finger [N] for a firmer squeeze (scale >= 1: the revise_squeeze route's
        grip_force_scale), within the contract's cap and the gripper's maximum (None: position control)."""
        base = self.grip_force_limit_n
        if base is None or scale <= 1.0:
            return base
        cap = min(L3Parameters.of(self.contract).grip_force_limit_n or math.inf,
                  gripper(self.gripper).spec.max_grip_force_n)
        return float(max(base, min(base * scale, cap)))

    def plan(self, values: dict[str, float], target_xy_m: tuple[float, float] | None = None,
             yaw_deg: float = 0.0) -> ActionPlan:
        """The ActionPlan of a candidate (editable fields) under a condition (target, initial yaw)."""
        o = self.options
        rank = int(min(max(0, round(values["grasp_rank"])), len(self.grasps) - 1))
        plan = ActionPlan(
            grasp=self.grasps[rank], gripper=self.gripper, gripper_reason=self.gripper_reason,
            grasp_reason=self.grasp_reason,
            squeeze_depth_m=float(values["squeeze_depth_m"]),
            grip_force_limit_n=self.grip_force_n(values.get("grip_force_scale", 1.0)),
            closing_speed_m_per_s=float(values["closing_speed_m_per_s"]),
            lift_height_m=L3Parameters.of(self.contract).lift_height_m,
            target_xy_m=target_xy_m or o.target_xy_m, initial_yaw_deg=yaw_deg,
            closure_duration_s=0.3, lift_duration_s=float(values["lift_duration_s"]),
            transport_duration_s=float(values["transport_duration_s"]),
            release_duration_s=float(values.get("release_duration_s", o.release_duration_s)),
            place_height_m=float(values.get("place_height_m", o.place_height_m)),
            retreat_duration_s=o.retreat_duration_s, settle_duration_s=o.settle_duration_s)
        return reachable_plan(plan, self.grasps, self.body)  # a yawed condition may turn a side grasp out of reach

    def trial(self, values: dict[str, float], role: str, action: str = "", material: Material | None = None,
              target_xy_m: tuple[float, float] | None = None, yaw_deg: float = 0.0) -> ProbeResult:
        """Run (or fetch from the cache) one trial and store it as an interaction attempt."""
        plan, inputs = self._trial_inputs(values, material, target_xy_m, yaw_deg)
        self.progress.trials(len(self.attempts) + 1, 1, _what(role, action, values))
        probe = self._store(trial_task(**inputs), plan, inputs, values, role, action, material, yaw_deg)
        self._report(probe)
        return probe

    def _trial_inputs(self, values: dict[str, float], material: Material | None,
                      target_xy_m: tuple[float, float] | None, yaw_deg: float) -> tuple[ActionPlan, dict[str, Any]]:
        """The plan of a trial and the inputs of its cached task."""
        plan = self.plan(values, target_xy_m, yaw_deg)
        settings = replace(self.options.settings, substeps=int(round(values.get("substeps", 1))),
                           device=self.options.device, cpu_threads=self.options.cpu_threads)
        inputs = {**body_inputs(self.body), "physical": self.physical, "material": material or self.material,
                  "plan": plan, "settings": settings_inputs(settings),
                  "tolerances": asdict(tolerances_from(self.contract))}
        return plan, inputs

    def _store(self, out: dict[str, Any], plan: ActionPlan, inputs: dict[str, Any], values: dict[str, float],
               role: str, action: str, material: Material | None, yaw_deg: float) -> ProbeResult:
        """Store a trial's output as the next interaction attempt; its probe result, keyed."""
        key = probe_cache_key(trial_task, inputs)
        probe: ProbeResult = out["probe"]
        attrs = {"labels": probe.metrics, "plan": plan.model_dump(mode="json"), "info": {k: v for k, v in out["info"].items() if k != "wall_time_s"}, "role": role,
                 "action": action, "values": values, "cache_key": key,
                 "material": (material or self.material).model_dump(mode="json"),
                 "physical_model": self.physical.model_dump(mode="json")}
        n = store_attempt(self.asset_dir, out["arrays"], attrs) if out["arrays"] else None
        trial = len(self.attempts) + 1  # the trial's one number (tasks.record.trials)
        rrd = (record_attempt(self.asset_dir, trial, out["arrays"], {**attrs, "trial": trial}, key)
               if n is not None and self.recordings else None)
        self.attempts.append(TrialRow(attempt=n, role=role, action=action, values=values, labels=probe.metrics,
                                      cache_key=key, recording=rrd,
                                      condition=TrialCondition(target_xy_m=list(plan.target_xy_m), yaw_deg=yaw_deg)))
        return probe.model_copy(update={"cache_key": key, "recording": attempt_path(n) if n is not None else None})

    def under(self, values: dict[str, float], conditions: tuple[tuple[float, float, float], ...], role: str,
              action: str = "", material: Material | None = None) -> list[ProbeResult]:
        """One trial per condition (x [m], y [m], yaw [deg]): the robustness or the held-out conditions. The trials
        are independent: on the CPU they run side by side (flows.harness.call_tasks: Prefect's thread-pool task
        runner), then are stored as attempts in the order of `conditions`, as one after another would."""
        runs = [self._trial_inputs(values, material, (x, y), yaw) for x, y, yaw in conditions]
        self.progress.trials(len(self.attempts) + 1, len(runs), f"{role}, {len(runs)} conditions side by side"
                             + (f" ({action})" if action else ""))
        outs = call_tasks([(trial_task, inputs) for _, inputs in runs], probe_workers(len(runs), self.options.device),
                          self.options.device)
        stored = [self._store(out, plan, inputs, values, role, action, material, yaw)
                  for (plan, inputs), out, (_, _, yaw) in zip(runs, outs, conditions)]
        for i, probe in enumerate(stored):
            self._report(probe, len(self.attempts) - len(stored) + i + 1)
        return stored

    def _report(self, probe: ProbeResult, number: int | None = None) -> None:
        """The progress line of a finished trial: its reason in words when it failed."""
        reason = trial_reason(probe.metrics, self.contract, tolerances_from(self.contract))
        self.progress.result(number or len(self.attempts), reason)


def _what(role: str, action: str, values: dict[str, float]) -> str:
    """A trial in words: role, revision, grasp rank and squeeze."""
    parts = [role + (f" ({action})" if action else "")]
    if "grasp_rank" in values:
        parts.append(f"grasp {int(round(values['grasp_rank']))}")
    if "squeeze_depth_m" in values:
        parts.append(f"squeeze {values['squeeze_depth_m'] * 1000:.1f} mm")
    return ", ".join(parts)


def initial_values(ctx: L3Context) -> dict[str, float]:
    """First candidate: the best grasp, the deepest squeeze of its stiffness-scaled range (the closure is
    force-controlled: the fingers stop at the force target, this only bounds how deep they may go), the draft timing,
    one substep."""
    o = ctx.options
    squeeze = (o.squeeze_depth_m if o.squeeze_depth_m is not None else ctx.squeeze.high_m if ctx.squeeze is not None
               else o.squeeze_fraction * ctx.grasps[0].width_m)
    values = {"grasp_rank": 0.0, "squeeze_depth_m": squeeze, "closing_speed_m_per_s": o.closing_speed_m_per_s,
              "lift_duration_s": o.lift_duration_s, "transport_duration_s": o.transport_duration_s, "substeps": 1.0,
              "grip_force_scale": 1.0, "place_height_m": o.place_height_m, "release_duration_s": o.release_duration_s}
    fields = {f.name: f for f in ctx.contract.editable_fields}
    # a field the contract does not let L3 edit keeps its default (ActionPlan's, L3Options')
    values = {k: v for k, v in values.items() if k in fields or k in CORE_FIELDS}
    for f in fields.values():
        values[f.name] = min(max(values[f.name], f.low), f.high)
    return values


def load_context(asset_dir: Path, options: L3Options, contract: StageContract,
                 material: Material | None = None) -> L3Context:
    """Read L0 / L1 / L2 from the asset directory, build the trial body and rank the grasps."""
    adir = AssetDir(asset_dir)
    asset, physical = adir.l0, adir.physical_model()
    source = "given"
    if material is None:
        material, source = material_of(asset_dir, asset)
    hold = _hold_inputs(physical, material, contract)
    com = np.asarray(physical.center_of_mass_m)
    if options.gripper is not None:
        name, reason, rows = options.gripper, "given (L3Options.gripper)", []
    else:  # the Planner's choose_gripper action (the L3 contract): from widths, mass and stiffness
        surf, faces = trimesh.sample.sample_surface_even(asset.mesh, SURFACE_SAMPLES, seed=0)
        choice = gripper_choice_task(np.asarray(surf), np.asarray(asset.mesh.face_normals[faces]), com,
                                     physical.gripper_friction, np.asarray(asset.mesh.extents), hold,
                                     _planner_code())
        if choice["name"] is None:  # run_l3 records it as L3's outcome (no grasp is a result)
            raise NoGraspError(choice["reason"])
        name, reason = choice["name"], choice["reason"]
        rows = [GripperOption.model_validate(o) for o in choice["options"]]
    g = gripper(name)
    spacing = options.particle_spacing_m or auto_trial_spacing(asset.mesh.extents, options.quality, g.pad_face_m)
    body = trial_body(asset.mesh, asset.particles_m, asset.spacing_m, asset.gaussians, spacing,
                      surface_samples=SURFACE_SAMPLES)
    nominal = squeeze_plan(width_m=g.stroke_m, pad_area_m2=g.pad_area_m2, gripper_max_n=g.spec.max_grip_force_n,
                           friction=physical.gripper_friction, **hold)
    reasons: list[str] = []

    def select(settings: GraspSettings) -> list[GraspCandidate]:
        sel = grasp_selection_task(body.surface_points_m, body.surface_normals, com, physical.gripper_friction,
                                   asdict(settings), _planner_code())
        reasons.append(sel["reason"])
        return sel["candidates"]

    info = asset.record["info"]  # the Planner holds a soft toy or animal by its body (tasks.robot.grasp_parts)
    program = ShapeProgram.model_validate(info["program"]) if info.get("program") else None
    def reachable(c: GraspCandidate) -> bool:  # at the nominal condition (the object at the origin, no yaw)
        return plan_or_error(ActionPlan(grasp=c, gripper=name, squeeze_depth_m=0.0, target_xy_m=options.target_xy_m),
                             body)[0] is not None

    grasps, grasp_reason = body_first_grasps(select, grasp_settings(name, nominal.soft_indent_m), info["category"],
                                             program, bool(info.get("reoriented")), asset.mesh, reachable,
                                             asset.particles_m)
    if not grasps:  # run_l3 records it as L3's outcome (no grasp is a result)
        raise NoGraspError(f"{name}: {reasons[0]}")
    sq = squeeze_plan(width_m=grasps[0].width_m, pad_area_m2=g.pad_area_m2,
                      gripper_max_n=g.spec.max_grip_force_n, friction=physical.gripper_friction,
                      **hold)
    if not L3Parameters.of(contract).hold_force_margin:  # no hold target: position control, the contract's range
        return L3Context(Path(asset_dir), body, physical, material, source, grasps, options, contract,
                         gripper=name, gripper_reason=reason, gripper_options=rows, l0=asset,
                         grasp_reason=grasp_reason)
    return L3Context(Path(asset_dir), body, physical, material, source, grasps, options,
                     _with_squeeze_range(contract, sq), gripper=name, gripper_reason=reason, squeeze=sq,
                     grasp_reason=grasp_reason,
                     gripper_options=rows, l0=asset)


@functools.cache
def _planner_code() -> str:
    """The code part of the grasp planner's cache keys: tasks/robot, the gripper specs and the robot contract (an
    edit there makes new keys; no version to bump by hand), and the libraries they compute with."""
    from cache.files import source_digest

    root = Path(__file__).resolve().parent.parent
    return source_digest([root / "tasks" / "robot", root / "contracts" / "grippers", root / "contracts" / "robot.py"],
                         ("numpy", "scipy", "trimesh"))


@cached_task(version="1", name="l3.gripper_choice")
def gripper_choice_task(points_m: np.ndarray, normals: np.ndarray, center_of_mass_m: np.ndarray, friction: float,
                        extents_m: np.ndarray, hold: HoldInputs, code: str) -> dict[str, Any]:
    """The Planner's choose_gripper on surface samples [m]: {'name' (None: no gripper holds it), 'reason', 'options'
    (the rows manipulation.json records)}. code: _planner_code(), part of the key."""
    choice = choose_gripper(points_m, normals, center_of_mass_m, friction, extents_m=extents_m, **hold)
    return {"name": choice.name, "reason": choice.reason, "options": choice.summary()}


@cached_task(version="1", name="l3.grasp_selection")
def grasp_selection_task(points_m: np.ndarray, normals: np.ndarray, center_of_mass_m: np.ndarray, friction: float,
                         settings: dict[str, Any], code: str) -> dict[str, Any]:
    """Ranked antipodal grasps on the trial body's surface: {'candidates' (best first), 'reason' (when none)}."""
    sel = select_grasps(points_m, normals, center_of_mass_m, friction=friction, settings=GraspSettings(**settings))
    return {"candidates": sel.candidates, "reason": sel.reason}


SURFACE_SAMPLES = 2000  # surface points for grasp sampling (the trial body's, and the gripper choice's)


class HoldInputs(TypedDict):
    """The keyword inputs that choose_gripper and squeeze_plan share (SI units)."""

    youngs_modulus_pa: float
    poisson_ratio: float
    mass_kg: float
    gravity_m_per_s2: float
    budget_n: float
    margin: float
    floor_n: float


def _hold_inputs(physical: PhysicalModel, material: Material, contract: StageContract) -> HoldInputs:
    """What the hold force and the squeeze estimate need: material, mass, gravity, force budget and margin."""
    p = L3Parameters.of(contract)
    budget = tolerances_from(contract).force_budget_n
    cap = p.grip_force_limit_n or 0.5 * budget
    # without a hold margin (position control) the squeeze estimate still needs one: the packaged contract's
    margin = p.hold_force_margin or packaged_parameters("L3")["hold_force_margin"]
    return {"youngs_modulus_pa": material.youngs_modulus_pa, "poisson_ratio": material.poisson_ratio,
            "mass_kg": physical.mass_kg, "gravity_m_per_s2": float(np.linalg.norm(physical.gravity_m_per_s2)),
            "budget_n": min(budget, 2.0 * cap), "margin": float(margin), "floor_n": p.hold_force_floor_n}


def _with_squeeze_range(contract: StageContract, sq: SqueezePlan) -> StageContract:
    """The contract with squeeze_depth_m's range narrowed to the object's stiffness-scaled range (inside the
    contract's own bounds)."""
    fields = []
    for f in contract.editable_fields:
        if f.name == "squeeze_depth_m":
            lo = min(max(sq.low_m, f.low), f.high)
            f = f.model_copy(update={"low": lo, "high": min(max(sq.high_m, lo), f.high)})
        fields.append(f)
    return contract.model_copy(update={"editable_fields": fields})


def material_of(asset_dir: Path, asset: Any) -> tuple[Material, str]:
    """The L2 material, else (L2 has not run, or found no material) the vocabulary prior of the asset's words; an
    unreadable material.json is an InputError naming it."""
    adir = AssetDir(asset_dir)
    found = adir.material().material if adir.has("material") else None
    if found is not None:
        return found, "L2"
    from tasks.agents import targets_from_intent

    info = geometry_info(asset.record)
    words = " ".join(str(x) for x in (info.name, info.category) if x) or "foam"
    p = targets_from_intent(words).priors  # the vocabulary's default material fills what the words leave out
    return Material(youngs_modulus_pa=p["youngs_modulus_pa"], poisson_ratio=p["poisson_ratio"],
                    damping_rate_per_s=p["damping_rate_per_s"]), "vocabulary prior"


def _accepted(metrics: dict[str, float], contract: StageContract) -> bool:
    """Every hard gate passes."""
    return all(g.passes(metrics.get(g.metric)) for g in contract.hard_gates)


def run_l3(asset_dir: Path, options: L3Options | None = None, agents: AgentConfig | None = None,
           contract: StageContract | None = None, material: Material | None = None,
           recordings: bool = True, progress: Progress | None = None) -> tuple[ManipulationRecord, StageOutcome]:
    """Run L3 on an asset directory (L0 + L1, L2 or a prior): the l3-manipulation flow against the local Prefect
    runtime; write manipulation.json; return (record, outcome)."""
    with cache.local_runtime():
        return l3_manipulation(asset_dir, options, agents, contract, material, recordings, progress)


@lean_flow(name="l3-manipulation", validate_parameters=False, persist_result=False)
def l3_manipulation(asset_dir: Path, options: L3Options | None = None, agents: AgentConfig | None = None,
                    contract: StageContract | None = None, material: Material | None = None, recordings: bool = True,
                    progress: Progress | None = None) -> tuple[ManipulationRecord, StageOutcome]:
    """L3: grasps, the harness stage over pick-and-place trials (a subflow), robustness and held-out trials (cached
    tasks), material revisions revalidated by L2 (the l2-revalidation subflow), manipulation.json.

    An object no gripper can hold is a result, not an error: manipulation.json and evidence/ record the reason as
    L3's one attempt (status 'no_grasp'). progress: a sink for 'L3 trial k of at most n: ... (elapsed)' lines."""
    t0 = time.perf_counter()
    asset_dir = Path(asset_dir)
    options = options or L3Options()
    contract = contract or load_contract("L3")
    report = L3Progress(progress, planned_trials(contract, len(options.robustness), len(options.held_out),
                                                 options.material_fallback), t0)
    report.say("L3: trial body and grasp selection")
    try:
        ctx = load_context(asset_dir, options, contract, material)
    except NoGraspError as exc:
        report.say(f"L3: {exc}")
        return _no_grasp(asset_dir, options, contract, material, str(exc), t0)
    ctx.progress = report
    ctx.recordings = recordings
    report.say(f"L3: {len(ctx.grasps)} grasp candidates, the best {ctx.grasps[0].width_m * 1000:.0f} mm wide; "
               f"{len(ctx.body.particles_m)} particles per trial")
    start = initial_values(ctx)

    def runner(values: dict[str, float], action: str) -> list[ProbeResult]:
        return [ctx.trial(values, "selection", action)]

    outcome = run_harness(contract, runner, TargetBehaviour(), agents=agents, record_dir=asset_dir, initial=start,
                          initial_action="revise_squeeze")
    chosen_values = outcome.values
    final_material, material_revision, robustness = ctx.material, None, None
    escalated = outcome.status == "escalated" and outcome.escalation == "revise_material"
    if outcome.passed and chosen_values is not None and options.robustness:
        # the accepted plan under the training perturbations; a failure asks the material for margin, adopted only
        # when the revised material passes the nominal condition and strictly more perturbations
        rob = ctx.under(dict(chosen_values), options.robustness, "robustness")
        robustness = _conditions(options.robustness, rob, contract)
        failing = [r for r in rob if not _accepted(r.metrics, contract)]
        if failing:
            material_revision = _revise_material(ctx, dict(chosen_values), failing[0].metrics, "robustness")
            if material_revision is not None and material_revision.accepted and material_revision.robustness and (
                    material_revision.robustness.passed > robustness.passed):
                final_material = material_revision.to
                robustness = material_revision.robustness
            elif material_revision is not None:
                material_revision = material_revision.model_copy(update={"accepted": False})
    elif escalated or (not outcome.passed and options.material_fallback):
        base = _base_attempt(ctx, outcome, escalated)
        if base is not None:
            material_revision = _revise_material(ctx, dict(base.proposal), base.evidence.metrics,
                                                 "escalation" if escalated else "no plan passed")
        if material_revision is not None and material_revision.accepted:
            chosen_values = dict(material_revision.plan_values)
            final_material = material_revision.to
            robustness = material_revision.robustness
    accepted = chosen_values is not None and (outcome.passed or final_material is not ctx.material)
    held: list[ConditionRow] = []
    if accepted and options.held_out and chosen_values is not None:  # (accepted: chosen_values is set)
        results = ctx.under(dict(chosen_values), options.held_out, "held_out", material=final_material)
        held = _conditions(options.held_out, results, contract).conditions
    chosen = _chosen_attempt(ctx, chosen_values, final_material) if accepted else None
    if recordings and chosen is not None:
        chosen = name_pick_and_place(asset_dir, ctx.attempts, chosen)
    rec_paths = [a.recording for a in ctx.attempts if a.recording]  # every trial's, failed ones included
    record = _record(ctx, outcome, accepted, chosen, final_material, material_revision, held, robustness, rec_paths)
    verdict = "passed" + _conditions_summary(held, robustness) if accepted else "did not pass: " + record.reason
    report.say(f"L3 {verdict}")
    # the file holds no wall time, so a rerun writes the same manipulation.json
    AssetDir(asset_dir).write_manipulation(record)
    return record, outcome


def _conditions_summary(held: list[ConditionRow], robustness: ConditionSummary | None) -> str:
    """' (nominal condition; held out 2/3, robustness 1/2)': the pass is the nominal trial's, the rest said beside it."""
    parts = [f"held out {sum(h.success for h in held)}/{len(held)}"] if held else []
    if robustness and robustness.conditions:
        parts.append(f"robustness {robustness.passed}/{len(robustness.conditions)}")
    return f" (nominal condition; {', '.join(parts)})" if parts else ""


def name_pick_and_place(asset_dir: Path, attempts: list[TrialRow], chosen: TrialRow) -> TrialRow:
    """Give the chosen trial's recording the name users open (recordings/L3_pick_and_place.rrd): its attempt file is
    renamed, not copied, and the attempt's row in `attempts` (manipulation.json `attempts`, whose `attempt` is its
    interaction data) names the new path. Returns the row as it now stands."""
    if not chosen.recording or chosen.recording == PICK_AND_PLACE_RECORDING:
        return chosen
    os.replace(Path(asset_dir) / chosen.recording, Path(asset_dir) / PICK_AND_PLACE_RECORDING)
    renamed = chosen.model_copy(update={"recording": PICK_AND_PLACE_RECORDING})
    attempts[next(i for i, a in enumerate(attempts) if a is chosen)] = renamed
    return renamed


def _no_grasp(asset_dir: Path, options: L3Options, contract: StageContract, material: Material | None, reason: str,
              t0: float) -> tuple[ManipulationRecord, StageOutcome]:
    """L3's record when no gripper can hold the object: no trial ran; the reason is L3's one attempt in evidence/."""
    adir = AssetDir(asset_dir)
    physical = adir.physical_model()
    source = "given"
    if material is None:
        material, source = material_of(asset_dir, adir.l0)
    attempts = record_no_grasp(asset_dir, reason)
    record = ManipulationRecord(
        passed=False, status="no_grasp", message=reason, reason=reason, best_attempt=None, material=material,
        material_source=source, physical_model=physical, plan=None, values=None, attempt=None, outcome={}, labels={},
        forces={}, force_budget_n=tolerances_from(contract).force_budget_n, grasps=[],
        gripper=GripperChoice(name=None, reason=reason, options=[], squeeze=None),
        held_out=HeldOutConditions(conditions=[], success_rate=None), robustness=None, material_revision=None,
        numerics=L3Numerics(quality=options.quality, device=options.device), attempts=attempts, harness_attempts=1,
        recordings=[])
    AssetDir(asset_dir).write_manipulation(record)
    return record, StageOutcome(stage="L3", status="no_valid_candidate", attempts_used=1, message=reason)


def _conditions(conditions: tuple[tuple[float, float, float], ...], results: list[ProbeResult],
                contract: StageContract) -> ConditionSummary:
    """Per-condition outcome of one plan: target, yaw, success, labels; and how many passed."""
    rows = [ConditionRow(target_xy_m=[x, y], initial_yaw_deg=yaw, success=_accepted(r.metrics, contract),
                         labels=r.metrics, attempt=r.recording) for (x, y, yaw), r in zip(conditions, results)]
    return ConditionSummary(conditions=rows, passed=sum(r.success for r in rows))


def _base_attempt(ctx: L3Context, outcome: StageOutcome, escalated: bool) -> Any:
    """The attempt a material revision starts from when no plan passed: the escalating one, else the one failing the
    fewest gates (the latest of those)."""
    probed = [a for a in outcome.attempts if a.evidence is not None and a.evidence.metrics]
    if not probed:
        return None
    if escalated:
        return probed[-1]
    return min(reversed(probed), key=lambda a: len(failed_gates(a.evidence.metrics, ctx.contract)))


def _revise_material(ctx: L3Context, values: dict[str, float], metrics: dict[str, float],
                     trigger: str) -> MaterialRevision | None:
    """Material revision asked by a trial's failed gates (flows.l3_material), L2 revalidation (one half-way retry
    when a band is left), then the robot under the same plan: the nominal condition, and the robustness conditions
    when it passes. 'accepted' when L2 passed and the nominal condition passes; None when the material has nothing to
    give."""
    limits = MaterialLimits.from_asset(ctx.asset_dir)
    proposal = revise_material(ctx.material, metrics, ctx.contract, limits)
    if proposal is None:
        return None
    revised, reason = proposal
    checks: list[L2Check] = []
    for _ in range(2):
        ctx.progress.say(f"L3 material revision ({trigger}): L2 revalidation of E = {revised.youngs_modulus_pa:.3g} "
                         f"Pa, damping {revised.damping_rate_per_s:.3g} 1/s")
        l2 = revalidate_in_l2(ctx.asset_dir, revised, ctx.physical, limits, sim=ctx.options.sim(), asset=ctx.l0)
        checks.append(l2)
        if l2.passed or not all(l2.gates.values()):
            break
        revised = halfway(ctx.material, revised)
    rev = MaterialRevision.model_validate({
        "trigger": trigger, "from": ctx.material, "to": revised, "reason": reason,
        "failed_gates": failed_gates(metrics, ctx.contract), "l2_revalidation": checks[-1], "l2_checks": checks,
        "plan_values": dict(values), "accepted": False})
    if checks[-1].passed:
        confirm = [ctx.trial(dict(values), "confirmation", "revise_material", material=revised)]
        accepted = _accepted(confirm[0].metrics, ctx.contract)
        if accepted:  # the robustness conditions only matter for a material the nominal condition accepts
            confirm += ctx.under(dict(values), ctx.options.robustness, "robustness", "revise_material", revised)
        rev = rev.model_copy(update={
            "accepted": accepted, "confirmation": confirm[0].metrics,
            "robustness": _conditions(ctx.options.robustness, confirm[1:], ctx.contract)})
    return rev


def _chosen_attempt(ctx: L3Context, values: dict[str, float] | None, material: Material) -> TrialRow | None:
    """The stored attempt of the chosen candidate with the final material: a selection trial under the asset's own
    material, a confirmation trial only when the revised material was adopted (a confirmation that was not adopted ran
    a material the asset does not carry)."""
    revised = material is not ctx.material
    for a in reversed(ctx.attempts):
        if a.values == values and a.labels and a.role == ("confirmation" if revised else "selection"):
            return a
    return None


def _forces(labels: dict[str, float]) -> dict[str, float]:
    """The force summary of a trial."""
    keys = ("max_finger_force_n", "max_finger_force_0_n", "max_finger_force_1_n", "hold_normal_force_n",
            "hold_vertical_force_n", "weight_n", "hold_friction_ratio", "hold_vertical_ratio", "gripper_friction")
    return {k: labels[k] for k in keys if k in labels}


def _record(ctx: L3Context, outcome: StageOutcome, accepted: bool, chosen: TrialRow | None, material: Material,
            material_revision: MaterialRevision | None, held: list[ConditionRow],
            robustness: ConditionSummary | None, recordings: list[str]) -> ManipulationRecord:
    """manipulation.json."""
    labels = chosen.labels if chosen else {}
    tol = tolerances_from(ctx.contract)
    # trial: the one number of a simulated pick-and-place, from 1 in the order run (tasks.record.trials; the
    # console's 'L3 trial k'); attempt: its interaction folder
    attempts = [a.model_copy(update={"trial": i + 1, "reason": trial_reason(a.labels, ctx.contract, tol)})
                for i, a in enumerate(ctx.attempts)]
    if chosen is not None:  # the row as numbered
        chosen = attempts[next(i for i, a in enumerate(ctx.attempts) if a is chosen)]
    best = chosen if accepted else best_attempt(attempts, ctx.contract)
    reason = "" if accepted else (trial_reason(best.labels, ctx.contract, tol) if best else outcome.message)
    if not accepted and material_revision is not None and not material_revision.accepted:
        reason += ("; the robot failed with the L2-revalidated material revision too"
                   if material_revision.l2_revalidation.passed else "; the material revision failed L2's revalidation")
    return ManipulationRecord(
        passed=bool(accepted), status=outcome.status, message=outcome.message, reason=reason,
        # the attempt the manifest reports: the adopted one, else the best trial under the asset's own material
        best_attempt=None if best is None else BestAttempt(
            attempt=best.attempt, trial=best.trial, role=best.role, values=best.values, labels=best.labels,
            plan=ctx.plan(best.values), cache_key=best.cache_key,
            failed_gates=failed_gate_names(best.labels, ctx.contract),
            reason=trial_reason(best.labels, ctx.contract, tol)),
        material=material,
        material_source=ctx.material_source if material is ctx.material else "L3 material revision (L2 revalidated)",
        physical_model=ctx.physical,
        plan=ctx.plan(chosen.values) if chosen else None,
        values=chosen.values if chosen else None, attempt=chosen.attempt if chosen else None,
        trial=chosen.trial if chosen else None,
        outcome={k: bool(labels[k]) for k in (*LABELS, "slipped", "force_budget_violated") if k in labels},
        labels=labels, forces=_forces(labels), force_budget_n=tol.force_budget_n, grasps=ctx.grasps,
        # the Planner's choose_gripper: the gripper, why, what it weighed; the force target and squeeze range
        gripper=GripperChoice(name=ctx.gripper, reason=ctx.gripper_reason, options=ctx.gripper_options,
                              squeeze=SqueezeSummary(**ctx.squeeze.as_dict()) if ctx.squeeze else None),
        held_out=HeldOutConditions(conditions=held,
                                   success_rate=(sum(h.success for h in held) / len(held)) if held else None),
        robustness=robustness if accepted else None,
        material_revision=material_revision,
        numerics=L3Numerics(
            quality=ctx.options.quality, trial_particle_spacing_m=ctx.body.spacing_m,
            l0_particle_spacing_m=ctx.body.source_spacing_m, trial_particles=int(len(ctx.body.particles_m)),
            grid_dx_m=2.0 * ctx.body.spacing_m, device=ctx.options.device,
            note="the L0 volume is resampled at the trial lattice (numerical choice); density, mass, friction and "
                 "material are unchanged"),
        attempts=attempts, harness_attempts=outcome.attempts_used, recordings=recordings)


def load_manipulation(asset_dir: Path) -> ManipulationRecord:
    """manipulation.json of an asset (InputError when L3 has not run): AssetDir's."""
    return AssetDir(asset_dir).manipulation()
