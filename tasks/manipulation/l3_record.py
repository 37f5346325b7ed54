"""manipulation.json from what L3 ran: the conditions a plan was tried under, the chosen trial (its recording under
the name users open), the attempt the manifest reports, the no-grasp outcome, and the record itself
(contracts.manipulation.ManipulationRecord)."""

from __future__ import annotations

import os
from pathlib import Path

from contracts.agents import StageOutcome
from contracts.manipulation import (BestAttempt, ConditionRow, ConditionSummary, GripperChoice, HeldOutConditions,
                                    L3Numerics, ManipulationRecord, MaterialRevision, SqueezeSummary, TrialRow)
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.stage import StageContract
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import load_l0
from tasks.manipulation.context import L3Context, L3Options, accepted, material_of, tolerances_from
from tasks.manipulation.recordings import trial_recording_name
from tasks.manipulation.report import best_attempt, failed_gate_names, record_no_grasp, trial_reason

PICK_AND_PLACE_RECORDING = "recordings/L3_pick_and_place.rrd"  # the chosen trial's recording
LABELS = ("lifted", "transported", "released_in_target", "settled", "numerically_healthy")


def conditions(conditions: tuple[tuple[float, float, float], ...], results: list[ProbeResult],
                contract: StageContract) -> ConditionSummary:
    """Per-condition outcome of one plan: target, yaw, success, labels; and how many passed."""
    rows = [ConditionRow(target_xy_m=[x, y], initial_yaw_deg=yaw, success=accepted(r.metrics, contract),
                         labels=r.metrics, attempt=r.recording) for (x, y, yaw), r in zip(conditions, results)]
    return ConditionSummary(conditions=rows, passed=sum(r.success for r in rows))


def conditions_summary(held: list[ConditionRow], robustness: ConditionSummary | None) -> str:
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


def unname_pick_and_place(asset_dir: Path, attempts: list[TrialRow]) -> list[TrialRow]:
    """The reverse of name_pick_and_place, for a record whose reported trial is about to change (a material confirmed
    from outside L3, flows.l3_manipulation.confirm_material): the row whose recording has the name users open gets
    it back under its trial's own name (recordings/L3_trial_NN.rrd; renamed, not copied), so the new reported trial
    can take the name and keep_trials can treat the old one as any other trial. Returns the rows."""
    rows = []
    for row in attempts:
        if row.recording == PICK_AND_PLACE_RECORDING and row.trial is not None:
            path = Path(asset_dir) / PICK_AND_PLACE_RECORDING
            if path.is_file():
                os.replace(path, Path(asset_dir) / trial_recording_name(row.trial))
                row = row.model_copy(update={"recording": trial_recording_name(row.trial)})
            else:
                row = row.model_copy(update={"recording": None})
        rows.append(row)
    return rows


def material_source(ctx: L3Context, material: Material, revision: MaterialRevision | None) -> str:
    """Where manipulation.json's material comes from: the context's own, an L3 material revision, or a calibrated
    material the robot confirmed (a revision with trigger 'calibration', flows.calibrate)."""
    if material is ctx.material:
        return ctx.material_source
    if revision is not None and revision.trigger == CALIBRATION_TRIGGER:
        return "calibrated from video (L2 revalidated, robot confirmed)"
    return "L3 material revision (L2 revalidated)"


CALIBRATION_TRIGGER = "calibration"  # a MaterialRevision's trigger when the material comes from `deformsmith calibrate`


def no_grasp_record(asset_dir: Path, options: L3Options, contract: StageContract, physical: PhysicalModel,
                    material: Material, source: str, reason: str) -> ManipulationRecord:
    """L3's record when no gripper can hold the object: no trial ran; the reason is L3's one attempt in evidence/
    (written here)."""
    attempts = record_no_grasp(asset_dir, reason)
    return ManipulationRecord(
        passed=False, status="no_grasp", message=reason, reason=reason, best_attempt=None, material=material,
        material_source=source, physical_model=physical, plan=None, values=None, attempt=None, outcome={}, labels={},
        forces={}, force_budget_n=tolerances_from(contract).force_budget_n, grasps=[],
        gripper=GripperChoice(name=None, reason=reason, options=[], squeeze=None),
        held_out=HeldOutConditions(conditions=[], success_rate=None), robustness=None, material_revision=None,
        numerics=L3Numerics(quality=options.quality, device=options.device), attempts=attempts, harness_attempts=1,
        recordings=[])


def no_grasp_outcome(asset_dir: Path, options: L3Options, contract: StageContract, material: Material | None,
                     reason: str) -> tuple[ManipulationRecord, StageOutcome]:
    """L3's outcome when no gripper can hold the object, its record written (manipulation.json, and the reason as
    L3's one attempt in evidence/): the given material, else the one the asset carries (material_of)."""
    adir = AssetDir(asset_dir)
    source = "given"
    if material is None:
        material, source = material_of(asset_dir, load_l0(adir.path))
    record = no_grasp_record(asset_dir, options, contract, adir.physical_model(), material, source, reason)
    adir.write_manipulation(record)
    return record, StageOutcome(stage="L3", status="no_valid_candidate", attempts_used=1, message=reason)


def chosen_attempt(ctx: L3Context, values: dict[str, float] | None, material: Material) -> TrialRow | None:
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


def build_record(ctx: L3Context, outcome: StageOutcome, accepted: bool, chosen: TrialRow | None, material: Material,
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
        material_source=material_source(ctx, material, material_revision),
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
