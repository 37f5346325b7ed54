"""How L0 reads a set of prompts, without building their meshes (the Designer's reading and program only): how many reach a named lexicon entry and which are built by
analogy (and how). Cheap (~0.1 s a prompt): the first look at a new prompt set, before the blind bench.

    python -m benchmarks.reading_coverage PROMPTS.jsonl [...] [--json] [--show analogy|all]
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
from pathlib import Path

from contracts.errors import DeformSmithError
from tasks.geometry import catalogue


def read_all(paths: list[Path]) -> list[dict]:
    """One row per prompt: its text, the concept read, the fallback level and the note."""
    rows = []
    for path in paths:
        for line in path.read_text(encoding="utf-8").splitlines():
            if not line.strip():
                continue
            prompt = json.loads(line)
            try:
                m = catalogue.design_from_text(prompt["text"]).concept
            except (ValueError, DeformSmithError) as exc:  # a refusal (rigid, too big): the user sees it as an error
                rows.append({"id": prompt.get("id"), "text": prompt["text"], "object": prompt.get("object"),
                             "concept": None, "level": "refused", "note": str(exc).splitlines()[0]})
                continue
            assert m is not None
            rows.append({"id": prompt.get("id"), "text": prompt["text"], "object": prompt.get("object"),
                         "concept": m.concept, "level": m.fallback_level, "by_analogy": m.by_analogy,
                         "note": m.fallback_note})
    return rows


def summary(rows: list[dict]) -> dict:
    """Counts by fallback level and the share that reached a named entry."""
    levels = collections.Counter(r["level"] for r in rows)
    named = sum(1 for r in rows if r["level"] != "refused" and not r.get("by_analogy"))
    return {"prompts": len(rows), "named_entry": named, "named_share": round(named / max(len(rows), 1), 3),
            "levels": dict(levels.most_common())}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("prompts", type=Path, nargs="+")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--show", choices=("analogy", "all", "none"), default="analogy")
    args = ap.parse_args(argv)
    rows = read_all(args.prompts)
    result = summary(rows)
    if args.json:
        print(json.dumps({"summary": result, "rows": rows}, indent=1))
        return 0
    for r in rows:
        if args.show == "all" or (args.show == "analogy" and (r.get("by_analogy") or r["level"] == "refused")):
            print(f"{r['level']:9} {r['concept'] or '-':22} {r['text'][:60]:60} | {r['object'] or ''}")
    print(json.dumps(result), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
