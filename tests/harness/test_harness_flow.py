"""The harness as a Prefect flow: probes run as cached tasks; a rerun executes nothing and records the same attempts."""

from __future__ import annotations

import math
from pathlib import Path

from harness_fakes import HEALTHY, fake_modulus_pa, fake_rebound, l2_targets

from cache import CacheStore, cache_root, cached_task
from contracts import Material, ProbeResult, ProbeSpec
from flows.harness import ProbeCall, run_harness, task_probe_runner
from tasks.agents.records import read_attempts


@cached_task(version="1", name="tests.harness.fake_compress")
def fake_compress(material: Material, strain: float) -> ProbeResult:
    """Fake compression probe on a Material."""
    m = {**HEALTHY, "effective_modulus_pa": fake_modulus_pa(material.youngs_modulus_pa), "recovery_ratio": 0.97}
    return ProbeResult(spec=ProbeSpec(kind="compress", params={"strain": strain}), metrics=m)


@cached_task(version="1", name="tests.harness.fake_drop")
def fake_drop(material: Material, height_m: float) -> ProbeResult:
    """Fake drop probe on a Material."""
    m = {**HEALTHY, "rebound_ratio": fake_rebound(material.damping_rate_per_s), "max_impact_strain": 0.1}
    return ProbeResult(spec=ProbeSpec(kind="drop", params={"height_m": height_m}), metrics=m)


def _material(values: dict[str, float], action: str) -> dict[str, Material]:
    return {"material": Material(**values)}


def test_flow_runs_probes_as_cached_tasks_and_reruns_nothing(prefect_api: str, tmp_path: Path) -> None:
    runner = task_probe_runner([ProbeCall(fake_compress, {"strain": 0.1}, _material),
                                ProbeCall(fake_drop, {"height_m": 0.05}, _material)])
    out = run_harness("L2", runner, l2_targets(2e5), record_dir=tmp_path)
    assert out.status == "accepted"
    events = CacheStore(cache_root()).events()
    assert [e["outcome"] for e in events] == ["miss"] * (2 * out.attempts_used)
    keys = [k for a in out.attempts for k in a.evidence.probe_keys]
    assert keys == [e["key"] for e in events]  # the evidence names the probes' cache keys
    again = run_harness("L2", runner, l2_targets(2e5), record_dir=tmp_path)
    new = CacheStore(cache_root()).events()[len(events):]
    assert [e["outcome"] for e in new] == ["hit"] * len(new)  # nothing executed
    assert again.attempts == out.attempts == read_attempts(tmp_path / "evidence" / "attempts.jsonl")
    assert math.isclose(fake_modulus_pa(out.values["youngs_modulus_pa"]), 2e5, rel_tol=0.1)
