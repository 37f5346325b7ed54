"""What the manifest says of a generated asset, from its typed records: each layer's line in the validation summary,
the pick-and-place outcome of the reported trial, the attempt the video shows and the plan reported, the cache keys
of the results it carries, the files it holds by role, and the provenance that reproduces it (flows.generate writes
them)."""

from __future__ import annotations

import json
import math
from importlib import metadata
from pathlib import Path
from typing import Any

from contracts.agents import AgentConfig
from contracts.asset_dir import ASSET_JSON, GeometryRecord, MaterialRecord, PhysicalRecord, attempt_path
from contracts.manifest import PROVENANCE_LIBRARIES, Provenance, StageSummary
from contracts.manipulation import ManipulationRecord
from contracts.robot import ActionPlan, ManipulationOutcome
from contracts.sim import Device, KernelOptions
from contracts.stage import load_contract
from tasks.asset_dir import AssetDir
from tasks.manipulation.report import NO_GRASP_GATE
from tasks.record.trials import reported_attempt

LIBRARIES = PROVENANCE_LIBRARIES  # (contracts.manifest: read without this module's imports)


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def provenance(device: Device, agents: AgentConfig | None, cpu_threads: int = 1,
               kernel: KernelOptions | None = None) -> Provenance:
    """Versions, backends and numerics that reproduce the asset (the MPM kernel options when not the defaults)."""
    return Provenance(deformsmith_version=_version("deformsmith"),
                      library_versions={lib: _version(lib) for lib in LIBRARIES},
                      backends=(agents or AgentConfig.rule()).describe(), device=device, cpu_threads=cpu_threads,
                      kernel=None if kernel is None or kernel == KernelOptions() else kernel)


def finite_metrics(values: dict[str, Any]) -> dict[str, float]:
    """The numeric, finite entries (a NaN, e.g. a hold force of a trial that never held, is written to JSON as null,
    and asset.json would no longer load)."""
    return {k: float(v) for k, v in values.items()
            if isinstance(v, (int, float)) and math.isfinite(float(v))}


def stage_summary(record: GeometryRecord | PhysicalRecord | MaterialRecord) -> StageSummary:
    """L0's, L1's or L2's line in the manifest's validation summary, from its typed record: L0 is one pass that
    simulates nothing and names its failed gates; L1 counts its harness attempts; L2's line counts one (its harness
    attempts are in evidence/ and the tallies)."""
    if isinstance(record, GeometryRecord):
        return StageSummary(stage="L0", passed=record.passed, attempts=1, sim_calls=0,
                            metrics=finite_metrics(record.metrics), failed_gates=list(record.failed_gates))
    return StageSummary(stage=record.stage, passed=record.passed,
                        attempts=record.attempts if isinstance(record, PhysicalRecord) else 1,
                        sim_calls=record.sim_calls, metrics=finite_metrics(record.metrics), failed_gates=[])


def l3_summary(record: ManipulationRecord) -> StageSummary:
    """L3's line in the validation summary: trials run (sim calls), the reported attempt's labels, its failed gates
    and the reason in words (no grasp: the one failed gate 'grasp available')."""
    trials = [a for a in record.attempts if a.labels and not a.labels.get("plan_failed")]
    metrics = finite_metrics(record.reported_labels())
    if record.passed:
        failed: list[str] = []
    elif record.status == "no_grasp":
        failed = [NO_GRASP_GATE]
    elif record.best_attempt is not None:
        failed = list(record.best_attempt.failed_gates)  # judged under the contract L3 ran with
    else:
        failed = [g.name for g in load_contract("L3").hard_gates if not g.passes(metrics.get(g.metric))]
    reason = None if record.passed else (record.reason or record.message or None)
    attempts = record.harness_attempts or len(record.attempts)  # harness attempts, as evidence
    return StageSummary(stage="L3", passed=record.passed, attempts=attempts,
                        sim_calls=len(trials), metrics=metrics, failed_gates=failed, reason=reason)


FILE_ROLES = {"manifest": ASSET_JSON, "mesh": "mesh.glb", "collision": "collision", "particles": "particles.zarr",
              "gaussians": "gaussians.ply", "evidence": "evidence", "recordings": "recordings", "renders": "renders",
              "interaction": "interaction", "geometry_record": "geometry.json", "physical_record": "physical.json",
              "material_record": "material.json", "manipulation_record": "manipulation.json",
              "physgaussian_config": "export/physgaussian_config.json",
              "drop_video_front": "renders/drop_front.mp4", "drop_video_side": "renders/drop_side.mp4",
              "pick_and_place_video": "renders/pick_and_place.mp4", "card_png": "renders/card.png",
              "card_html": "renders/card.html"}  # the manifest's `files`: role -> path in the asset directory


def asset_files(work: Path) -> dict[str, str]:
    """Role -> relative path of what the asset directory holds (the manifest always)."""
    return {role: rel for role, rel in FILE_ROLES.items() if (work / rel).exists() or role == "manifest"}


def shown_attempt(record: ManipulationRecord) -> int | None:
    """The attempt the pick-and-place video shows: the accepted one, else the one the manifest reports, else the
    last trial that ran (the one trial whose states a default asset keeps: tasks.manipulation.keep)."""
    return reported_attempt(record)


def reported_plan(record: ManipulationRecord) -> ActionPlan | None:
    """The manifest's action plan: the adopted one, else the best plan tried (None when no plan was possible)."""
    return record.plan or (record.best_attempt.plan if record.best_attempt else None)


def cache_keys(work: Path, l3: ManipulationRecord | None) -> dict[str, str]:
    """Task -> cache key of the results the asset carries: L2's chosen candidate's probes and its held-out probes,
    L3's reported trial and its robustness and held-out trials (`CacheStore(root).get(key)` returns each)."""
    keys: dict[str, str] = {}
    if AssetDir(work).has("material"):
        l2 = AssetDir(work).material()
        best = l2.selection.best_iteration
        attempts = work / "evidence" / "L2_attempts.jsonl"
        if best is not None and attempts.is_file():
            for line in attempts.read_text(encoding="utf-8").splitlines():
                a = json.loads(line) if line.strip() else {}
                if a.get("iteration") == best:
                    for i, key in enumerate((a.get("evidence") or {}).get("probe_keys") or []):
                        keys[f"l2.selection.{i}"] = str(key)
        for probe in l2.held_out.probes:  # ProbeResult dumps
            if probe["cache_key"]:
                keys[f"l2.{probe['spec']['kind']}.held_out"] = str(probe["cache_key"])
    if l3:
        if l3.best_attempt is not None and l3.best_attempt.cache_key:
            keys["l3.trial"] = l3.best_attempt.cache_key
        # a condition row names its trial by its interaction path (None: the plan failed, nothing was stored)
        by_path = {(attempt_path(a.attempt) if a.attempt is not None else None): a.cache_key for a in l3.attempts}
        groups = {"robustness": l3.robustness.conditions if l3.robustness else [], "held_out": l3.held_out.conditions}
        for group, rows in groups.items():
            for i, row in enumerate(rows):
                key = by_path.get(row.attempt)
                if key:
                    keys[f"l3.trial.{group}.{i}"] = key
    return keys


def manipulation_outcome(labels: dict[str, float]) -> Any:
    """The manifest's ManipulationOutcome from a trial's labels (None when no trial ran)."""
    if not labels or labels.get("plan_failed"):
        return None
    return ManipulationOutcome(
        lifted=bool(labels["lifted"]), transported=bool(labels["transported"]),
        released_in_target=bool(labels["released_in_target"]), settled=bool(labels["settled"]),
        slipped=bool(labels["slipped"]), force_budget_violated=bool(labels["force_budget_violated"]),
        numerically_healthy=bool(labels["numerically_healthy"]), max_strain=float(labels["max_strain"]),
        strain_p99=float(labels["strain_p99"]) if "strain_p99" in labels else None,
        max_finger_force_n=(float(labels["max_finger_force_0_n"]), float(labels["max_finger_force_1_n"])),
        slip_distance_m=float(labels["slip_distance_m"]), place_error_m=float(labels["place_error_m"]))
