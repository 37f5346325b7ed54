"""The reusable harness flow: one stage's plan -> design -> probe (cached tasks) -> gate -> critique loop."""

from __future__ import annotations

import inspect
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cache  # noqa: F401  (sets the local Prefect environment before prefect is imported)
from prefect.futures import PrefectFuture, wait
from prefect.task_runners import ThreadPoolTaskRunner

from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig, StageOutcome, TargetBehaviour
from contracts.probes import ProbeResult
from contracts.stage import StageContract, StageName, load_contract
from tasks.agents.orchestrator import ProbeRunner, run_stage
from tasks.agents.records import AttemptRecorder
from tasks.agents.roles import build_roles
from tasks.agents.vocab import stage_routes
from tasks.probes.registry import with_probe_routes
from cache import content_key
from cache.prefect_task import KEY_SCHEMA

InputBuilder = Callable[[dict[str, float], str], dict[str, Any]]


def _values_only(values: dict[str, float], action: str) -> dict[str, Any]:
    return {"values": values}


@dataclass(frozen=True)
class ProbeCall:
    """One probe of a stage: a Prefect task (e.g. `@cached_task`) returning a ProbeResult, its fixed inputs, and
    how the candidate becomes task inputs (default: `values=<dict of editable fields>`)."""

    task: Any
    fixed: dict[str, Any] = field(default_factory=dict)
    inputs: InputBuilder = _values_only


def probe_cache_key(task: Any, inputs: dict[str, Any]) -> str | None:
    """The content key a `cached_task` computes for these inputs (None for a task without a content policy)."""
    if getattr(task, "version", None) is None or not hasattr(task, "fn"):
        return None
    sig = inspect.signature(task.fn)
    bound = sig.bind_partial(**inputs)
    bound.apply_defaults()
    return content_key(KEY_SCHEMA, task.name, str(task.version), dict(bound.arguments))


def _with_key(state: Any, key: str | None) -> ProbeResult:
    """The task's ProbeResult, carrying its cache key when the probe did not set one."""
    result = state.result()
    if not isinstance(result, ProbeResult):
        raise TypeError(f"a probe task must return a ProbeResult, got {type(result).__name__}")
    if key and result.cache_key is None:
        result = result.model_copy(update={"cache_key": key})
    return result


def task_states(calls: Sequence[tuple[Any, dict[str, Any]]], workers: int = 1,
                device: str | None = "cpu") -> list[Any]:
    """Run each (Prefect task, inputs) and return the final states in call order: up to `workers` at a time through
    Prefect's ThreadPoolTaskRunner (each a task run of the calling flow run, submitted in a copy of the caller's
    context), else one after another on the caller's thread. device="cpu": the tasks launch CPU MPM kernels, so the
    engine's Warp modules are loaded before they run side by side (tasks.mpm.cpu_launch.load_cpu_modules)."""
    if workers <= 1 or len(calls) <= 1:
        return [task(**inputs, return_state=True) for task, inputs in calls]
    if device == "cpu":
        from tasks.mpm.cpu_launch import load_cpu_modules  # lazy: pulls warp (1.3 s); L0 and L1 run no MPM

        load_cpu_modules()
    runner: ThreadPoolTaskRunner[Any]
    with ThreadPoolTaskRunner(max_workers=workers) as runner:
        futures: list[PrefectFuture[Any]] = [runner.submit(task, inputs) for task, inputs in calls]
        wait(futures)  # every run ends before the runner closes (closing cancels what has not started)
    return [future.state for future in futures]


def call_tasks(calls: Sequence[tuple[Any, dict[str, Any]]], workers: int = 1, device: str | None = "cpu") -> list[Any]:
    """Call each (Prefect task, inputs) of CPU MPM probes and return the results in order, up to `workers` at a time
    (task_states); an error is raised once every call has finished (one worker: at once, as a direct call does)."""
    if workers <= 1 or len(calls) <= 1:
        return [task(**inputs) for task, inputs in calls]
    return [state.result() for state in task_states(calls, workers, device)]


def task_probe_runner(probes: Sequence[ProbeCall], parallel: bool = False) -> ProbeRunner:
    """A ProbeRunner that calls each probe task (inside the running flow: cached, a hit runs nothing); parallel: all of
    a candidate's probes at once, through Prefect's thread-pool task runner (task_states)."""

    def run(values: dict[str, float], action: str) -> list[ProbeResult]:
        calls = [(p.task, {**p.fixed, **p.inputs(dict(values), action)}) for p in probes]
        keys = [probe_cache_key(t, kw) for t, kw in calls]
        states = task_states(calls, len(calls) if parallel else 1, device=None)
        return [_with_key(state, k) for state, k in zip(states, keys)]

    return run


@lean_flow(name="harness-stage", validate_parameters=False, persist_result=False)  # the probe runner: by name
def harness_stage(
    contract: StageContract,
    probe_runner: Callable[[dict[str, float], str], Sequence[ProbeResult]],
    targets: TargetBehaviour | None = None,
    agents: AgentConfig | None = None,
    initial: dict[str, float] | None = None,
    initial_action: str | None = None,
    record_dir: Path | None = None,
    completion: Any = None,
) -> StageOutcome:
    """Run one stage under its contract; attempts go to record_dir/evidence/attempts.jsonl and a harness .rrd."""
    routes = with_probe_routes(stage_routes(contract.stage, contract.parameters), contract)
    roles = build_roles(agents, completion=completion, routes=routes)
    recorder = AttemptRecorder(record_dir, contract.stage) if record_dir is not None else None
    outcome = run_stage(contract, probe_runner, targets, roles=roles, initial=initial, initial_action=initial_action,
                        recorder=recorder, routes=routes)
    if recorder is not None:
        recorder.close(outcome)
    return outcome


def run_harness(
    stage: StageName | StageContract,
    probe_runner: ProbeRunner,
    targets: TargetBehaviour | None = None,
    **kwargs: Any,
) -> StageOutcome:
    """Convenience: load the stage's contract (or take one) and run the flow with the local Prefect runtime."""
    contract = stage if isinstance(stage, StageContract) else load_contract(stage)
    with cache.local_runtime():
        return harness_stage(contract, probe_runner, targets, **kwargs)
