"""Pydantic data model and stage contracts (data). SI units everywhere; no heavy imports here."""

from contracts.base import Model
from contracts.errors import CacheError, ContractError, DeformSmithError, InputError, SimulationError
from contracts.evidence import AgentSource, Attempt, EvidenceRecord, GateResult
from contracts.manifest import AssetManifest, Provenance, StageSummary
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import HealthStatus, ProbeResult, ProbeSpec
from contracts.request import AssetRequest
from contracts.robot import ActionPlan, GraspCandidate, ManipulationOutcome
from contracts.shape import ShapeProgram
from contracts.sim import SimConfig
from contracts.stage import EditableField, HardGate, StageContract, load_contract, load_contract_file

__all__ = [
    "Model", "CacheError", "ContractError", "DeformSmithError", "InputError", "SimulationError",
    "AgentSource", "Attempt", "EvidenceRecord", "GateResult", "AssetManifest", "Provenance", "StageSummary",
    "Material", "PhysicalModel", "HealthStatus", "ProbeResult", "ProbeSpec", "AssetRequest", "ActionPlan",
    "GraspCandidate", "ManipulationOutcome", "ShapeProgram", "SimConfig", "EditableField", "HardGate",
    "StageContract", "load_contract", "load_contract_file",
]
