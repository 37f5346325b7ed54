"""The default request set of `deformsmith bench throughput`: distinct draft requests spread over the lexicon's
categories, written to benchmarks/throughput_requests.jsonl (committed with this script).

    python -m benchmarks.make_throughput_requests [--count 120] [--out FILE] [--check]

Deterministic: the categories in name order, round robin, each category's entries in the lexicon's order (the
everyday ones first); an entry is phrased as people ask for it ("a plush koala", "a kitchen sponge", "a strip of
bacon": its first noun that reads back as the entry) and taken only when the pipeline accepts the request
(tasks.request.checked_request: no rigid object, a size L0 can build) and L0 reads the text as that entry
(tasks.geometry.concepts.read_text); the others are skipped. --check: exit 1 when the committed file differs from
what the lexicon gives now.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Iterator
from pathlib import Path

from contracts.errors import DeformSmithError
from contracts.lexicon import LexiconEntry, load_lexicon
from contracts.request import AssetRequest
from tasks.geometry.concepts import read_text
from tasks.request import checked_request

DEFAULT_OUT = Path(__file__).with_name("throughput_requests.jsonl")
DEFAULT_COUNT = 120
# a plush animal is asked for as a toy ("a koala" alone is the animal); the rest by their name
PREFIX = {"plush_animal": "plush "}
# nouns of a stuff rather than a thing are asked for by a measure of it ("a strip of bacon", not "a bacon"), by the
# whole noun or its last word
MEASURE = {"bread": "a loaf of", "nori": "a sheet of", "bubble wrap": "a sheet of", "tofu": "a block of",
           "cheese": "a block of", "butter": "a stick of", "bacon": "a strip of"}
STUFF = frozenset({"nougat", "dough", "jelly", "taffy", "cotton candy", "tempeh", "marzipan", "clay", "slime",
                   "putty", "fudge", "sand", "yarn", "wool", "felt", "foam", "gelatin", "jello", "mince", "pastry"})
VOWEL_SOUND = ("a", "e", "i", "o", "u")
CONSONANT_SOUND = ("one", "uni", "use", "usu", "ure", "eu", "ewe")  # 'a onesie', 'a unicorn'


def article(words: str) -> str:
    """'a' or 'an' by how the words start."""
    return "an" if words.startswith(VOWEL_SOUND) and not words.startswith(CONSONANT_SOUND) else "a"


def phrasings(entry: LexiconEntry, noun: str) -> list[str]:
    """How people ask for the entry by this noun: 'a plush koala', 'an oven mitt', 'a strip of bacon' (then 'a
    bacon', in case L0 reads the measure otherwise)."""
    words = PREFIX.get(entry.category, "") + noun
    plain = f"{article(words)} {words}"
    last = noun.split()[-1]
    measure = MEASURE.get(noun) or MEASURE.get(last) or ("a piece of" if noun in STUFF or last in STUFF else None)
    return [f"{measure} {words}", plain] if measure else [plain]


def request_for(entry: LexiconEntry) -> str | None:
    """The first phrasing of the entry that the pipeline accepts and L0 reads back as the entry; None when none."""
    for noun in entry.nouns:
        if noun.startswith("("):  # '(generic)': the generic_* concepts, which no noun names
            return None
        for text in phrasings(entry, noun):
            try:
                checked_request(AssetRequest(text=text))
            except DeformSmithError:  # a rigid object, a size L0 cannot build
                continue
            if read_text(text).entry.key == entry.key:
                return text
    return None


def round_robin() -> Iterator[tuple[str, LexiconEntry]]:
    """(category, entry): one entry of each category in turn, categories by name, entries in the lexicon's order
    (its files by name, each file's entries as written: the everyday ones first)."""
    by_cat: dict[str, list[LexiconEntry]] = {}
    for entry in load_lexicon().entries.values():
        by_cat.setdefault(entry.category, []).append(entry)
    queues = {cat: iter(entries) for cat, entries in sorted(by_cat.items())}
    while queues:
        for cat in list(queues):
            following = next(queues[cat], None)
            if following is None:
                del queues[cat]
            else:
                yield cat, following


def make(count: int) -> list[dict[str, str]]:
    """`count` distinct requests (fewer when the lexicon runs out), each with its name and quality."""
    out: list[dict[str, str]] = []
    seen: set[str] = set()
    for _, entry in round_robin():
        text = request_for(entry)
        if text is None or text in seen:
            continue
        seen.add(text)
        name = f"{len(out) + 1:03d}_" + re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")
        out.append({"name": name, "text": text, "quality": "draft"})
        if len(out) == count:
            break
    return out


def render(requests: list[dict[str, str]]) -> str:
    return "".join(json.dumps(r) + "\n" for r in requests)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.make_throughput_requests", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--count", type=int, default=DEFAULT_COUNT, help="requests to write (at least 100 for #38)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--check", action="store_true", help="compare with --out instead of writing it")
    args = ap.parse_args(argv)
    requests = make(args.count)
    text = render(requests)
    cats = {load_lexicon().entries[read_text(r["text"]).entry.key].category for r in requests}
    if args.check:
        same = args.out.is_file() and args.out.read_text(encoding="utf-8") == text
        print(f"{args.out}: {'up to date' if same else 'differs from the lexicon'}", file=sys.stderr)
        return 0 if same else 1
    args.out.write_text(text, encoding="utf-8")
    print(f"{len(requests)} requests over {len(cats)} categories -> {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
