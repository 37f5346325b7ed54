"""L3's context: how L3 runs (L3Options), what a trial needs that L3 does not edit (L3Context: the trial body,
the physical model, the material, the ranked grasps, the gripper and its squeeze range, the contract), the candidate's
plan under a condition, the trial task's inputs (hashed into its cache key: keep them as they are) and the storing of
each trial as an interaction attempt and a row of manipulation.json.

The cached trial task and Prefect's concurrency are the flow's (flows/l3_manipulation.py): it hands the context a
TrialRunner.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Protocol, TypedDict

import numpy as np

from cache import CacheMiss, CacheStore, cache_relative, cache_root, content_key
from cache.files import cached_file, source_digest
from contracts.asset_dir import attempt_path
from contracts.manipulation import GripperOption, TrialCondition, TrialRow
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult
from contracts.robot import DEFAULT_GRIPPER, ActionPlan, GraspCandidate
from contracts.sim import SimConfig
from contracts.stage import L3Parameters, StageContract, packaged_parameters
from tasks.agents import targets_from_intent
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset
from tasks.manipulation.body import TrialBody
from tasks.manipulation.data import attempt_indices, interaction_root, write_attempt
from tasks.manipulation.diagnosis import MODES
from tasks.manipulation.outcome import TrialTolerances, force_budget_n
from tasks.manipulation.recordings import cached_recording_path, record_attempt
from tasks.manipulation.report import L3Progress, trial_reason
from tasks.manipulation.trial import TrialSettings, plan_or_error, reachable_plan
from tasks.robot.grasp import GraspSettings
from tasks.robot.gripper import gripper
from tasks.robot.squeeze import SqueezePlan

CORE_FIELDS = ("grasp_rank", "squeeze_depth_m", "closing_speed_m_per_s", "lift_duration_s", "transport_duration_s",
               "substeps")  # the plan's fields every L3 contract has
SURFACE_SAMPLES = 2000  # surface points for grasp sampling (the trial body's, and the gripper choice's)


class TrialRunner(Protocol):
    """Runs the cached trial task (the flow's): each inputs dict -> {'probe', 'arrays', 'info'}, in order; and names
    the cache key of one."""

    def run(self, inputs: list[dict[str, Any]], device: str) -> list[dict[str, Any]]: ...

    def key(self, inputs: dict[str, Any]) -> str | None: ...


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
    material_fallback: bool = True  # when no plan passes, ask L2 for a material within its bands
    # (tasks.manipulation.material_revision)
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


def body_from(particles_m: np.ndarray, volumes_m3: np.ndarray, spacing_m: float, source_spacing_m: float,
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


@functools.cache
def _attempt_code() -> str:
    """The code part of an encoded attempt's cache key: the encoder's sources and the libraries that write it."""
    root = Path(__file__).resolve().parent
    return source_digest([root / "data.py", root / "particle_frames.py"], ("numcodecs", "numpy", "zarr"))


PLAN_CHECK_VERSION = "1"  # bump when what plan_executable answers changes beyond the code _reach_code digests


@functools.cache
def _reach_code() -> str:
    """The code part of a plan's reachability key (plan_executable): the trajectory planner and the Panda
    (tasks/robot but its drawing), plan_or_error and the trial settings' defaults (trial.py), the gripper specs and the
    robot contract, and the libraries they compute with (pybullet: the Panda's URDF and IK)."""
    here = Path(__file__).resolve().parent
    root = here.parent.parent
    robot = [p for p in (root / "tasks" / "robot").rglob("*")
             if p.is_file() and "__pycache__" not in p.parts and p.name != "visual.py"]
    return source_digest([*robot, here / "trial.py", root / "tasks" / "quiet_pybullet.py", root / "contracts" / "grippers",
                          root / "contracts" / "robot.py"], ("numpy", "pybullet", "scipy", "trimesh"))


def plan_executable(plan: ActionPlan, body: TrialBody) -> bool:
    """Whether the arm can execute `plan` on `body` (plan_or_error's trajectory is not None: IK, the dense pad table,
    the table test), remembered in the content cache by the plan, the body's height and the planner's code. A trial's
    plan is checked this way before its cached task runs (reachable_plan; the trial plans it again inside the task on a
    miss), ~1 s on the CPU per plan: a fully cached rerun of the default turtle checked 6 plans, 6-7 s of its wall
    time (#37)."""
    key = content_key("l3.plan_executable", PLAN_CHECK_VERSION, _reach_code(), plan, float(body.height_m))
    store = CacheStore(cache_root())
    try:
        return bool(store.get(key))
    except CacheMiss:
        pass
    ok = plan_or_error(plan, body)[0] is not None
    store.put(key, ok, meta={"task": "l3.plan_executable"})
    return ok


def store_attempt(asset_dir: Path, arrays: dict[str, np.ndarray], attrs: dict[str, Any]) -> int:
    """Store a trial as the asset's next interaction attempt (tasks.manipulation.data.write_attempt) through the cache:
    a rerun copies the attempt encoded before from the same arrays, attributes, index and encoder code instead of
    compressing its particle frames again (~0.3-1 s a trial on two cores). Returns the attempt's index."""
    return store_attempt_keyed(asset_dir, arrays, attrs)[0]


def store_attempt_keyed(asset_dir: Path, arrays: dict[str, np.ndarray], attrs: dict[str, Any],
                        first: int = 0) -> tuple[int, str]:
    """store_attempt, and the cache key the attempt's Zarr group is stored under (the trial row's data_key: the
    asset may later drop the folder, tasks.manipulation.keep; CacheStore(root).get(key) gives it back). first: the
    lowest index it may take (after the rows of trials whose folders the asset no longer holds)."""
    n = max(max(attempt_indices(asset_dir), default=-1) + 1, first)
    interaction_root(asset_dir)
    attrs_json = json.dumps({**attrs, "attempt": n}, sort_keys=True,
                            default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    key = content_key("l3.interaction_attempt/1", _attempt_code(), {k: np.asarray(v) for k, v in arrays.items()},
                      attrs_json)
    cached_file(key, Path(asset_dir) / attempt_path(n), lambda _: write_attempt(asset_dir, arrays, attrs, index=n))
    return n, key


def tolerances_from(contract: StageContract) -> TrialTolerances:
    """Label limits from the L3 contract (parameters and the force-budget gate)."""
    p = L3Parameters.of(contract)
    return TrialTolerances(lift_height_m=p.lift_height_m, place_tolerance_m=p.place_tolerance_m,
                           slip_tolerance_m=p.slip_tolerance_m, force_budget_n=force_budget_n(contract))


OnStored = Callable[[TrialRow, bool], None]  # a stored trial's row and whether it passed every hard gate


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
    grasp_settings: GraspSettings | None = None  # the sampler's (the hand's collision test of a turned approach)
    progress: L3Progress = field(default_factory=L3Progress)
    l0: L0Asset | None = None  # the L0 data the body was built from (L2's revalidation probes it too)
    runner: TrialRunner | None = None  # runs the cached trial task (the flow's); needed before the first trial
    on_stored: OnStored | None = None  # told of each trial once it is stored (generate: the video of a passed
    # selection trial is drawn while L3 goes on)

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
        # a yawed condition may turn a side grasp out of reach: the same contacts from another side, else another grasp
        return reachable_plan(plan, self.grasps, self.body, grasp_settings=self.grasp_settings,
                              executable=lambda p: plan_executable(p, self.body))

    def trial(self, values: dict[str, float], role: str, action: str = "", material: Material | None = None,
              target_xy_m: tuple[float, float] | None = None, yaw_deg: float = 0.0) -> ProbeResult:
        """Run (or fetch from the cache) one trial and store it as an interaction attempt."""
        plan, inputs = self._trial_inputs(values, material, target_xy_m, yaw_deg)
        self.progress.trials(len(self.attempts) + 1, 1, _what(role, action, values))
        probe = self._store(self._runner().run([inputs], self.options.device)[0], plan, inputs, values, role, action,
                            material, yaw_deg)
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
        key = self._runner().key(inputs)
        probe: ProbeResult = out["probe"]
        attrs = {"labels": probe.metrics, "plan": plan.model_dump(mode="json"), "info": {k: v for k, v in out["info"].items() if k != "wall_time_s"},
                 "role": role, "action": action, "values": values, "cache_key": key,
                 "material": (material or self.material).model_dump(mode="json"),
                 "physical_model": self.physical.model_dump(mode="json")}
        after = max((a.attempt for a in self.attempts if a.attempt is not None), default=-1) + 1  # a row may name a
        # folder the asset dropped (kept in the cache): a new trial never reuses its index
        n, data_key = (store_attempt_keyed(self.asset_dir, out["arrays"], attrs, after) if out["arrays"]
                       else (None, None))
        trial = len(self.attempts) + 1  # the trial's one number (tasks.record.trials)
        rrd = (record_attempt(self.asset_dir, trial, out["arrays"], {**attrs, "trial": trial}, key)
               if n is not None and self.recordings else None)
        stored: dict[str, Any] = {"data_key": data_key} if data_key is not None else {}
        if rrd is not None and key is not None:  # its recording as the cache holds it (the asset's copy may go)
            stored["recording_in_cache"] = cache_relative(cached_recording_path(key))
        self.attempts.append(TrialRow(attempt=n, role=role, action=action, values=values, labels=probe.metrics,
                                      cache_key=key, recording=rrd,
                                      condition=TrialCondition(target_xy_m=list(plan.target_xy_m), yaw_deg=yaw_deg),
                                      **stored))
        if self.on_stored is not None:
            self.on_stored(self.attempts[-1], not trial_reason(probe.metrics, self.contract,
                                                               tolerances_from(self.contract)))
        return probe.model_copy(update={"cache_key": key, "recording": attempt_path(n) if n is not None else None})

    def under(self, values: dict[str, float], conditions: tuple[tuple[float, float, float], ...], role: str,
              action: str = "", material: Material | None = None) -> list[ProbeResult]:
        """One trial per condition (x [m], y [m], yaw [deg]): the robustness or the held-out conditions. The trials
        are independent: on the CPU the runner runs them side by side (the flow's: Prefect's thread-pool task runner),
        then are stored as attempts in the order of `conditions`, as one after another would."""
        runs = [self._trial_inputs(values, material, (x, y), yaw) for x, y, yaw in conditions]
        self.progress.trials(len(self.attempts) + 1, len(runs), f"{role}, {len(runs)} conditions side by side"
                             + (f" ({action})" if action else ""))
        outs = self._runner().run([inputs for _, inputs in runs], self.options.device)
        stored = [self._store(out, plan, inputs, values, role, action, material, yaw)
                  for (plan, inputs), out, (_, _, yaw) in zip(runs, outs, conditions)]
        for i, probe in enumerate(stored):
            self._report(probe, len(self.attempts) - len(stored) + i + 1)
        return stored

    def _runner(self) -> TrialRunner:
        if self.runner is None:
            raise RuntimeError("L3Context.runner is not set: the flow gives it (flows.l3_manipulation.load_context)")
        return self.runner

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


class HoldInputs(TypedDict):
    """The keyword inputs that choose_gripper and squeeze_plan share (SI units)."""

    youngs_modulus_pa: float
    poisson_ratio: float
    mass_kg: float
    gravity_m_per_s2: float
    budget_n: float
    margin: float
    floor_n: float


def hold_inputs(physical: PhysicalModel, material: Material, contract: StageContract) -> HoldInputs:
    """What the hold force and the squeeze estimate need: material, mass, gravity, force budget and margin."""
    p = L3Parameters.of(contract)
    budget = tolerances_from(contract).force_budget_n
    cap = p.grip_force_limit_n or 0.5 * budget
    # without a hold margin (position control) the squeeze estimate still needs one: the packaged contract's
    margin = p.hold_force_margin or packaged_parameters("L3")["hold_force_margin"]
    return {"youngs_modulus_pa": material.youngs_modulus_pa, "poisson_ratio": material.poisson_ratio,
            "mass_kg": physical.mass_kg, "gravity_m_per_s2": float(np.linalg.norm(physical.gravity_m_per_s2)),
            "budget_n": min(budget, 2.0 * cap), "margin": float(margin), "floor_n": p.hold_force_floor_n}


def with_squeeze_range(contract: StageContract, sq: SqueezePlan) -> StageContract:
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
    info = geometry_info(asset.record)
    words = " ".join(str(x) for x in (info.name, info.category) if x) or "foam"
    p = targets_from_intent(words).priors  # the vocabulary's default material fills what the words leave out
    return Material(youngs_modulus_pa=p["youngs_modulus_pa"], poisson_ratio=p["poisson_ratio"],
                    damping_rate_per_s=p["damping_rate_per_s"]), "vocabulary prior"


def accepted(metrics: dict[str, float], contract: StageContract) -> bool:
    """Every hard gate passes."""
    return all(g.passes(metrics.get(g.metric)) for g in contract.hard_gates)
