"""The words a pack prints on its label: the goods the request names ('a bag of rolled oats' -> ROLLED OATS, 'pack of
nappies' -> NAPPIES, 'a ketchup sachet' -> KETCHUP, 'a protein bar in its wrapper' -> PROTEIN BAR), as a real pack
carries its product's name."""

from __future__ import annotations

import functools
import re

from contracts.shape import MAX_PRINT_CHARS, Print, ShapeProgram
from tasks.geometry.wordnet import wordnet

CONTAINERS = ("multipack", "multi pack", "pocket pack", "pack", "packet", "package", "bag", "pouch", "sachet", "sack",
              "carton", "box", "wrapper", "tub", "tube", "ream", "parcel", "bottle", "jug", "pot")
_CONTAINER = "|".join(sorted((re.escape(c) for c in CONTAINERS), key=len, reverse=True))
_OF_GOODS = re.compile(rf"\b(?:{_CONTAINER})s?\s+of\s+(.+)")
# words after the goods that say no more about them ('a bag of fudge tied with ribbon', 'oats, half full', 'lens
# solution 10 fl oz')
_GOODS_END = re.compile(r"(?<=[a-z])\s+(?=\d)|\s*(?:[,;(]|\b(?:with|in|inside|on|tied|from|for|that|which|half|still|top|torn|opened|"
                        r"unopened|sealed|resealed|size|open|closed|crushed|squashed|rolled down|folded|new|full|"
                        r"empty|and then|by|at|to|like|about|around|approx)\b)")
_LEAD = re.compile(r"^(?:(?:a|an|the|some|of|fresh|loose|my|our|\d+(?:\.\d+)?|two|three|four|five|six|seven|eight|"
                   r"nine|ten|eleven|twelve|dozen|half|couple|pair|few)\s+)+")  # (a count is not the goods' name)
_CONTAINER_WORD = re.compile(rf"\b(?:{_CONTAINER})s?\b")
# words of a container's own kind, not of goods in it ('a standup pouch', 'a paper bag', 'an empty zip bag')
CONTAINER_KINDS = frozenset({"standup", "stand", "up", "paper", "plastic", "zip", "ziplock", "ziploc", "resealable",
                             "foil", "mesh", "kraft", "brown", "clear", "empty", "small", "large", "big", "little",
                             "mini", "giant", "reusable", "freezer", "gift", "party", "lunch", "sandwich", "shopping",
                             "carrier", "tote", "gym", "school", "beach", "sleeping", "laundry", "garbage", "trash", "gallon",
                             "pint", "litre", "liter", "quart", "squeezy", "squeeze", "food", "retail"})
LABEL_PARTS = ("label", "picture label")  # the parts a pack prints its name on, the first found
MAX_WORDS = 3


def goods_words(text: str, noun: str | None, food: bool = False) -> str | None:
    """The goods a request names for its pack's label, lower case: after '<container> of' in the text or in the
    entry's noun ('pack of tissues'), else a food's noun less its container words ('ketchup sachet', 'granola bar');
    None otherwise (a 'tote bag' or 'paper bag' names its bag, not goods in it)."""
    found = _OF_GOODS.search(text)
    words = ""
    if found is not None:
        words = _GOODS_END.split(found.group(1), maxsplit=1)[0]
    if not words.strip() and noun and (food or _OF_GOODS.search(noun)):
        words = " ".join(w for w in re.sub(r"\bof\b", " ", _CONTAINER_WORD.sub(" ", noun)).split()
                         if w not in CONTAINER_KINDS)
    words = _LEAD.sub("", " ".join(re.findall(r"[a-z0-9&'-]+", words)))
    words = re.split(r"\bof\s+", words)[-1]  # 'a pack of 50 sheets of origami paper': the paper
    if all(w in CONTAINER_KINDS for w in words.split()):
        return None
    kept = words.split()[-MAX_WORDS:]
    return " ".join(kept) or None


@functools.lru_cache(maxsize=256)
def food_goods(noun: str | None) -> bool:
    """Whether a container's noun names food before its container word ('ketchup bottle', 'cat food pouch'): its
    last other word's most frequent WordNet sense is a food."""
    words = [w for w in _CONTAINER_WORD.sub(" ", noun or "").split() if w not in CONTAINER_KINDS]
    if not words:
        return False
    senses = wordnet().senses(words[-1])
    return bool(senses) and senses[0].lexname == "noun.food"


@functools.lru_cache(maxsize=256)
def _food_noun(noun: str | None) -> bool:
    """Whether a pouch's noun names food before its container word ('ketchup sachet', 'cat food pouch'; not 'hockey
    bag', 'bean bag'): food_goods, and not a thing of its own in WordNet."""
    own = " ".join(w for w in (noun or "").split() if w not in CONTAINER_KINDS)
    if any(s.lexname == "noun.artifact" for form in (own.replace(" ", "_"), own.replace(" ", ""))
           for s in wordnet().senses(form)):
        return False  # a thing of its own ('a bean bag', 'a tea bag'), not a pack of the food
    return food_goods(noun)


def labelled(program: ShapeProgram, text: str, noun: str | None, food: bool = False,
             pouch: bool = False) -> ShapeProgram:
    """The program with the goods' name printed on its label part (LABEL_PARTS), else, for a pack the words name as
    one ('a bag of prawn crackers', 'a ketchup sachet': a pouch's noun is a pack), on its body; when the words fit
    (goods_words)."""
    names = {p.name for p in program.parts}
    part = next((name for name in LABEL_PARTS if name in names), None)
    words = goods_words(text, noun, food or (pouch and _food_noun(noun)))
    if part is None and words and "body" in names and (_OF_GOODS.search(text) or _CONTAINER_WORD.search(noun or "")):
        part = "body"
    if part is None or not words:
        return program
    printed = re.sub(r"[^A-Z0-9 &'.,-]", "", words.upper().replace("_", " ")).strip()
    if not printed or len(printed) > MAX_PRINT_CHARS:
        return program
    return program.model_copy(update={"prints": [Print(text=printed, part=part)]})
