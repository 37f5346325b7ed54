"""Integration: a real Prefect server and two process workers on loopback, a batch through the deployments, one
worker killed (SIGKILL, with its flow-run process) mid-run; every request completes exactly once, cache intact.

Run with `pytest -m slow tests/deployments` (about 5-10 minutes on 2 busy cores).
"""

from __future__ import annotations

import importlib.util
import json
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[2]
SPONGE = "a kitchen sponge 10 x 7 x 3 cm"
REQUESTS = [{"name": f"sponge-{i}", "text": SPONGE, "seed": i, "quality": "draft"} for i in range(4)]


def _load_cluster_module() -> Any:
    spec = importlib.util.spec_from_file_location("local_cluster", REPO / "deployments" / "local_cluster.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _events(cache: Path) -> list[dict[str, Any]]:
    path = cache / "events.jsonl"
    if not path.is_file():
        return []
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]


def _victim(lc: Any, cluster: Any, cache: Path, timeout_s: float) -> str:
    """A generation worker whose flow-run process has already finished some cached work (mid-run)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        pids = {e["pid"] for e in _events(cache) if e["outcome"] == "miss"}
        for name, proc in cluster.workers.items():
            if name.startswith("gen-") and pids & set(lc.descendants(proc.pid)):
                return str(name)
        time.sleep(1.0)
    raise TimeoutError("no worker started cached work in time")


@pytest.mark.slow
@pytest.mark.timeout(1500)
def test_batch_through_deployments_survives_a_killed_worker(tmp_path: Path) -> None:
    """>= 4 requests, 2 workers, one killed mid-run: one Completed run and one asset per request, each key executed
    once, the killed request resumed from the cache, CacheStore.verify() empty."""
    from cache import CacheStore

    lc = _load_cluster_module()
    cache, out = tmp_path / "cache", tmp_path / "out"
    requests = tmp_path / "requests.jsonl"
    requests.write_text("".join(json.dumps(r) + "\n" for r in REQUESTS), encoding="utf-8")
    with lc.LocalCluster(tmp_path / "cluster", cache, workers=2) as cluster:
        batch_id = cluster.run_deployment(lc.NIGHTLY, {
            "requests_jsonl": str(requests), "out_root": str(out), "poll_s": 3.0,
            "heartbeat_timeout_s": 75.0, "pending_timeout_s": 120.0, "timeout_s": 1200.0,
            "job": "flows.batch_job:generate_job_without_l3"})  # the machinery under test, not L3 (minutes/request)
        victim = _victim(lc, cluster, cache, timeout_s=600)
        killed = cluster.kill_worker(victim)
        killed_events = [e for e in _events(cache) if e["pid"] in killed]
        assert len(killed) >= 2, "the killed worker was running a flow run"
        batch = cluster.wait_flow_run(batch_id, timeout_s=1200)
        runs = cluster.flow_runs()

    assert batch["state"] == "COMPLETED", batch
    report = json.loads((out / "batch_report.json").read_text(encoding="utf-8"))
    assert report["requested"] == 4 and report["ok"] == 4 and report["failed"] == 0, report

    # Exactly one Completed generate run per request; the killed one was marked Crashed and submitted again.
    generate = [r for r in runs if r["name"].split("#")[0] in {q["name"] for q in REQUESTS} and "#" in r["name"]]
    completed = Counter(r["name"].split("#")[0] for r in generate if r["state"] == "COMPLETED")
    assert completed == Counter({q["name"]: 1 for q in REQUESTS}), generate
    crashed = [r for r in generate if r["state"] == "CRASHED"]
    assert len(crashed) == 1 and "heartbeat" in (crashed[0]["message"] or ""), generate
    resumed = crashed[0]["name"].split("#")[0]
    assert {r["attempts"] for r in report["results"] if r["name"] == resumed} == {2}

    # One published asset per request, nothing half-written next to them.
    for q in REQUESTS:
        assert (out / q["name"] / "asset.json").is_file()
    assert not [p.name for p in out.iterdir() if ".partial-" in p.name]

    # Each cached task executed once per key; the resubmitted run took the killed run's finished work from the cache.
    events = _events(cache)
    misses = Counter(e["key"] for e in events if e["outcome"] == "miss")
    assert misses and max(misses.values()) == 1, [k for k, n in misses.items() if n > 1]
    finished_before_kill = {e["key"] for e in killed_events if e["outcome"] == "miss"}
    assert finished_before_kill
    later_hits = {e["key"] for e in events if e["outcome"] == "hit" and e["pid"] not in killed}
    assert finished_before_kill <= later_hits
    assert CacheStore(cache).verify() == []
