"""Load: a Prefect server on PostgreSQL (Debian's package), two process workers, 30 requests through the nightly
deployment, one worker SIGKILLed mid-run. Every request ends exactly once (one Completed generate run, one asset), and
each asset is the same (content fingerprint) as a clean run of its request outside the cluster.

Run with `pytest -m slow tests/deployments/test_postgres_load.py -s` (about 15-25 minutes on 2 cores); it prints the
figures (requests, minutes, requests per minute, duplicates, lost) and writes them to $DEFORMSMITH_LOAD_JSON if set.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "deployments"))

JOB = "flows.batch_job:generate_job_without_l3"  # the orchestration under load, not L3 (minutes per request)
DISTINCT = [{"text": text, "seed": seed, "quality": "draft"}
            for text in ("a kitchen sponge 10 x 7 x 3 cm", "a soft foam cube, 6 cm") for seed in range(3)]
COPIES = 5  # 6 distinct requests x 5 names = 30 requests: distinct work side by side with shared cache entries
REQUESTS = [{"name": f"r{i:02d}", **DISTINCT[i % len(DISTINCT)]} for i in range(len(DISTINCT) * COPIES)]


def _needs_postgres() -> None:
    try:
        from local_postgres import _pg_bin

        _pg_bin("initdb")
    except FileNotFoundError as exc:
        pytest.skip(str(exc))


def _clean_run(req: dict[str, Any], cache: Path, out: Path) -> Path:
    """The request through the same job in a fresh process and a cache of its own (no cluster)."""
    from contracts.request import AssetRequest

    request = AssetRequest.model_validate({k: v for k, v in req.items() if k != "name"})
    work = out.parent / f"{out.name}.job"
    work.mkdir(parents=True)
    (work / "request.json").write_text(request.model_dump_json(), encoding="utf-8")
    env = {**os.environ, "DEFORMSMITH_CACHE": str(cache), "PREFECT_HOME": str(work / "prefect")}
    subprocess.run([sys.executable, "-m", "flows.batch_job", "--request", str(work / "request.json"), "--out",
                    str(out), "--result", str(work / "result.json"), "--job", JOB], cwd=REPO, env=env, check=True,
                   timeout=1800)
    return out


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_thirty_requests_on_postgres_survive_a_killed_worker(tmp_path: Path) -> None:
    _needs_postgres()
    import local_cluster as lc
    from local_postgres import LocalPostgres

    from tasks.record.fingerprint import content_fingerprint
    from test_cluster_integration import _victim  # type: ignore[import-not-found]

    cache, out = tmp_path / "cache", tmp_path / "out"
    requests = tmp_path / "requests.jsonl"
    requests.write_text("".join(json.dumps(r) + "\n" for r in REQUESTS), encoding="utf-8")
    with LocalPostgres(tmp_path / "pg") as pg:
        env = {"PREFECT_API_DATABASE_CONNECTION_URL": pg.url, "PREFECT_API_DATABASE_TIMEOUT": "60"}
        with lc.LocalCluster(tmp_path / "cluster", cache, workers=2, extra_env=env) as cluster:
            t0 = time.monotonic()
            batch_id = cluster.run_deployment(lc.NIGHTLY, {
                "requests_jsonl": str(requests), "out_root": str(out), "poll_s": 3.0, "heartbeat_timeout_s": 75.0,
                "pending_timeout_s": 300.0, "timeout_s": 3000.0, "job": JOB})
            victim = _victim(lc, cluster, cache, timeout_s=900)
            killed = cluster.kill_worker(victim)
            batch = cluster.wait_flow_run(batch_id, timeout_s=3000)
            minutes = (time.monotonic() - t0) / 60
            runs = cluster.flow_runs()

    assert batch["state"] == "COMPLETED", batch
    assert len(killed) >= 2, "the killed worker was running a flow run"
    report = json.loads((out / "batch_report.json").read_text(encoding="utf-8"))
    names = {q["name"] for q in REQUESTS}
    generate = [r for r in runs if r["name"].split("#")[0] in names and "#" in r["name"]]
    completed = Counter(r["name"].split("#")[0] for r in generate if r["state"] == "COMPLETED")
    duplicates = sum(n - 1 for n in completed.values() if n > 1)
    lost = len(names - set(completed))
    figures = {"requests": len(REQUESTS), "minutes": round(minutes, 2),
               "requests_per_minute": round(len(REQUESTS) / minutes, 2), "duplicates": duplicates, "lost": lost,
               "crashed_runs": sum(r["state"] == "CRASHED" for r in generate), "ok": report["ok"],
               "database": "postgresql"}
    print(json.dumps(figures))
    if os.environ.get("DEFORMSMITH_LOAD_JSON"):
        Path(os.environ["DEFORMSMITH_LOAD_JSON"]).write_text(json.dumps(figures, indent=1), encoding="utf-8")
    assert report["requested"] == len(REQUESTS) and report["ok"] == len(REQUESTS) and report["failed"] == 0, report
    assert duplicates == 0 and lost == 0, completed
    assert not [p.name for p in out.iterdir() if ".partial-" in p.name]

    # Same asset as a clean run: each distinct request once, in its own cache, outside the cluster.
    clean: dict[int, dict[str, str]] = {}
    for i, req in enumerate(DISTINCT):
        clean[i] = content_fingerprint(_clean_run(req, tmp_path / "clean-cache", tmp_path / "clean" / f"d{i}"))
        shutil.rmtree(tmp_path / "clean" / f"d{i}.job", ignore_errors=True)
    for i, q in enumerate(REQUESTS):
        got = content_fingerprint(out / q["name"])
        want = clean[i % len(DISTINCT)]
        assert got == want, (q["name"], sorted(k for k in set(got) | set(want) if got.get(k) != want.get(k))[:10])
