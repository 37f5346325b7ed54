"""What a request says a bag, pouch or sack is filled with, and how full: 'half full of rice', 'filled with sand',
'a sand-filled ankle weight', 'an empty tote'. A fill's mass is its share of the bag's capacity times its loose bulk
density (contracts/vocab/fills.yaml, each with its source); the shape shows it slumped to the bag's bottom."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from pathlib import Path

from contracts.yaml_io import load_yaml

FILLS_FILE = Path(__file__).resolve().parents[2] / "contracts" / "vocab" / "fills.yaml"

# how full, in words -> share of capacity [-]
AMOUNTS: dict[str, float] = {
    "half": 0.5, "half full": 0.5, "halfway": 0.5, "half way": 0.5, "quarter": 0.25, "a quarter": 0.25,
    "three quarters": 0.75, "third": 0.33, "a third": 0.33, "two thirds": 0.67, "partly": 0.4, "partially": 0.4,
    "part": 0.4, "a little": 0.2, "slightly": 0.25, "nearly": 0.85, "almost": 0.85, "mostly": 0.75,
    "completely": 1.0, "fully": 1.0, "full": 0.9, "filled": 0.8, "stuffed": 0.9, "packed": 1.0,
}


@dataclass(frozen=True)
class Fill:
    """A stated fill: the fill's key, the words read, its share of capacity, bulk density and colour."""

    key: str
    words: str
    fraction: float
    bulk_density_kg_per_m3: float
    color: str
    source: str

    @classmethod
    def of(cls, rec: dict, words: str, fraction: float) -> Fill:
        """The fill of a table record ('key', bulk density, colour, source), read from `words` at `fraction`."""
        return cls(rec["key"], words, fraction, float(rec["bulk_density_kg_per_m3"]), rec["color"], rec["source"])

    def mass_kg(self, capacity_m3: float) -> float:
        """The fill's mass in a bag of this capacity [kg]."""
        return self.fraction * capacity_m3 * self.bulk_density_kg_per_m3


@functools.lru_cache(maxsize=1)
def fills() -> dict[str, dict]:
    """Fill word -> its record (contracts/vocab/fills.yaml), longest words first."""
    raw = load_yaml(FILLS_FILE.read_text(encoding="utf-8"))["fills"]
    table = {w: {"key": k, **v} for k, v in raw.items() for w in v["words"]}
    return dict(sorted(table.items(), key=lambda kv: -len(kv[0])))


@functools.lru_cache(maxsize=1)
def _by_key() -> dict[str, dict]:
    return {v["key"]: v for v in fills().values()}  # (every word of a fill carries the same record)


def record(key: str) -> dict | None:
    """The fill table's record of a fill key ('beans': its bulk density, colour, piece, tints...), None if unknown."""
    return _by_key().get(key)


def retail_bag_m(key: str) -> float | None:
    """The longest side of the bag a fill is usually sold in (a 50 l bag of compost: 0.7 m), if the table gives one."""
    rec = record(key)
    return float(rec["bag_m"]) if rec is not None and "bag_m" in rec else None


def retail_pack_kg(key: str) -> tuple[float, str] | None:
    """(mass [kg], source) of the retail pack a fill is usually sold in when smaller than a filled food bag of it (a bag
    of sweets: 150 g), if the table gives one."""
    rec = record(key)
    return (float(rec["pack_kg"]), str(rec["pack_source"])) if rec is not None and "pack_kg" in rec else None


def _amount(words: str) -> float | None:
    words = " ".join(words.split())
    if m := re.search(r"(\d{1,3})\s*%", words):
        return min(int(m.group(1)), 100) / 100.0
    for k in sorted(AMOUNTS, key=len, reverse=True):
        if re.search(rf"\b{k}\b", words):
            return AMOUNTS[k]
    return None


_AMOUNT_WORDS = (r"half|halfway|a quarter|quarter|three quarters|a third|two thirds|partly|partially|mostly|nearly|"
                 r"almost")
_FULLNESS = re.compile(rf"\b({_AMOUNT_WORDS})\s+(full|empty|used)\b")  # ('half-used': half of it used, half empty)


def stated_fullness(text: str) -> tuple[float, str] | None:
    """How full a request says a bag is with no fill named ('a half-empty sack of chicken feed': 0.5, 'a nearly
    empty bag': 0.15), and the words; None when it says nothing of it."""
    m = _FULLNESS.search(" ".join(text.lower().replace("-", " ").split()))
    if m is None:
        return None
    share = AMOUNTS[m.group(1)]
    return (share if m.group(2) == "full" else 1.0 - share), m.group(0)  # (empty or used: the rest is left)


_FULL_OF = re.compile(r"\b((?:\d{1,3}\s*%|[a-z]+(?:\s+[a-z]+)?)\s+)?(full|filled|stuffed|packed|loaded)\s+"
                      r"(?:up\s+)?(?:of|with)\s+(?:some\s+|dry\s+|loose\s+)?([a-z]+(?:\s+[a-z]+)?)")
_X_FILLED = re.compile(r"\b([a-z]+(?:\s+[a-z]+)?)[\s-]filled\b")
_BAG_OF = re.compile(r"\b(?:bag|pouch|sack|sachet|packet)\s+of\s+([a-z]+(?:\s+[a-z]+)?)")
# 'a quart ziplock bag w/ travel size liquids', 'a toiletry bag holding toothpaste and a razor': what a container is
# said to hold, when it is a fill of the table
_HOLDING = re.compile(r"\b(?:bag|pouch|sack|case|kit|cube|tote)\s+(?:w/\s*|(?:with|holding|containing)\s+)"
                      r"(?:some\s+|a few\s+|about\s+\d+\s+|\d+\s+)?([a-z]+(?:\s+[a-z]+){0,2})")
# 'half full - toothpaste, razor, deodorant': how full, then what with, after a dash, colon or bracket
# (the request's dash may be gone, 'half full toothpaste, razor': then an amount is said before 'full'; the words after
# name a fill of the table and no container: 'a full makeup bag' is the bag, full)
_FULL_LISTED = re.compile(rf"\b((?:{_AMOUNT_WORDS})\s+)?(full|filled|stuffed|packed|loaded)(\s*[-:(,]\s*|\s+)"
                          r"(?:with\s+|of\s+)?([a-z]+(?:\s+[a-z]+){0,2})")
_CONTAINER = re.compile(r"\b(?:bag|bags|pouch|case|kit|sack|tote|box|cube|bin|basket)\b")


def _fill_key(words: str) -> tuple[str, dict] | None:
    table = fills()
    for w in table:  # longest first: 'coffee beans' before 'beans'
        if re.search(rf"\b{re.escape(w)}\b", words):
            return w, table[w]
    return None


_QUALIFIERS = re.compile(r"^(?:(?:small|little|mini|tiny|big|large|assorted|various|several|some|loose|my|his|her|"
                         r"their|our)\s+)+")


def _leading_fill(words: str) -> tuple[str, dict] | None:
    """The fill the words start with ('travel size liquids for ...'), else None ('a straw hole', 'top rolled down':
    a fill word further in is another thing's)."""
    table = fills()
    words = _QUALIFIERS.sub("", words)  # ('travel size liquids' reaches here as 'small liquids')
    return next(((w, table[w]) for w in table if words == w or words.startswith(f"{w} ")), None)



def read_fill(text: str) -> Fill | None:
    """The fill a request states, if any: 'half full of rice' (0.5 of rice), 'filled with sand' (0.8), 'a
    sand-filled weight' (0.8), 'a bag of marbles' (0.8), 'a zip bag w/ travel size liquids' (0.8), 'half full -
    toothpaste, razor' (0.5); None when no fill word of the table is named."""
    t = " ".join(text.lower().replace("-", " ").split())
    for m in _FULL_OF.finditer(t):
        hit = _fill_key(m.group(3))
        if hit is None:
            continue
        amount = _amount(f"{m.group(1) or ''} {m.group(2)}") or 0.8
        return Fill.of(hit[1], m.group(0).strip(), amount)
    t2 = " ".join(text.lower().split())
    said = stated_fullness(text)  # 'a half-full bag of compost': the bag of compost, half full
    share, words = (said[0], f"{said[1]} ") if said is not None else (0.8, "")
    for m in _X_FILLED.finditer(t2):
        hit = _fill_key(m.group(1))
        if hit is not None:
            return Fill.of(hit[1], words + m.group(0).strip(), share)
    for m in _FULL_LISTED.finditer(t2):
        if not (m.group(1) or m.group(3).strip()) or _CONTAINER.search(m.group(4)):
            continue
        hit = _leading_fill(m.group(4))
        if hit is not None:
            return Fill.of(hit[1], m.group(0).strip(), said[0] if said is not None else AMOUNTS[m.group(2)])
    for m in _HOLDING.finditer(t2):
        hit = _leading_fill(m.group(1))
        if hit is not None:
            return Fill.of(hit[1], words + m.group(0).strip(), share)
    for m in _BAG_OF.finditer(t):
        hit = _fill_key(m.group(1))
        if hit is not None:
            return Fill.of(hit[1], words + m.group(0).strip(), share)
    return None
