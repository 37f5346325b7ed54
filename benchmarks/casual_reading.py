"""How often a lexicon noun wrapped in the words a person types around it still reads as the noun's own entry.

Each of N lexicon nouns (one or two words, drawn with a seed) is put into every template of a family (commands,
places, counts, labels, states, several objects ...); a wording counts as read when `design_from_text` gives the
same entry as the bare noun. Prints a table, or `--json` the per-family and overall fractions with the misses.

    python -m benchmarks.casual_reading --nouns 60 --seed 1 --json
"""

from __future__ import annotations

import argparse
import json
import random
import time

from contracts.errors import InputError
from tasks.geometry import catalogue, concepts

FAMILIES: dict[str, list[str]] = {
    "commands": ["grab that {} off the table", "pls pick up {}", "hand me that {} real quick",
                 "lift the {} into the tray", "move the {} to the bin", "can you grab the {} pls",
                 "toss the {} in the basket", "ok robot, grab the {}", "put that {} back", "get me the {} from the counter"],
    "after_the_object": ["{} - bin it", "{}, put it in the crate", "{} thx", "{} left on the bench", "{}???",
                         "{} that came back", "{} on the shelf, put it in the crate", "{}, needs washing",
                         "{} with a hole in it", "{} missing a button"],
    "counts": ["a couple of {}", "{} x2", "{} (x2)", "2x {}", "{} ×2", "the other {}", "another {}", "{} #2"],
    "unsure": ["the {} thing", "some sort of {}", "that {} thingy", "a {} i think", "{} or whatever its called"],
    "labels_and_searches": ["item: {}", "order 42: {}", "looking for the {}", "someone left a {} here",
                            "is there a {}?", "wheres the {}", "next up: {}", "the customer wants the {}"],
    "several_objects": ["{} then the towel", "{} or the sponge", "{} plus the bag it came in", "{} and the box",
                        "{}, also the mat"],
    "places": ["{} on a hanger", "{} draped over the chair", "{} in the sink", "{} under the bench",
               "{} from the dryer", "{} at station 3", "{} on the trolley", "{} by the till"],
    "sizes_and_masses": ["{} about the size of a football", "fist sized {}", "a tiny {}", "{} 2ft", "{} 15cm",
                         "{}, roughly 1 kg", "{} (approx 40cm)", "mini {}"],
}


def _nouns(n: int, seed: int) -> list[str]:
    pool = sorted(k for k in concepts.noun_index() if 1 <= len(k.split()) <= 2 and k.isascii() and " of " not in k)
    return random.Random(seed).sample(pool, n)


def run(n_nouns: int, seed: int, nouns: list[str] | None = None) -> dict:
    """Read every wording; the fraction read as the bare noun per family and overall, with the misses (`nouns`: a
    fixed list, to compare two versions of the lexicon on the same nouns)."""
    def entry(text: str) -> str:
        try:
            return catalogue.design_from_text(text).entry
        except InputError as exc:
            return f"refused: {str(exc)[:60]}"
        except Exception as exc:  # noqa: BLE001 - a crash on a wording is a miss the table must show, not the end
            return f"crashed: {type(exc).__name__}: {str(exc)[:80]}"

    t0 = time.perf_counter()
    nouns = nouns or _nouns(n_nouns, seed)
    bare = {n: entry(n) for n in nouns}
    families: dict[str, dict] = {}
    total = read = 0
    for family, templates in FAMILIES.items():
        misses = []
        for noun in nouns:
            for template in templates:
                text = template.format(noun)
                got = entry(text)
                if got != bare[noun]:
                    misses.append({"text": text, "expected": bare[noun], "got": got})
        n = len(nouns) * len(templates)
        families[family] = {"wordings": n, "read": n - len(misses), "fraction": round(1 - len(misses) / n, 4),
                            "misses": misses[:20]}
        total, read = total + n, read + n - len(misses)
    return {"nouns": len(nouns), "seed": seed, "wordings": total, "read": read, "fraction": round(read / total, 4),
            "seconds": round(time.perf_counter() - t0, 1), "families": families}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nouns", type=int, default=60)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--nouns-from", help="a file of nouns, one per line (else --nouns drawn with --seed)")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    fixed = None
    if args.nouns_from:
        with open(args.nouns_from, encoding="utf-8") as fh:
            fixed = [line.strip() for line in fh if line.strip()]
    out = run(args.nouns, args.seed, fixed)
    if args.json:
        print(json.dumps(out))
        return
    for family, f in out["families"].items():
        print(f"{family:22s} {f['read']:5d} / {f['wordings']:5d}  {100 * f['fraction']:5.1f} %")
    print(f"{'all':22s} {out['read']:5d} / {out['wordings']:5d}  {100 * out['fraction']:5.1f} %  ({out['seconds']} s)")


if __name__ == "__main__":
    main()
