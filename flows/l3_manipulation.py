"""L3 manipulation flow, as the layer's steps: plan (gripper, grasps, trial body) -> pick-and-place trials under the
harness -> robustness conditions -> material revision (L2 revalidation, robot confirmation) -> held-out conditions ->
manipulation.json.

Reads L0 (geometry), L1 (physical.json, frozen) and L2 (material.json, or the vocabulary prior when L2 has not run).
Action revisions (grasp rank, squeeze, timing) and numerical revisions (substeps: dt / n, same durations) are
re-evaluated here by the harness; a material revision (a gate only the material can fix: deformation bound) goes back
through L2 revalidation (flows.l3_material: the l2-revalidation subflow, exactly the L2 probes re-execute) and is then
confirmed by the robot under the same plan, physical model and force budget. An accepted plan is tried under two
robustness conditions (other yaws, training only); when one fails, or when no plan passed at all, L3 asks L2 for a
material inside its target bands (tasks.manipulation.material_revision), adopted only when the robot then does
better. The final plan is then evaluated under held-out conditions, recorded apart. Writes ``manipulation.json``
(tasks.manipulation.l3_record), ``interaction/`` (one Zarr group per trial, failures kept), ``evidence/`` and
``recordings/L3_*.rrd``. The context, the record and the revision logic live in tasks/manipulation/; here are the
cached tasks (trial, gripper choice, grasp selection) and the flow.
"""

from __future__ import annotations

import functools
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any, cast

import numpy as np
import trimesh

import cache
from cache import cached_task
from cache.files import source_digest
from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig, StageOutcome, TargetBehaviour
from contracts.asset_dir import DEFAULT_KEEP, KeepTrials, attempt_path
from contracts.manipulation import (ConditionRow, ConditionSummary, GripperOption, L2Check, ManipulationRecord,
                                    MaterialRevision)
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, ProbeSpec
from contracts.robot import ActionPlan, GraspCandidate
from contracts.shape import ShapeProgram
from contracts.stage import L3Parameters, StageContract, load_contract
from flows.harness import call_tasks, probe_cache_key, run_harness
from flows.l3_material import revalidate_in_l2
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import load_l0
from tasks.manipulation.body import auto_trial_spacing, trial_body
from tasks.manipulation.context import (SURFACE_SAMPLES, HoldInputs, L3Context, L3Options, OnStored, body_from,
                                        failed_metrics, hold_inputs, initial_values, material_of, plan_executable,
                                        with_squeeze_range)
from tasks.manipulation.keep import keep_trials
from tasks.manipulation.l3_record import (build_record, chosen_attempt, conditions, conditions_summary,
                                          name_pick_and_place, no_grasp_outcome, unname_pick_and_place)
from tasks.manipulation.material_revision import MaterialLimits, robot_confirmation, robustness_and_revision
from tasks.manipulation.outcome import TrialTolerances
from tasks.manipulation.report import L3Progress, Progress, planned_trials
from tasks.manipulation.trial import TrialSettings, plan_or_error, run_trial
from tasks.probes.workers import probe_workers
from tasks.robot import NoGraspError, select_grasps
from tasks.robot.choice import choose_gripper, grasp_settings
from tasks.robot.grasp import GraspSettings
from tasks.robot.grasp_parts import body_first_grasps
from tasks.robot.gripper import gripper
from tasks.robot.squeeze import squeeze_plan, torque_lever_m

TASK_VERSION = "13"  # bump when tasks/manipulation/{trial,outcome,body,frame}.py change what a trial returns
# (6: settle until at rest; 7: simulated in the frame where the closing axis is at 45 degrees to the grid; 8: the
# approach is recorded; 9: grippers as data, a force-controlled closure that keeps its target while held and skips the
# rest of the closure, the time-step cap follows dx; 10: the hold's contact stiffness measured from where the force
# began to rise, what-happened metrics and failure-mode flags (tasks.manipulation.diagnosis); 11: release_rotation_deg;
# 12: a what-happened figure that does not exist is absent, not NaN; 13: `settled` also needs the body's turn rate
# small, and the settle runs up to 2 s after the plan)


@cached_task(version=TASK_VERSION, name="l3.trial")
def trial_task(particles_m: np.ndarray, volumes_m3: np.ndarray, spacing_m: float, source_spacing_m: float,
               height_m: float, gaussians: dict[str, np.ndarray], physical: PhysicalModel, material: Material,
               plan: ActionPlan, settings: dict[str, Any], tolerances: dict[str, float]) -> dict[str, Any]:
    """One pick-and-place in the MPM: {'probe': ProbeResult, 'arrays': recorded arrays, 'info': numerics}."""
    body = body_from(particles_m, volumes_m3, spacing_m, source_spacing_m, height_m, gaussians)
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


class CachedTrials:
    """The context's TrialRunner: the cached trial task, a plan's conditions side by side on the CPU
    (flows.harness.call_tasks: Prefect's thread-pool task runner, probe_workers at a time)."""

    def run(self, inputs: list[dict[str, Any]], device: str) -> list[dict[str, Any]]:
        return call_tasks([(trial_task, kw) for kw in inputs], probe_workers(len(inputs), device), device)

    def key(self, inputs: dict[str, Any]) -> str | None:
        return probe_cache_key(trial_task, inputs)


def load_context(asset_dir: Path, options: L3Options, contract: StageContract,
                 material: Material | None = None) -> L3Context:
    """Read L0 / L1 / L2 from the asset directory, build the trial body and rank the grasps."""
    adir = AssetDir(asset_dir)
    asset, physical = load_l0(adir.path), adir.physical_model()
    source = "given"
    if material is None:
        material, source = material_of(asset_dir, asset)
    hold = hold_inputs(physical, material, contract)
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
                      surface_samples=SURFACE_SAMPLES, shell_volumes_m3=asset.volumes_m3 if asset.shell else None)
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
        return plan_executable(ActionPlan(grasp=c, gripper=name, squeeze_depth_m=0.0, target_xy_m=options.target_xy_m),
                               body)

    settings = grasp_settings(name, nominal.soft_indent_m)
    grasps, grasp_reason = body_first_grasps(select, settings, info["category"],
                                             program, bool(info.get("reoriented")), asset.mesh, reachable,
                                             asset.particles_m)
    if not grasps:  # run_l3 records it as L3's outcome (no grasp is a result)
        raise NoGraspError(f"{name}: {reasons[0]}")
    sq = squeeze_plan(width_m=grasps[0].width_m, pad_area_m2=g.pad_area_m2,
                      gripper_max_n=g.spec.max_grip_force_n, friction=physical.gripper_friction,
                      lever_m=torque_lever_m(np.asarray(grasps[0].center_m), np.asarray(grasps[0].closing_axis), com),
                      **hold)
    if not L3Parameters.of(contract).hold_force_margin:  # no hold target: position control, the contract's range
        return L3Context(Path(asset_dir), body, physical, material, source, grasps, options, contract,
                         gripper=name, gripper_reason=reason, gripper_options=rows, l0=asset,
                         grasp_reason=grasp_reason, grasp_settings=settings, runner=CachedTrials())
    return L3Context(Path(asset_dir), body, physical, material, source, grasps, options,
                     with_squeeze_range(contract, sq), gripper=name, gripper_reason=reason, squeeze=sq,
                     grasp_reason=grasp_reason, gripper_options=rows, l0=asset, grasp_settings=settings,
                     runner=CachedTrials())


@functools.cache
def _planner_code() -> str:
    """The code part of the grasp planner's cache keys: tasks/robot, the gripper specs and the robot contract (an
    edit there makes new keys; no version to bump by hand), and the libraries they compute with. The robot's visual
    meshes (tasks/robot/visual.py) only draw it: not part of the planner's keys."""
    root = Path(__file__).resolve().parent.parent
    robot = [p for p in (root / "tasks" / "robot").rglob("*")
             if p.is_file() and "__pycache__" not in p.parts and p.name != "visual.py"]
    return source_digest([*robot, root / "contracts" / "grippers", root / "contracts" / "robot.py"],
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


def run_l3(asset_dir: Path, options: L3Options | None = None, agents: AgentConfig | None = None,
           contract: StageContract | None = None, material: Material | None = None,
           recordings: bool = True, progress: Progress | None = None,
           keep: KeepTrials = DEFAULT_KEEP, on_stored: OnStored | None = None) -> tuple[ManipulationRecord, StageOutcome]:
    """Run L3 on an asset directory (L0 + L1, L2 or a prior): the l3-manipulation flow against the local Prefect
    runtime; write manipulation.json; return (record, outcome)."""
    with cache.local_runtime():
        return l3_manipulation(asset_dir, options, agents, contract, material, recordings, progress, keep, on_stored)


@lean_flow(name="l3-manipulation", validate_parameters=False, persist_result=False)
def l3_manipulation(asset_dir: Path, options: L3Options | None = None, agents: AgentConfig | None = None,
                    contract: StageContract | None = None, material: Material | None = None, recordings: bool = True,
                    progress: Progress | None = None, keep: KeepTrials = DEFAULT_KEEP,
                    on_stored: OnStored | None = None) -> tuple[ManipulationRecord, StageOutcome]:
    """L3: grasps, the harness stage over pick-and-place trials (a subflow), robustness and held-out trials (cached
    tasks), material revisions revalidated by L2 (the l2-revalidation subflow), manipulation.json.

    An object no gripper can hold is a result, not an error: manipulation.json and evidence/ record the reason as
    L3's one attempt (status 'no_grasp'). progress: a sink for 'L3 trial k of at most n: ... (elapsed)' lines.
    keep: 'adopted' (the default) leaves the reported trial's states and recording in the asset and every other
    trial's in the cache, its row naming the key (tasks.manipulation.keep); 'all' keeps every trial's in the asset.
    on_stored: told of each trial once it is stored: its row, and whether it passed (L3Context.on_stored)."""
    asset_dir = Path(asset_dir)
    options = options or L3Options()
    contract = contract or load_contract("L3")
    report = L3Progress(progress, planned_trials(contract, len(options.robustness), len(options.held_out),
                                                 options.material_fallback))
    # 1. plan: the gripper, the ranked grasps, the trial body and the squeeze range
    report.say("L3: trial body and grasp selection")
    try:
        ctx = load_context(asset_dir, options, contract, material)
    except NoGraspError as exc:
        report.say(f"L3: {exc}")
        return no_grasp_outcome(asset_dir, options, contract, material, str(exc))
    ctx.progress, ctx.recordings, ctx.on_stored = report, recordings, on_stored
    report.say(f"L3: {len(ctx.grasps)} grasp candidates, the best {ctx.grasps[0].width_m * 1000:.0f} mm wide; "
               f"{len(ctx.body.particles_m)} particles per trial")

    # 2. pick-and-place trials under the harness (action and numerical revisions)
    def runner(values: dict[str, float], action: str) -> list[ProbeResult]:
        return [ctx.trial(values, "selection", action)]

    outcome = run_harness(contract, runner, TargetBehaviour(), agents=agents, record_dir=asset_dir,
                          initial=initial_values(ctx), initial_action="revise_squeeze")

    def revalidate(revised: Material, limits: MaterialLimits) -> L2Check:  # the L3 -> L2 edge (a subflow)
        return revalidate_in_l2(asset_dir, revised, ctx.physical, limits, sim=options.sim(), asset=ctx.l0)

    # 3. the accepted plan under the training perturbations; 4. material revision: for margin when one fails, or
    # from the attempt that came closest when no plan passed
    after = robustness_and_revision(ctx, outcome, contract, revalidate)
    chosen_values, final_material, revision, robustness = after.values, after.material, after.revision, after.robustness
    passed = chosen_values is not None and (outcome.passed or final_material is not ctx.material)
    record = write_l3_record(ctx, outcome, contract, passed, chosen_values, final_material, revision, robustness, keep)
    report.say("L3 " + ("passed" + conditions_summary(record.held_out.conditions, robustness) if passed
                        else "did not pass: " + record.reason))
    return record, outcome


def write_l3_record(ctx: L3Context, outcome: StageOutcome, contract: StageContract, passed: bool,
                    values: dict[str, float] | None, material: Material, revision: MaterialRevision | None,
                    robustness: ConditionSummary | None, keep: KeepTrials) -> ManipulationRecord:
    """L3's last steps, the one writer of manipulation.json after trials ran (the l3-manipulation flow's, and a
    material confirmed from outside L3, confirm_material): 5. the final plan (`values`) under the held-out conditions
    with the final `material` (recorded apart); 6. the chosen trial (its recording under the name users open when
    ctx.recordings), every trial in ctx.attempts, the conditions, what the asset keeps (`keep`), written into
    ctx.asset_dir. `contract`: the stage's contract as given (the gates the conditions are judged by)."""
    held: list[ConditionRow] = []
    if passed and ctx.options.held_out and values is not None:
        results = ctx.under(dict(values), ctx.options.held_out, "held_out", material=material)
        held = conditions(ctx.options.held_out, results, contract).conditions
    chosen = chosen_attempt(ctx, values, material) if passed else None
    if ctx.recordings and chosen is not None:
        chosen = name_pick_and_place(ctx.asset_dir, ctx.attempts, chosen)
    record = build_record(ctx, outcome, passed, chosen, material, revision, held, robustness,
                          [a.recording for a in ctx.attempts if a.recording])  # every trial's, failed ones included
    record = keep_trials(ctx.asset_dir, record, keep)  # by default the reported trial's states alone; the rest cached
    AssetDir(ctx.asset_dir).write_manipulation(record)  # no wall time in it: a rerun writes the same file
    return record


def recorded_options(record: ManipulationRecord, device: str = "cpu", cpu_threads: int = 1) -> L3Options:
    """The L3Options a manipulation.json was run with, as far as it records them: its quality's timing (the CLI's
    draft or standard), its trial lattice and, for a passed record, its robustness and held-out conditions (a passed
    L3 records every condition it ran: none when it ran none)."""
    base = (L3Options.standard(device, cpu_threads) if record.numerics.quality == "standard"
            else L3Options(device=device, cpu_threads=cpu_threads))
    spacing = record.numerics.trial_particle_spacing_m
    if spacing:
        base = replace(base, particle_spacing_m=spacing)
    if not record.passed:
        return base
    rows = record.robustness.conditions if record.robustness is not None else []
    return replace(base, robustness=_recorded(rows), held_out=_recorded(record.held_out.conditions))


def _recorded(rows: list[ConditionRow]) -> tuple[tuple[float, float, float], ...]:
    """Conditions (x [m], y [m], yaw [deg]) as L3Options holds them, from their rows."""
    return tuple((float(r.target_xy_m[0]), float(r.target_xy_m[1]), float(r.initial_yaw_deg)) for r in rows)


def confirm_material(asset_dir: Path, check: L2Check, trigger: str, reason: str, scratch: Path | None = None,
                     device: str = "cpu", cpu_threads: int = 1, progress: Progress | None = None,
                     publish: bool = False) -> MaterialRevision | str:
    """A material from outside L3 (a calibration's) through L3's revise/re-validate edge after L2 passed it (`check`:
    flows.l3_material.revalidate_in_l2): the robot under the plan, physical model, force budget and conditions of the
    asset's manipulation.json (tasks.manipulation.material_revision.robot_confirmation), the l3-material-confirmation
    flow against the local Prefect runtime. The trials are cached tasks. Not `publish`: their interaction data go to
    `scratch`, never into the asset. `publish`: asset_dir is the working copy of an asset being published
    (tasks.publish.staged_update, swapped in whole or not at all); the trials are stored in it as L3 stores its own,
    and a material the robot confirmed becomes L3's result there as the flow's material revision does
    (write_l3_record: the held-out conditions with it, the confirmation as the reported trial, manipulation.json).
    Returns the revision (accepted: the nominal condition passed), or why the robot could not confirm it (no L3 plan
    passed on this asset)."""
    record = AssetDir(asset_dir).manipulation()
    if not record.passed or record.values is None:
        return f"L3 did not pass on this asset ({record.status}): no plan to confirm the material under"
    if check.material is None:
        raise ValueError("the L2 check names no material")
    if not publish and scratch is None:
        raise ValueError("a confirmation that does not publish needs a scratch folder for its trials")
    rev = MaterialRevision.model_validate({
        "trigger": trigger, "from": record.material, "to": check.material, "reason": reason, "failed_gates": [],
        "l2_revalidation": check, "l2_checks": [check], "plan_values": dict(record.values), "accepted": False})
    with cache.local_runtime():
        return l3_material_confirmation(Path(asset_dir), rev, recorded_options(record, device, cpu_threads),
                                        None if publish else Path(cast(Path, scratch)), progress)


@lean_flow(name="l3-material-confirmation", validate_parameters=False, persist_result=False)
def l3_material_confirmation(asset_dir: Path, revision: MaterialRevision, options: L3Options, scratch: Path | None,
                             progress: Progress | None = None) -> MaterialRevision:
    """The robot's confirmation of a material revision from outside L3 (confirm_material): the context L3 ran under
    (its material, gripper, grasps, squeeze range), then robot_confirmation under the recorded plan. scratch: where
    the trials' data go (no recordings); None: into asset_dir after the trials L3 recorded, numbered after them and
    recorded as L3 recorded its own, and an accepted revision written as L3's result (write_l3_record)."""
    record = AssetDir(asset_dir).manipulation()
    contract = load_contract("L3")
    ctx = load_context(asset_dir, options, contract, revision.from_)
    publish = scratch is None
    if publish:  # L3's trials first (the new ones numbered after them); its reported recording back under its number
        ctx.attempts, ctx.recordings = unname_pick_and_place(asset_dir, record.attempts), bool(record.recordings)
    else:
        ctx.asset_dir, ctx.recordings = Path(cast(Path, scratch)), False  # the trials' data to the scratch folder
    ctx.progress = L3Progress(progress, 1 + len(options.robustness) + (len(options.held_out) if publish else 0))
    rev = robot_confirmation(ctx, revision)
    if publish:
        if rev.accepted:
            harness = StageOutcome(stage="L3", status=record.status, message=record.message,
                                   attempts_used=record.harness_attempts)
            write_l3_record(ctx, harness, contract, True, dict(rev.plan_values), rev.to, rev, rev.robustness,
                            recorded_keep(record))
        return rev
    if rev.robustness is None:
        return rev
    # the conditions' interaction paths were the scratch folder's: name their data by cache key instead
    where = {attempt_path(a.attempt): f"in the cache, key {a.data_key}" if a.data_key else None
             for a in ctx.attempts if a.attempt is not None}
    rows = [c.model_copy(update={"attempt": where.get(c.attempt or "")}) for c in rev.robustness.conditions]
    return rev.model_copy(update={"robustness": rev.robustness.model_copy(update={"conditions": rows})})


def recorded_keep(record: ManipulationRecord) -> KeepTrials:
    """What of its trials an asset keeps, as its manipulation.json shows it: 'all' when it keeps more than one trial's
    data and every one of them, else 'adopted' (the default)."""
    stored = [a for a in record.attempts if a.attempt is not None]
    return "all" if len(stored) > 1 and all(a.kept_in == "asset" for a in stored) else "adopted"


def load_manipulation(asset_dir: Path) -> ManipulationRecord:
    """manipulation.json of an asset (InputError when L3 has not run): AssetDir's."""
    return AssetDir(asset_dir).manipulation()
