"""L2's results as it records them: the object's compression and drop metrics in their object view (the target
bands are the specimen's), one metrics dict per candidate (each gate metric at its worst), and material.json's
record of a run (no wall time in it: a rerun writes the same file)."""

from __future__ import annotations

from typing import Any

from contracts.agents import StageOutcome, TargetBehaviour
from contracts.asset_dir import HeldOutSummary, KeepTrials, MaterialRecord, SelectionSummary
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, not_measured_reason
from contracts.stage import StageContract
from tasks.agents import merge_metrics

OBJECT_VIEW_KINDS = ("compress", "drop")  # object probes whose non-gate metrics are reported as object_<name>


def object_view(results: list[ProbeResult], contract: StageContract) -> list[ProbeResult]:
    """The object's compression / drop metrics renamed object_<name> except the hard-gate ones: the band metrics come
    from the specimen (the object's effective modulus is its structure's, e.g. 0.024 x E for a dog on four legs).
    Idempotent: a result already in this view is returned as it is."""
    gates = {g.metric for g in contract.hard_gates}
    out = []
    for r in results:
        if r.spec.kind in OBJECT_VIEW_KINDS:
            r = r.model_copy(update={"metrics": {(k if k in gates or k.startswith("object_") else f"object_{k}"): v
                                                 for k, v in r.metrics.items()}})
        out.append(r)
    return out


def l2_metrics(results: list[ProbeResult], contract: StageContract) -> dict[str, float]:
    """One metrics dict of L2 probes (object view + specimen), each gate metric at its worst (merge_metrics)."""
    return merge_metrics(object_view(results, contract), contract)


def material_record(outcome: StageOutcome, targets: TargetBehaviour, material: Material | None,
                    physical: PhysicalModel, contract: StageContract, screening: dict[str, Any],
                    held: list[ProbeResult], recordings: dict[str, str | None], cached: dict[str, str],
                    keep: KeepTrials, inflation: dict[str, float | str] | None = None) -> MaterialRecord:
    """material.json of an L2 run: the harness's outcome and ranking, the screening, the chosen material's held-out
    tests (`held`: none when no material passed) and its recordings (kind -> path in the asset; under keep 'adopted'
    those left in the cache are named in `cached`); `inflation`: a pressurised shell's (tasks.realworld.inflation),
    recorded with the rubber's E and the wall's."""
    held_metrics = l2_metrics(held, contract) if held else {}
    held_targets = targets.model_copy(update={"bands": [b for b in targets.bands if b.metric in held_metrics]})
    sim_calls = outcome.sim_calls + int(screening["sim_calls"]) + sum(r.sim_calls for r in held)
    return MaterialRecord(
        passed=outcome.passed, status=outcome.status, message=outcome.message, intent=targets.intent, targets=targets,
        material=material, physical_model=physical, metrics=outcome.metrics,
        not_measured={m: not_measured_reason(m, outcome.metrics) for m in targets.not_measured(outcome.metrics)},
        held_out=HeldOutSummary(metrics=held_metrics, targets_met=held_targets.met(held_metrics) if held else None,
                                score=held_targets.score(held_metrics) if held else None,
                                bands=[b.metric for b in held_targets.bands],
                                probes=[r.model_dump(mode="json", exclude={"wall_time_s"}) for r in held]),
        selection=SelectionSummary(
            status=outcome.status, score=outcome.score, targets_met=targets.met(outcome.metrics),
            best_iteration=outcome.best_iteration, attempts=outcome.attempts_used, sim_calls=outcome.sim_calls,
            screening=screening,
            ranking=sorted(({"iteration": a.iteration, "values": a.proposal, "score": a.score, "verdict": a.verdict}
                            for a in outcome.attempts if a.score is not None), key=lambda d: -d["score"])),
        sim_calls=sim_calls, recordings={k: v for k, v in recordings.items() if v is not None or keep == "all"},
        **({"cached_recordings": cached} if cached else {}),
        **({"inflation": {**inflation, **({"rubber_youngs_modulus_pa": material.youngs_modulus_pa,
                                           "wall_modulus_pa": material.wall_modulus_pa} if material else {})}}
           if inflation else {}))
