"""Name -> model for every agent-facing schema (`deformsmith schema NAME`)."""

from __future__ import annotations

from pydantic import BaseModel

from contracts.agents import AGENT_SCHEMAS
from contracts.evidence import Attempt, EvidenceRecord
from contracts.manifest import AssetManifest
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, ProbeSpec
from contracts.request import AssetRequest
from contracts.robot import ActionPlan, GraspCandidate, GripperSpec, ManipulationOutcome
from contracts.shape import ShapeProgram
from contracts.sim import SimConfig
from contracts.stage import StageContract

SCHEMAS: dict[str, type[BaseModel]] = {
    m.__name__: m
    for m in (
        AssetRequest, ShapeProgram, PhysicalModel, Material, SimConfig, ProbeSpec, ProbeResult,
        GraspCandidate, GripperSpec, ActionPlan, ManipulationOutcome, StageContract, Attempt, EvidenceRecord,
        AssetManifest,
    )
}


def register_schema(model: type[BaseModel]) -> type[BaseModel]:
    """Add a model to the registry (used by modules that define more agent-facing models)."""
    SCHEMAS[model.__name__] = model
    return model


def _register_agent_schemas() -> None:
    """Add the harness's role I/O models (contracts.agents)."""
    for model in AGENT_SCHEMAS:
        register_schema(model)


_register_agent_schemas()


def schema_model(name: str) -> type[BaseModel]:
    """Look a model up by name, case-insensitively."""
    by_lower = {k.lower(): v for k, v in SCHEMAS.items()}
    try:
        return by_lower[name.lower()]
    except KeyError:
        raise KeyError(name) from None
