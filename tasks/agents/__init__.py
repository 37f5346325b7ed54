"""The harness's roles: rule and litellm backends, intent -> targets, the orchestrator loop and its records.

Layer engineers need: `run_stage(contract, probe_runner, targets, ...)` (or the Prefect flow `flows.harness`),
`targets_from_request(request)`, `AttemptRecorder(asset_dir, stage)` and `build_roles(AgentConfig)`.
"""

from tasks.agents.intent import targets_from_intent, targets_from_request
from tasks.agents.orchestrator import ProbeRunner, Roles, merge_metrics, run_stage
from tasks.agents.records import AttemptRecorder, read_attempts
from tasks.agents.roles import build_roles

__all__ = ["AttemptRecorder", "ProbeRunner", "Roles", "build_roles", "merge_metrics", "read_attempts", "run_stage",
           "targets_from_intent", "targets_from_request"]
