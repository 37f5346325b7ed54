"""A new process for each request against worker processes that serve many, side by side in one run, each cold.

    python -m benchmarks.served_workers [REQUESTS.jsonl] --limit 4 [--concurrency 1] [--no-l3] [--device cpu] --json

Runs the same first N requests of the throughput set twice through `flows.throughput.run_throughput`, each run with
its own output root and cache (cold): `--requests-per-worker 1` (a process per request, as before session 57), then
`--requests-per-worker 20` (a worker per slot serving them). Prints, per run, assets per hour, the mean seconds per
asset outside generate's stages ('other': process start, imports, Warp's kernels, the Prefect client), the mean wall
per asset, and the ratio of the two rates; and whether each asset of the served run is equal, file by file
(tasks.record.fingerprint), to the same request's asset from its own process.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

from cache import use_cache_root
from flows.throughput import run_throughput
from tasks.record.fingerprint import content_fingerprint

REPO = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.served_workers")
    ap.add_argument("requests", nargs="?", type=Path, default=REPO / "benchmarks" / "throughput_requests.jsonl")
    ap.add_argument("--limit", type=int, default=4)
    ap.add_argument("--concurrency", type=int, default=1)
    ap.add_argument("--l3", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--out", type=Path, default=None, help="where the two runs go (default: a new temporary folder)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)

    root = args.out or Path(tempfile.mkdtemp(prefix="served_workers_"))
    runs: dict[str, dict] = {}
    reports = {}
    for mode, per_worker in (("process_per_request", 1), ("served", 20)):
        out = root / mode
        use_cache_root(out / "_cache")
        report = run_throughput(args.requests, out, concurrency=args.concurrency, l3=args.l3, limit=args.limit,
                                requests_per_worker=per_worker)
        reports[mode] = report
        runs[mode] = {"requests_per_worker": per_worker, "ok": report.ok, "failed": report.failed,
                      "wall_s": round(report.wall_s, 1), "assets_per_hour": round(report.assets_per_hour, 2),
                      "request_wall_s_mean": report.request_wall_s.get("mean"),
                      "other_s_per_asset": report.stage_s_per_asset.get("other"),
                      "stage_s_per_asset": report.stage_s_per_asset}
    same: list[str] = []
    differ: list[str] = []
    for rec in reports["served"].records:
        a, b = root / "process_per_request" / rec.name, root / "served" / rec.name
        if rec.status == "ok" and a.is_dir() and b.is_dir():
            (same if content_fingerprint(a) == content_fingerprint(b) else differ).append(rec.name)
    base = runs["process_per_request"]["assets_per_hour"]
    given = args.requests.resolve()
    result = {"requests": str(given.relative_to(REPO)) if given.is_relative_to(REPO) else str(args.requests), "limit": args.limit, "concurrency": args.concurrency, "l3": args.l3,
              "cpu_count": os.cpu_count(), "runs": runs,
              "served_over_process_rate": round(runs["served"]["assets_per_hour"] / base, 3) if base else None,
              "assets_equal_by_fingerprint": len(same), "assets_differing": differ, "out": str(root)}
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        for mode, r in runs.items():
            print(f"{mode}: {r['assets_per_hour']} assets/h, other {r['other_s_per_asset']} s/asset, "
                  f"{r['ok']} ok, {r['failed']} failed")
        print(f"served / process: {result['served_over_process_rate']}x; equal assets {len(same)}, differ {differ}")
    return 0 if not differ else 1


if __name__ == "__main__":
    raise SystemExit(main())
