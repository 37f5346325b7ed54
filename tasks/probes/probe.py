"""One probe shape: the `Probe` protocol, what a stage gives a probe (`ProbeContext`), and `ProbeModule`, the usual way
a probe module declares itself (`PROBE = ProbeModule(...)`, found by tasks/probes/registry.py).

A probe declares
  its inputs   `run`'s signature: the keyword inputs of its cached task, hence its cache key (name, version, inputs);
               `inputs(ctx)` builds them from a stage's context (asset, candidate models, contract, held-out or not)
  its metrics  a `contracts.probes.ProbeMetrics` model: every metric it may report, typed; a result with a metric the
               model does not declare fails at the boundary (`check`)
  its recording  the .rrd `run` writes under the cache (`cache_recording_path`), copied into the asset under
               `recording_name()` for the chosen candidate
  its routes   defaults for the stage's route table (gate metric -> diagnosis and directions, metric -> couplings),
               used where routes.yaml and the contract say nothing about the metric
No Prefect here: flows/probe_tasks.py makes each registered probe a cached task.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

from cache import cache_root
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeMetrics, ProbeResult
from contracts.sim import SimConfig
from contracts.stage import StageContract, StageProbes


@dataclass(frozen=True)
class ProbeContext:
    """What a stage gives its probes to build their inputs from: the L0 asset (or a stand-in with its fields), the
    candidate's physical model and material, the stage contract, the numerics, and whether this is a held-out test."""

    asset: Any
    contract: StageContract
    physical: PhysicalModel
    material: Material | None = None
    sim: SimConfig | None = None
    held_out: bool = False

    def settings(self, name: str) -> dict[str, float]:
        """The probe's own settings from its contract entry."""
        return dict(StageProbes.of(self.contract).entry(name).settings)


@runtime_checkable
class Probe(Protocol):
    """A probe of one stage: a cached unit of work with declared inputs, typed metrics, a recording and routes."""

    stage: str
    name: str
    version: str
    metrics: type[ProbeMetrics]
    batch: Callable[..., list[ProbeResult]] | None  # several candidates at once (a screening), if it can

    @property
    def task_name(self) -> str:
        """The cached task's name, '<stage>.<name>' in lower case (e.g. 'l2.compress'): part of its cache key."""
        ...

    @property
    def kind(self) -> str:
        """The ProbeSpec kind its results carry."""
        ...

    def inputs(self, ctx: ProbeContext) -> dict[str, Any]:
        """Keyword inputs of `run` for a stage's candidate (what its cache key is made of)."""
        ...

    def run(self, *args: Any, **kwargs: Any) -> ProbeResult:
        """Measure and record; one ProbeResult."""
        ...

    def check(self, result: ProbeResult) -> ProbeResult:
        """The result, once its metrics fit `metrics` (a pydantic ValidationError otherwise)."""
        ...

    def recording_name(self, held_out: bool = False) -> str:
        """The file name of its recording inside an asset's recordings/ folder."""
        ...

    def route_table(self) -> dict[str, Any]:
        """Its route defaults: {'gates': {metric: route}, 'couplings': {metric: [coupling]}}."""
        ...


@dataclass(frozen=True)
class ProbeModule:
    """A probe declared by a module: `run` (signature = the task's inputs), `inputs`, `metrics`, its recording name,
    route defaults. kind defaults to name; recording to '<stage>_<kind>.rrd'."""

    stage: str
    name: str
    version: str
    metrics: type[ProbeMetrics]
    run: Callable[..., ProbeResult]
    inputs: Callable[[ProbeContext], dict[str, Any]]
    spec_kind: str | None = None
    recording: str | None = None
    batch: Callable[..., list[ProbeResult]] | None = None  # several candidates at once (a screening), if it can
    gates: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    couplings: Mapping[str, list[Mapping[str, Any]]] = field(default_factory=dict)

    @property
    def task_name(self) -> str:
        """'<stage>.<name>' in lower case."""
        return f"{self.stage.lower()}.{self.name}"

    @property
    def kind(self) -> str:
        """The ProbeSpec kind of its results."""
        return self.spec_kind or self.name

    def check(self, result: ProbeResult) -> ProbeResult:
        """The result once its metrics fit the declared model (pydantic raises on an undeclared or non-float one)."""
        self.metrics.model_validate(result.metrics)
        return result

    def recording_name(self, held_out: bool = False) -> str:
        """'<stage>_<kind>.rrd' (or the declared name); a held-out test's gets '_held_out' before the suffix."""
        name = self.recording or f"{self.stage}_{self.kind}.rrd"
        return name.replace(".rrd", "_held_out.rrd") if held_out else name

    def route_table(self) -> dict[str, Any]:
        """{'gates': ..., 'couplings': ...} as declared."""
        return {"gates": {k: dict(v) for k, v in self.gates.items()},
                "couplings": {k: [dict(c) for c in v] for k, v in self.couplings.items()}}


def cache_recording_path(stage: str, kind: str, key: str) -> Path:
    """Where a probe's recording lives in the cache: recordings/<stage>_<kind>-<key[:16]>.rrd (copied into the asset
    for the chosen candidate)."""
    return cache_root() / "recordings" / f"{stage}_{kind}-{key[:16]}.rrd"


__all__ = ["Probe", "ProbeContext", "ProbeModule", "cache_recording_path"]
