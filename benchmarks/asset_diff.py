"""How two asset directories of the same request differ: files equal by content fingerprint, and for JSON files that
differ, the largest relative difference of their numbers and the non-numeric values that differ (a GPU's float
atomics make two runs differ in the last digits; a decision that differs is another asset).

    python -m benchmarks.asset_diff RUN_A RUN_B [--json]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from tasks.record.fingerprint import content_fingerprint

TINY = 1e-12  # numbers both within this of zero count as equal


def _walk(a: object, b: object, path: str, out: dict) -> None:
    """Record numeric relative differences and other differing values of two JSON documents."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out["values"].append({"at": f"{path}/{k}", "a": a.get(k, "<absent>"), "b": b.get(k, "<absent>")})
            else:
                _walk(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _walk(x, y, f"{path}/{i}", out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool) \
            and not isinstance(b, bool):
        if abs(a) < TINY and abs(b) < TINY:
            return
        rel = abs(a - b) / max(abs(a), abs(b))
        if math.isfinite(rel) and rel > out["max_rel"]:
            out["max_rel"], out["max_at"] = rel, path
    elif a != b:
        out["values"].append({"at": path, "a": str(a)[:80], "b": str(b)[:80]})


def diff(run_a: Path, run_b: Path) -> dict:
    """The per-file comparison of two asset directories."""
    fa, fb = content_fingerprint(run_a), content_fingerprint(run_b)
    files = sorted(set(fa) | set(fb))
    report: dict = {"files": len(files), "equal": 0, "only_in_a": [], "only_in_b": [], "differ": {}}
    for rel in files:
        if rel not in fb:
            report["only_in_a"].append(rel)
        elif rel not in fa:
            report["only_in_b"].append(rel)
        elif fa[rel] == fb[rel]:
            report["equal"] += 1
        else:
            entry: dict = {"max_rel": 0.0, "max_at": None, "values": []}
            if rel.endswith(".json"):
                _walk(json.loads((run_a / rel).read_text()), json.loads((run_b / rel).read_text()), "", entry)
                entry["values"] = entry["values"][:20]
            report["differ"][rel] = entry
    return report


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_a", type=Path)
    ap.add_argument("run_b", type=Path)
    ap.add_argument("--json", action="store_true", help="print the whole report as JSON")
    args = ap.parse_args(argv)
    for d in (args.run_a, args.run_b):
        if not d.is_dir():
            print(f"error: {d} is not a directory", file=sys.stderr)
            return 2
    report = diff(args.run_a, args.run_b)
    if args.json:
        print(json.dumps(report, indent=1, default=str))
    else:
        print(f"{report['equal']} of {report['files']} files equal; differ: {len(report['differ'])}")
        for rel, e in report["differ"].items():
            print(f"  {rel}: max relative {e['max_rel']:.3g} at {e['max_at']}; {len(e['values'])} other values differ")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
