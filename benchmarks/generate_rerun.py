"""The main job's rerun: time a fully cached `deformsmith generate` (and its first progress line) and weigh the
asset it publishes, per top-level folder.

    python -m benchmarks.generate_rerun [TEXT] --cache DIR --out DIR [--runs 3] [--json]

A run that finds the cache empty first fills it with one cold run (timed and reported apart). Each timed run is a
fresh process, as a user's rerun is.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

DEFAULT_TEXT = "a soft plush turtle toy, about 25 cm long"


def timed_generate(text: str, out: Path, cache: Path, extra: list[str]) -> dict[str, Any]:
    """One `deformsmith generate` in its own process: wall seconds, seconds to the first stderr line, and the CPU
    seconds it and its Prefect server used (steadier than the wall time on a shared machine)."""
    import resource

    cmd = [sys.executable, "-m", "flows.cli.main", "generate", text, "--out", str(out), "--cache", str(cache), *extra]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "COLUMNS": "100"})
    assert proc.stderr is not None
    first_line_s: float | None = None
    tail: list[str] = []
    for line in proc.stderr:
        if first_line_s is None and line.strip():
            first_line_s = time.perf_counter() - t0
        tail = (tail + [line])[-20:]
    rc = proc.wait()
    wall_s = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if rc != 0:
        raise RuntimeError(f"generate exited {rc}:\n{''.join(tail)}")
    cpu_s = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return {"wall_s": round(wall_s, 2), "first_line_s": round(first_line_s or wall_s, 2), "cpu_s": round(cpu_s, 2),
            "load_average_1min": round(os.getloadavg()[0], 2)}


def asset_size(asset: Path) -> dict[str, Any]:
    """Bytes of the asset directory: total and per top-level entry (files' sizes, not disk blocks)."""
    per: dict[str, int] = {}
    for path in asset.rglob("*"):
        if path.is_file():
            top = path.relative_to(asset).parts[0]
            per[top] = per.get(top, 0) + path.stat().st_size
    return {"total_mb": round(sum(per.values()) / 1e6, 2),
            "per_entry_mb": {k: round(v / 1e6, 2) for k, v in sorted(per.items(), key=lambda kv: -kv[1])}}


def run(text: str, out: Path, cache: Path, runs: int, extra: list[str]) -> dict[str, Any]:
    """Fill the cache if needed, then `runs` fully cached reruns; their figures and the asset's size."""
    result: dict[str, Any] = {"text": text, "extra_args": extra, "cpu_count": os.cpu_count(),
                              "load_average_before": [round(x, 2) for x in os.getloadavg()]}
    entries = cache / "entries"
    if not entries.is_dir() or not any(entries.iterdir()):
        result["cold"] = timed_generate(text, out, cache, extra)
    warm = [timed_generate(text, out, cache, extra) for _ in range(runs)]
    result["warm_runs"] = warm
    result["warm_wall_s_median"] = statistics.median(w["wall_s"] for w in warm)
    result["first_line_s_median"] = statistics.median(w["first_line_s"] for w in warm)
    result["cpu_s_median"] = statistics.median(w["cpu_s"] for w in warm)
    result["asset"] = asset_size(out)
    result["load_average_after"] = [round(x, 2) for x in os.getloadavg()]
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.generate_rerun", description=__doc__.splitlines()[0])
    ap.add_argument("text", nargs="?", default=DEFAULT_TEXT)
    ap.add_argument("--cache", type=Path, required=True, help="cache root (filled by a cold run when empty)")
    ap.add_argument("--out", type=Path, required=True, help="asset directory")
    ap.add_argument("--runs", type=int, default=3, help="fully cached reruns to time")
    ap.add_argument("--no-l3", action="store_true", help="pass --no-l3 to generate")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.runs < 1:
        print("error: --runs must be at least 1", file=sys.stderr)
        return 2
    result = run(args.text, args.out, args.cache, args.runs, ["--no-l3"] if args.no_l3 else [])
    print(json.dumps(result, indent=1) if args.json else
          f"warm rerun {result['warm_wall_s_median']} s (first line {result['first_line_s_median']} s); "
          f"asset {result['asset']['total_mb']} MB {result['asset']['per_entry_mb']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
