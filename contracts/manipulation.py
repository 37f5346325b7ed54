"""L3's record, manipulation.json, as typed models end to end: the trials (one row each), the conditions a plan was
tried under (robustness, held out), the attempt the manifest reports, the gripper the Planner chose, the material
revision and its L2 revalidation, the numerics.

Each model holds exactly the keys L3 writes, so a record read and written back is the same JSON: a key that older
records (or some rows: a plan that never ran, the no-grasp outcome) lack is in the model's ABSENT_UNLESS_GIVEN and
stays absent unless it was given.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import ConfigDict, Field, SerializerFunctionWrapHandler, model_serializer

from contracts.base import Model
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan, GraspCandidate

Labels = dict[str, float]  # a trial's metrics and outcome labels (ProbeResult.metrics; NaN: not measured)
PlanValues = dict[str, float]  # a candidate's editable fields (the L3 contract's)


class Row(Model):
    """A part of manipulation.json whose keys in ABSENT_UNLESS_GIVEN are written only when they were given."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset()

    @model_serializer(mode="wrap")
    def _drop_absent(self, handler: SerializerFunctionWrapHandler) -> Any:
        out = handler(self)
        if isinstance(out, dict):
            for key in self.ABSENT_UNLESS_GIVEN:
                if key not in self.model_fields_set:
                    out.pop(key, None)
        return out


class TrialCondition(Row):
    """Where a trial put the object down and how it stood at the start."""

    target_xy_m: list[float]
    yaw_deg: float


class TrialRow(Row):
    """One trial (one simulated pick-and-place; the no-grasp outcome's one row ran none): manipulation.json
    `attempts`."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"values", "cache_key", "recording", "condition",
                                                               "trial", "reason", "data_key", "kept_in",
                                                               "recording_in_cache", "frame_stride"})
    attempt: int | None = Field(description="its interaction folder (interaction/attempt_NNN); None: nothing stored")
    role: str = Field(description="selection, robustness, confirmation, held_out, grasp_selection")
    action: str = Field(description="the harness action that asked for it ('' for a condition trial)")
    values: PlanValues = Field(default_factory=dict)
    labels: Labels
    cache_key: str | None = None
    recording: str | None = None
    condition: TrialCondition | None = None
    trial: int | None = Field(default=None, description="its number, from 1 in the order run (tasks.record.trials)")
    reason: str = Field(default="", description="why it failed L3, in words ('' when it passed every gate)")
    data_key: str | None = Field(default=None, description="the cache key of its interaction data: "
                                 "CacheStore(cache root).get(data_key) is the attempt_NNN Zarr group (#38)")
    kept_in: Literal["asset", "cache"] = Field(
        default="asset", description="where its interaction data and recording are: the asset (interaction/"
        "attempt_NNN, `recording`), or only the cache (data_key, recording_in_cache): by default an asset keeps the "
        "reported trial's alone (`--record all` keeps every trial's); records before #38: absent, the asset")
    recording_in_cache: str | None = Field(default=None, description="its Rerun recording's path under the cache "
                                           "root (recordings/L3_trial-<key>-r<version>.rrd)")
    frame_stride: int = Field(default=1, ge=1, description="the asset keeps every frame_stride-th of its particle "
                              "frames (the first and last kept) so that its states fit the asset's budget "
                              "(tasks.manipulation.keep.KEPT_FRAMES_BYTES); every frame stays in the cache entry "
                              "data_key, and `--record all` keeps them in the asset")


class ConditionRow(Row):
    """One plan under one condition (robustness or held out)."""

    target_xy_m: list[float]
    initial_yaw_deg: float
    success: bool
    labels: Labels
    attempt: str | None = Field(description="the trial's interaction path (None: the plan failed, nothing stored)")


class ConditionSummary(Row):
    """The accepted plan under the robustness conditions: each condition and how many passed."""

    conditions: list[ConditionRow]
    passed: int


class HeldOutConditions(Row):
    """The final plan under the held-out conditions (recorded apart from the selection)."""

    conditions: list[ConditionRow]
    success_rate: float | None


class BestAttempt(Row):
    """The attempt the manifest reports: the adopted one, else the best trial under the asset's own material."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"trial"})
    attempt: int | None
    trial: int | None = None
    role: str
    values: PlanValues
    labels: Labels
    plan: ActionPlan
    cache_key: str | None
    failed_gates: list[str]
    reason: str


class SqueezeSummary(Row):
    """tasks.robot.squeeze.SqueezePlan: force target per finger [N], stiffness estimate, squeeze depth and range."""

    force_target_n: float
    stiffness_n_per_m: float
    depth_m: float
    low_m: float
    high_m: float
    soft_indent_m: float
    torsion_force_n: float = 0.0  # the force per finger the weight's torque about the closing axis asks for [N]

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"torsion_force_n"})  # records before it keep their bytes


class GripperOption(Row):
    """One gripper the Planner's choose_gripper weighed (tasks.robot.choice.GripperChoice.summary)."""

    gripper: str
    stroke_m: float
    good: bool
    note: str
    grasps: int
    best_width_m: float | None
    com_offset_m: float | None
    squeeze: SqueezeSummary | None


class GripperChoice(Row):
    """The gripper, why, what was weighed; the force target and squeeze range of the best grasp."""

    name: str | None
    reason: str
    options: list[GripperOption]
    squeeze: SqueezeSummary | None


class L2Check(Row):
    """L2's revalidation of a revised material (flows.l3_material.revalidate_in_l2)."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"material", "held_out_gates", "held_out_metrics",
                                                               "held_out_probes"})
    material: Material | None = Field(default=None, description="the material revalidated (L3 always writes it)")
    passed: bool
    gates: dict[str, bool]
    bands: dict[str, bool]
    metrics: dict[str, float]
    probe_keys: list[str]
    held_out_gates: dict[str, bool] = Field(default_factory=dict, description="each L2 hard gate on the held-out "
                                            "tests' metrics (given when they ran: a calibrated material's check)")
    held_out_metrics: dict[str, float] = Field(default_factory=dict, description="the held-out tests' metrics")
    held_out_probes: list[str] = Field(default_factory=list, description="the held-out tests run, in the contract's "
                                       "order (probe kind)")


class MaterialRevision(Row):
    """A material revision asked by the robot, its L2 revalidation and the robot's confirmation under the same plan."""

    model_config = ConfigDict(**Model.model_config, serialize_by_alias=True, validate_by_name=True,
                              validate_by_alias=True)
    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"l2_checks", "confirmation", "robustness"})
    trigger: str = Field(description="robustness, escalation, no plan passed (L3's own); calibration (a material "
                         "fitted to a video, `deformsmith calibrate`)")
    from_: Material = Field(alias="from")
    to: Material
    reason: str
    failed_gates: list[str]
    l2_revalidation: L2Check = Field(description="the last of l2_checks")
    l2_checks: list[L2Check] = Field(default_factory=list, description="every revalidation, a half-way retry too")
    plan_values: PlanValues
    accepted: bool
    confirmation: Labels | None = Field(default=None, description="the nominal condition's labels under the revised "
                                        "material (given when L2 passed it)")
    robustness: ConditionSummary | None = None


class L3Numerics(Row):
    """How the trials were simulated (the no-grasp outcome: quality and device only)."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"trial_particle_spacing_m", "l0_particle_spacing_m",
                                                               "trial_particles", "grid_dx_m", "note"})
    quality: str
    device: str
    trial_particle_spacing_m: float | None = None
    l0_particle_spacing_m: float | None = None
    trial_particles: int | None = None
    grid_dx_m: float | None = None
    note: str = ""


class ManipulationRecord(Row):
    """manipulation.json: L3's outcome, the chosen plan and every trial (status 'no_grasp': no trial could run)."""

    ABSENT_UNLESS_GIVEN: ClassVar[frozenset[str]] = frozenset({"best_attempt", "trial"})  # keys older records lack
    schema_version: int = 1
    stage: Literal["L3"] = "L3"
    passed: bool
    status: str = Field(description="the harness's OutcomeStatus, or 'no_grasp'")
    message: str
    reason: str
    best_attempt: BestAttempt | None = Field(default=None, description="records before it: absent")
    material: Material
    material_source: str
    physical_model: PhysicalModel
    plan: ActionPlan | None
    values: PlanValues | None
    attempt: int | None
    trial: int | None = Field(default=None, description="the adopted trial's number (from 1, in the order run: "
                              "tasks.record.trials); records before #36: absent")
    outcome: dict[str, bool]
    labels: Labels
    forces: dict[str, float]
    force_budget_n: float
    grasps: list[GraspCandidate]
    gripper: GripperChoice
    held_out: HeldOutConditions
    robustness: ConditionSummary | None
    material_revision: MaterialRevision | None
    numerics: L3Numerics
    attempts: list[TrialRow]
    harness_attempts: int
    recordings: list[str]

    def reported_labels(self) -> Labels:
        """The labels the manifest reports: the adopted trial's, else the best trial under the asset's own material,
        else (a record written before best_attempt existed) the last trial that ran."""
        ran = [a for a in self.attempts if a.labels and not a.labels.get("plan_failed")]
        return dict(self.labels or (self.best_attempt.labels if self.best_attempt else {})
                    or (ran[-1].labels if ran else {}))

    def trial_of_attempt(self, attempt: int | None) -> int | None:
        """The trial number (from 1, in the order run: tasks.record.trials) of the row whose interaction folder is
        attempt_NNN; a record written before #36 lacks the rows' `trial`: their position then."""
        if attempt is None:
            return None
        return next((a.trial or i + 1 for i, a in enumerate(self.attempts) if a.attempt == attempt), None)

    def simulated_trials(self) -> int:
        """How many trials simulated a pick-and-place (a plan that could not run simulated nothing)."""
        return sum(1 for a in self.attempts if a.labels and not a.labels.get("plan_failed"))

    def adopted_revision(self) -> MaterialRevision | None:
        """The material revision L3 passed with (L2 revalidated, robot confirmed), else None."""
        rev = self.material_revision
        return rev if self.passed and rev is not None and rev.accepted else None


__all__ = ["BestAttempt", "ConditionRow", "ConditionSummary", "GripperChoice", "GripperOption", "HeldOutConditions",
           "L2Check", "L3Numerics", "Labels", "ManipulationRecord", "MaterialRevision", "PlanValues", "Row",
           "SqueezeSummary", "TrialCondition", "TrialRow"]
