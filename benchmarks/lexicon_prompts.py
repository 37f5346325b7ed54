"""Prompts that name every lexicon entry by its first noun, for a recognisability audit of the lexicon's own objects:
run them through the blind bench and have a judge who has not seen the lexicon name each object from its renders.

    python -m benchmarks.lexicon_prompts --out audit.jsonl [--shards 16]   # writes audit.jsonl or audit_00.jsonl ..

Each line is a blind-bench prompt (id = entry key, text = 'a <first noun>', object, mass_kg and its source)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from contracts.lexicon import load_lexicon


def lexicon_prompts() -> list[dict]:
    """One prompt per named entry (the generic_* concepts, which no noun names, are left out), in key order."""
    rows = []
    for key, entry in sorted(load_lexicon().entries.items()):
        noun = entry.nouns[0]
        if noun == "(generic)":
            continue
        article = "an" if noun[0] in "aeiou" else "a"
        rows.append({"id": key, "text": f"{article} {noun}", "object": noun, "mass_kg": entry.mass_kg,
                     "mass_source": entry.mass_source})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--shards", type=int, default=1)
    args = ap.parse_args(argv)
    rows = lexicon_prompts()
    shards = max(1, args.shards)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    for i in range(shards):
        path = args.out if shards == 1 else args.out.with_name(f"{args.out.stem}_{i:02d}{args.out.suffix}")
        path.write_text("".join(json.dumps(r) + "\n" for r in rows[i::shards]), encoding="utf-8")
    print(f"{len(rows)} prompts in {shards} file(s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
