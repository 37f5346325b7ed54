"""One cached task per registered probe (tasks/probes/registry.py), and the Prober that runs a stage's probes.

A probe's task is `cached_task(version=probe.version, name=probe.task_name)` over its `run`: the key is the task name,
the version and `run`'s inputs by content, so a probe keeps the keys it had as a hand-written task. Its metrics are
checked against the probe's typed model before the result is stored.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

from cache import cached_task
from contracts.probes import ProbeResult
from flows.harness import call_tasks, probe_cache_key
from tasks.probes.probe import Probe, ProbeContext
from tasks.probes.registry import probe as find_probe


_TASKS: dict[tuple[str, str, int], Any] = {}


def _task_of(probe: Probe) -> Any:
    """`cached_task` over the probe's `run` (its signature: the task's inputs), the metrics checked on the way out."""
    run = probe.run

    @functools.wraps(run)
    def checked(*args: Any, **kwargs: Any) -> ProbeResult:
        return probe.check(run(*args, **kwargs))

    return cached_task(version=probe.version, name=probe.task_name)(checked)


def probe_task(probe: Probe | tuple[str, str]) -> Any:
    """The cached task of a probe (or of (stage, name)); made once per process and probe."""
    p = find_probe(*probe) if isinstance(probe, tuple) else probe
    key = (p.task_name, p.version, id(p))
    if key not in _TASKS:
        _TASKS[key] = _task_of(p)
    return _TASKS[key]


def probe_calls(probes: Sequence[Probe], ctx: ProbeContext) -> list[tuple[Any, dict[str, Any]]]:
    """(cached task, inputs) of each probe for one context."""
    return [(probe_task(p), p.inputs(ctx)) for p in probes]


def run_probes(probes: Sequence[Probe], ctx: ProbeContext, workers: int = 1, device: str | None = "cpu",
               keys: bool = True) -> list[ProbeResult]:
    """Run the probes (cached; up to `workers` side by side, flows.harness.call_tasks) for one context; keys: every
    result carries its cache key."""
    calls = probe_calls(probes, ctx)
    results: list[ProbeResult] = call_tasks(calls, workers, device)
    if not keys:
        return results
    return [r if r.cache_key else r.model_copy(update={"cache_key": probe_cache_key(t, kw)})
            for r, (t, kw) in zip(results, calls)]


__all__ = ["probe_calls", "probe_task", "run_probes"]
