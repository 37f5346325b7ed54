"""Whole, valid asset documents for test fixtures that stand in for a layer (contracts/asset_dir.py)."""

from __future__ import annotations

from typing import Any

from contracts.agents import TargetBehaviour
from contracts.asset_dir import HeldOutSummary, MaterialRecord, PhysicalRecord, SelectionSummary
from contracts.manipulation import GripperChoice, HeldOutConditions, L3Numerics, ManipulationRecord, TrialRow
from contracts.material import Material
from contracts.physical import PhysicalModel


def physical_record(physical: PhysicalModel | None, message: str = "given by the test") -> PhysicalRecord:
    """physical.json of an L1 that produced `physical` (None: an L1 that failed with `message`)."""
    return PhysicalRecord(passed=physical is not None, status="accepted" if physical else "no_valid_candidate",
                          message=message, material_class=physical.category if physical else "foam", intent="",
                          mass_check={}, targets=TargetBehaviour(), physical_model=physical, metrics={}, sim_calls=0,
                          attempts=1, recordings=[])


def material_record(material: Material | None, physical: PhysicalModel, targets: TargetBehaviour | None = None,
                    metrics: dict[str, float] | None = None, screening: dict[str, Any] | None = None) -> MaterialRecord:
    """material.json of an L2 that selected `material` (None: found none) under `targets`, its metrics and the
    screening summary L2 writes (default: none ran)."""
    return MaterialRecord(
        passed=material is not None, status="accepted" if material else "no_valid_candidate", message="given by the test",
        intent="", targets=targets or TargetBehaviour(), material=material, physical_model=physical,
        metrics=metrics or {}, held_out=HeldOutSummary(metrics={}, targets_met=None, score=None, bands=[], probes=[]),
        selection=SelectionSummary(status="accepted" if material else "no_valid_candidate", score=None,
                                   targets_met=True, best_iteration=0 if material else None, attempts=1, sim_calls=0,
                                   screening=screening or {"sim_calls": 0}, ranking=[]),
        sim_calls=0, recordings={})


def manipulation_record(passed: bool, attempts: list[TrialRow], **fields: Any) -> ManipulationRecord:
    """manipulation.json of an L3 that ran `attempts` (rows) and passed or not; the other fields a stand-in's (a
    foam cube, no gripper choice recorded) unless given."""
    physical = PhysicalModel(density_kg_per_m3=300.0, volume_m3=2.7e-5, mass_kg=8.1e-3, particle_count=1000,
                             particle_spacing_m=0.003, ground_friction=0.5, gripper_friction=0.8,
                             center_of_mass_m=(0.0, 0.0, 0.015), extents_m=(0.03, 0.03, 0.03), category="foam")
    base: dict[str, Any] = dict(
        passed=passed, status="accepted" if passed else "no_valid_candidate", message="given by the test", reason="",
        material=Material(youngs_modulus_pa=5e4, poisson_ratio=0.3, damping_rate_per_s=5.0), material_source="L2",
        physical_model=physical, plan=None, values=None, attempt=None, outcome={}, labels={}, forces={},
        force_budget_n=20.0, grasps=[], gripper=GripperChoice(name=None, reason="", options=[], squeeze=None),
        held_out=HeldOutConditions(conditions=[], success_rate=None), robustness=None, material_revision=None,
        numerics=L3Numerics(quality="draft", device="cpu"), attempts=attempts, harness_attempts=len(attempts),
        recordings=[])
    return ManipulationRecord(**{**base, **fields})
