"""Whole, valid asset documents for test fixtures that stand in for a layer (contracts/asset_dir.py)."""

from __future__ import annotations

from typing import Any

from contracts.agents import TargetBehaviour
from contracts.asset_dir import HeldOutSummary, MaterialRecord, PhysicalRecord, SelectionSummary
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
