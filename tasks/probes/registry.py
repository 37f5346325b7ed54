"""The probe registry: every module of a probe package that defines `PROBE` (a tasks.probes.probe.Probe) is one probe.

Rigid (L1) probes live in tasks/probes/rigid_probes/, deformable (L2) ones in tasks/probes/deformable_probes/; a new
probe is one new module there plus its entry in the stage contract's `parameters.probes` (and its metrics under
`required_observations` / `hard_gates`). The flows make cached tasks of them (flows/probe_tasks.py), the harness
merges their route defaults into the stage's route table.
"""

from __future__ import annotations

import importlib
import pkgutil
from functools import cache

from contracts.errors import ContractError
from contracts.stage import StageContract, StageProbes
from tasks.agents.vocab import StageRoutes
from tasks.probes.probe import Probe

PACKAGES = ("tasks.probes.rigid_probes", "tasks.probes.deformable_probes")


@cache
def registry() -> dict[str, Probe]:
    """Every registered probe by task name ('l1.place', 'l2.compress', ...), discovered once per process."""
    found: dict[str, Probe] = {}
    for package in PACKAGES:
        pkg = importlib.import_module(package)
        for info in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
            if info.name.startswith("_"):
                continue
            module = importlib.import_module(f"{package}.{info.name}")
            probe = getattr(module, "PROBE", None)
            if probe is None:
                continue
            if not isinstance(probe, Probe):
                raise TypeError(f"{module.__name__}.PROBE is not a Probe")
            if probe.task_name in found:
                raise ContractError(f"two probe modules register '{probe.task_name}'")
            found[probe.task_name] = probe
    return found


def reset() -> None:
    """Forget the discovered probes (a test that adds a probe module)."""
    registry.cache_clear()


def probe(stage: str, name: str) -> Probe:
    """The probe `name` of a stage (ContractError naming the known ones)."""
    found = registry().get(f"{stage.lower()}.{name}")
    if found is None:
        known = sorted(p.name for p in registry().values() if p.stage == stage)
        raise ContractError(f"no {stage} probe '{name}' is registered; known: {', '.join(known)}")
    return found


def stage_probes(contract: StageContract, held_out: bool = False) -> list[Probe]:
    """The probes a stage contract runs (its held-out tests when held_out), in the contract's order."""
    return [probe(contract.stage, n) for n in StageProbes.of(contract).names(held_out)]


def by_kind(stage: str, kind: str) -> Probe:
    """The probe of a stage whose results carry this ProbeSpec kind."""
    for p in registry().values():
        if p.stage == stage and p.kind == kind:
            return p
    raise ContractError(f"no {stage} probe reports the kind '{kind}'")


def with_probe_routes(routes: StageRoutes, contract: StageContract) -> StageRoutes:
    """The stage's route table plus the route defaults (gate routes, couplings) of the registered probes its contract
    runs, for the metrics routes.yaml and the contract leave out: a new probe brings its own routes."""
    table = routes.model_dump()
    added = False
    for p in stage_probes(contract):
        own = p.route_table()
        for section in ("gates", "couplings"):
            for metric, route in own[section].items():
                if metric not in table[section]:
                    table[section][metric] = route
                    added = True
    return StageRoutes.model_validate(table) if added else routes


__all__ = ["PACKAGES", "by_kind", "probe", "registry", "reset", "stage_probes", "with_probe_routes"]
