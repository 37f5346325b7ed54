"""Sizes said by comparison ('the size of an orange', 'fist-sized') and length words that are not a supported unit.

A comparison resolves to a longest extent [m]: a body or everyday reference (fist, palm, coin...) from the table
below, else a lexicon object's typical size. A comparison that is not understood, or a number with a length word
this parser does not know, becomes a warning: a size is never dropped without saying so.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from contracts.lexicon import load_lexicon
from tasks.geometry.concepts import normalise, noun_index

# Everyday references [m], longest extent (adult hand anthropometry; coin ~ 1 euro / US quarter; credit card ISO/IEC 7810)
REFERENCE_SIZES_M: dict[str, float] = {
    "fist": 0.10, "palm": 0.09, "hand": 0.19, "thumb": 0.06, "finger": 0.08, "head": 0.22, "pocket": 0.12,
    "bite": 0.03, "coin": 0.025, "marble": 0.016, "pea": 0.01, "credit card": 0.086, "card": 0.086,
    "shoe box": 0.33, "shoebox": 0.33, "phone": 0.15, "smartphone": 0.15,
    "teacup": 0.09, "tea cup": 0.09, "mug": 0.1, "coffee mug": 0.1,  # a teacup's rim ~8-9.5 cm, a mug ~9-10 cm tall
}
# 'life-sized', 'full-size': the object's own typical size; nothing to change
SAME_SIZE_WORDS = frozenset({"life", "full", "real", "normal", "regular", "standard", "medium", "mid", "average",
                             "true", "actual", "natural"})

_NOT_A_SIZE_WORD = frozenset({"a", "an", "the", "any", "one", "same", "what", "this", "that", "of", "in", "by", "to",
                              "and", "for", "its", "right", "each", "every", "which", "no"})  # 'a size 5 football'

_ARTICLE = r"(?:an?\s+|the\s+|one\s+)?"
_OWNER = r"(?:(?:an?\s+)?(?:adult|child|kid|man|woman|person|grown\s*up)(?:'s|s')?\s+)?"
_COMPARE = re.compile(
    rf"\b(?:(?:about|roughly|around|approximately|nearly|almost)\s+)?(?:the\s+)?size\s+of\s+{_ARTICLE}{_OWNER}"
    r"([a-z]+(?:\s+[a-z]+)?)", re.I)
# ('deflated size 5 football': 'size 5' is the ball's size label, not 'deflated-sized'; development set 42)
_SIZED = re.compile(r"\b([a-z]+)(?:-|\s)?sized?\b(?!\s*\d)", re.I)
_LENGTH_WORD = re.compile(r"(\d+(?:\.\d+)?)\s*([a-zµ]*(?:met(?:er|re)s?|metric)|furlongs?|leagues?|nmi|angstroms?|"
                          r"parsecs?|light\s*years?)\b", re.I)


@dataclass
class SizeWords:
    """What the comparisons in a text say: a longest extent [m] (or None), the phrases read, and warnings."""

    longest_m: float | None = None
    stated: list[str] = field(default_factory=list)
    spans: list[tuple[int, int]] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def _lexicon_size(words: str) -> float | None:
    """Typical longest extent [m] of the lexicon object these words name (singular or plural), if any."""
    hit = noun_index().get(normalise(words))
    return None if hit is None else float(load_lexicon().entries[hit[0]].size_m)


def _reference_size(words: str) -> float | None:
    w = words.lower().strip()
    if w in REFERENCE_SIZES_M:
        return REFERENCE_SIZES_M[w]
    if w.endswith("s") and w[:-1] in REFERENCE_SIZES_M:
        return REFERENCE_SIZES_M[w[:-1]]
    return _lexicon_size(w)


def read_size_words(text: str, relative_words: frozenset[str] | set[str] = frozenset()) -> SizeWords:
    """Comparisons and unsupported length words in `text`; `relative_words` ('mini', 'giant') are left to modifiers."""
    out = SizeWords()
    for m in _COMPARE.finditer(text):
        words = m.group(1).split()
        size, end = None, m.end()
        for n in (2, 1):  # 'a tennis ball' before 'a tennis'; 'an orange with stripes' -> 'orange'
            if len(words) >= n and (size := _reference_size(" ".join(words[:n]))) is not None:
                end = m.end() if n == 2 else m.start(1) + len(words[0])
                break
        phrase = text[m.start():end]
        out.spans.append((m.start(), end))
        if size is None:
            out.warnings.append(f"size comparison '{phrase.strip()}' not understood: the object's typical size is used")
            continue
        out.longest_m = size
        out.stated.append(f"{phrase.strip()} (~{size:g} m)")
    for m in _SIZED.finditer(text):
        word = m.group(1).lower()
        if word in relative_words or word in _NOT_A_SIZE_WORD or any(a <= m.start() < b for a, b in out.spans):
            continue
        out.spans.append((m.start(), m.end()))
        if word in SAME_SIZE_WORDS:
            continue
        size = _reference_size(word)
        if size is None:
            out.warnings.append(f"size word '{m.group(0)}' not understood: the object's typical size is used")
            continue
        out.longest_m = size
        out.stated.append(f"{m.group(0)} (~{size:g} m)")
    for m in _LENGTH_WORD.finditer(text):
        out.warnings.append(f"length unit in '{m.group(0)}' not understood (use mm, cm, m, km, in or ft): ignored")
    return out


def strip_spans(text: str, spans: list[tuple[int, int]]) -> str:
    """`text` with the given character spans blanked out."""
    chars = list(text)
    for a, b in spans:
        chars[a:b] = " " * (b - a)
    return "".join(chars)


# a mass stated in a request: '1 kg', '500 g', '2 lb', '8 oz', '1.5 kilograms' -> kg
MASS_UNITS_KG: dict[str, float] = {"kg": 1.0, "kgs": 1.0, "kilo": 1.0, "kilos": 1.0, "kilogram": 1.0, "kilograms": 1.0,
                                   "kilogramme": 1.0, "kilogrammes": 1.0, "g": 1e-3, "gr": 1e-3, "gram": 1e-3,
                                   "grams": 1e-3, "gramme": 1e-3, "grammes": 1e-3, "mg": 1e-6, "lb": 0.45359237,
                                   "lbs": 0.45359237, "pound": 0.45359237, "pounds": 0.45359237,
                                   "oz": 0.028349523125, "ounce": 0.028349523125, "ounces": 0.028349523125}
# a fabric's weight grade in ounces is no mass of the object ('2oz poly wadding', '12 oz canvas', '10oz denim',
# '8 oz per yard')
_FABRIC_GRADE = re.compile(r"\s*(?:/\s*(?:sq|yd|yard|m)\b|per\s+(?:sq|square|yard|metre|meter|m)\b)|\s+(?:(?!of\b)[a-z]+\s+)?"
                           r"(?:wadding|batting|canvas|denim|duck|fleece|fabric|twill|felt|hessian|burlap|wool|cotton|"
                           r"leather|vinyl)\b", re.I)
_MASS = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?|\d*\.\d+)\s*(" + "|".join(sorted(MASS_UNITS_KG, key=len, reverse=True))
                   + r")(?![a-z])", re.I)


def _mass_match(text: str) -> re.Match[str] | None:
    """The first mass in the text that is not a fabric's weight grade in ounces."""
    for m in _MASS.finditer(text):
        if m.group(2).lower() in ("oz", "ounce", "ounces") and _FABRIC_GRADE.match(text, m.end()):
            continue
        return m
    return None


@dataclass
class StatedMass:
    """A mass the request states: its value [kg] (SI), the words read and their span in the text."""

    kg: float
    stated: str
    span: tuple[int, int]


# a fraction in words before a mass unit: 'a quarter-pound bag', 'half a pound of', 'a half kilo'
_FRACTION_MASS = re.compile(r"(?<![\w.])(quarter|half|three quarters?|three quarter)(?:\s*a)?[\s-]+(" +
                            "|".join(sorted(MASS_UNITS_KG, key=len, reverse=True)) + r")(?![a-z])", re.I)
_FRACTIONS = {"quarter": 0.25, "half": 0.5, "three quarter": 0.75, "three quarters": 0.75}


def read_stated_mass(text: str) -> StatedMass | None:
    """The object's mass said in a request ('sand-filled ankle weight, 1 kg' -> 1.0 kg; '2 lb' -> 0.907 kg;
    'a quarter-pound bag' -> 0.113 kg); the first one wins. None when no mass is stated ('a 2 l bag' is a volume;
    'weighs about' alone is no number)."""
    m = _mass_match(text)
    f = _FRACTION_MASS.search(text)
    if f is not None and (m is None or f.start() < m.start()):
        kg = _FRACTIONS[" ".join(f.group(1).lower().split())] * MASS_UNITS_KG[f.group(2).lower()]
        return StatedMass(kg=kg, stated=f.group(0).strip(), span=(f.start(), f.end()))
    if m is None:
        return None
    kg = float(m.group(1)) * MASS_UNITS_KG[m.group(2).lower()]
    if kg <= 0:
        return None
    return StatedMass(kg=kg, stated=m.group(0).strip(), span=(m.start(), m.end()))
