"""How two asset directories of the same request differ: files equal by content fingerprint, and for JSON files that
differ, the largest relative difference of their numbers and the non-numeric values that differ (a GPU's float
atomics make two runs differ in the last digits; a decision that differs is another asset).

    python -m benchmarks.asset_diff RUN_A RUN_B [--json] [--equivalent [--rtol 0.05] [--atol 0.001]]

`--equivalent` decides whether two GPU runs of one request made the same asset, as far as a GPU's float atomics allow
(exit 1 if not): the same files; in every JSON document the same decisions (every value that is not a number, with
content keys and the recording names made from them, hexadecimal runs of 10 or more characters, set aside) and every
number within `atol + rtol * max(|a|, |b|)` (SI units, so the 1e-3 floor is a millimetre, a millisecond, a thousandth
of a ratio); recordings, renders and array chunks, which differ by bytes when their numbers do, are listed unchecked.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

from tasks.record.fingerprint import content_fingerprint

TINY = 1e-12  # numbers both within this of zero count as equal
CONTENT_ID = re.compile(r"[0-9a-f]{10,}")  # a content key or a hash, whole or cut, as it appears in values


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
        if a == b:
            return
        rel = abs(a - b) / max(abs(a), abs(b))
        out["numbers"].append((path, a, b))
        if math.isfinite(rel) and rel > out["max_rel"]:
            out["max_rel"], out["max_at"] = rel, path
    elif a != b:
        key_only = isinstance(a, str) and isinstance(b, str) and CONTENT_ID.sub("#", a) == CONTENT_ID.sub("#", b)
        out["keys" if key_only else "values"].append({"at": path, "a": str(a)[:80], "b": str(b)[:80]})


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
            entry: dict = {"max_rel": 0.0, "max_at": None, "values": [], "keys": [], "numbers": [],
                           "compared": rel.endswith((".json", ".jsonl"))}
            if entry["compared"]:
                _walk(_load(run_a / rel), _load(run_b / rel), "", entry)
            report["differ"][rel] = entry
    return report


def _load(path: Path) -> object:
    """A JSON document, or a JSONL file as the list of its lines' documents."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".jsonl":
        return [json.loads(line) for line in text.splitlines() if line.strip()]
    return json.loads(text)


def equivalence(report: dict, rtol: float = 0.05, atol: float = 1e-3) -> dict:
    """Whether the two runs of `report` made the same asset: the same files, the same decisions, numbers in tolerance."""
    broken: list[dict] = []
    unchecked: list[str] = []
    for rel in report["only_in_a"] + report["only_in_b"]:
        broken.append({"file": rel, "why": "in one run only"})
    for rel, e in report["differ"].items():
        if not e["compared"]:
            unchecked.append(rel)
            continue
        broken += [{"file": rel, "why": "decision differs", **v} for v in e["values"]]
        broken += [{"file": rel, "why": "number out of tolerance", "at": at, "a": a, "b": b}
                   for at, a, b in e["numbers"] if not abs(a - b) <= atol + rtol * max(abs(a), abs(b))]
    return {"equivalent": not broken, "rtol": rtol, "atol": atol, "broken": broken[:50],
            "broken_count": len(broken), "unchecked_by_bytes": unchecked}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_a", type=Path)
    ap.add_argument("run_b", type=Path)
    ap.add_argument("--json", action="store_true", help="print the whole report as JSON")
    ap.add_argument("--equivalent", action="store_true",
                    help="decide whether the runs made the same asset within tolerance (exit 1 if not)")
    ap.add_argument("--rtol", type=float, default=0.05, help="relative tolerance of numbers with --equivalent")
    ap.add_argument("--atol", type=float, default=1e-3, help="absolute tolerance of numbers (SI) with --equivalent")
    args = ap.parse_args(argv)
    for d in (args.run_a, args.run_b):
        if not d.is_dir():
            print(f"error: {d} is not a directory", file=sys.stderr)
            return 2
    report = diff(args.run_a, args.run_b)
    verdict = equivalence(report, args.rtol, args.atol) if args.equivalent else None
    if args.json:
        shown = {**report, "differ": {rel: {k: (v[:20] if isinstance(v, list) else v) for k, v in e.items()}
                                      for rel, e in report["differ"].items()}}
        print(json.dumps({**shown, "equivalence": verdict} if verdict else shown, indent=1, default=str))
    else:
        print(f"{report['equal']} of {report['files']} files equal; differ: {len(report['differ'])}")
        for rel, e in report["differ"].items():
            print(f"  {rel}: max relative {e['max_rel']:.3g} at {e['max_at']}; {len(e['values'])} other values "
                  f"differ; {len(e['keys'])} content keys differ")
        if verdict:
            print(f"equivalent: {verdict['equivalent']} (rtol {args.rtol}, atol {args.atol}); "
                  f"{verdict['broken_count']} differences beyond that; "
                  f"{len(verdict['unchecked_by_bytes'])} files differ by bytes only, unchecked")
            for b in verdict["broken"][:10]:
                print(f"  {b['file']} {b.get('at', '')}: {b['why']} ({b.get('a', '')} / {b.get('b', '')})")
    return 1 if verdict and not verdict["equivalent"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
