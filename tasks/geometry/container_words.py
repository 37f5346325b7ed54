"""A request for a container of goods the lexicon does not name ('a tube of tomato puree', '500ml bottle of shower gel',
'a box of 6 chewy cereal bars', 'honey in one of those squeezy bear bottles') read as the lexicon's container of that
kind with the goods printed on its label (tasks/geometry/label_words.py): it was a generic block, bag or blob named
after the container word (development set 60)."""

from __future__ import annotations

import re

from tasks.geometry import label_words
from tasks.geometry.wordnet import wordnet

# container word -> the lexicon noun of that container (a drink's when the goods are a drink)
CONTAINER_NOUNS: dict[str, tuple[str, str]] = {
    "tube": ("squeeze tube", "squeeze tube"),
    "bottle": ("squeeze bottle", "plastic bottle"),
    "tub": ("food tub", "food tub"),
    "pot": ("food tub", "food tub"),
    "box": ("retail box", "milk carton"),
    "carton": ("retail box", "milk carton"),
    "jug": ("milk jug", "milk jug"),
}
DRINK_WORDS = frozenset({"water", "juice", "drink", "drinks", "squash", "pop", "soda", "milk", "milkshake", "smoothie",
                         "lemonade", "cola", "coke", "kombucha", "iced tea", "cordial"})
# words of a container's own kind, not goods ('a squeezy plastic bottle'): a pack's (label_words) and these
KIND_WORDS = label_words.CONTAINER_KINDS | frozenset({
    "cardboard", "sized", "size", "crushed", "squashed", "dented", "half", "full", "open", "opened", "new", "old",
    "upside", "down", "those", "one", "of", "the", "a", "an", "bear", "shaped", "kind", "ml", "l", "oz", "g", "kg",
    "travel", "family", "spray", "pump", "trigger", "sports", "squirt", "refill"})
# what ends goods words, said after 'of' or before the container word ('crushed' and a measure there are kind words:
# label_words' end, which stops at them, would leave nothing of 'a crushed 2 litre fizzy drink bottle')
_GOODS_END = re.compile(r"\s*(?:[,;(]|\b(?:with|in|inside|on|for|that|which|half|still|from|the|and then|by|at|to|"
                        r"like|about|around|approx|gone|bit|slightly)\b)")
_IN_CONTAINER = re.compile(r"^(?P<goods>[a-z][a-z' ]*?)\s+in\s+(?:an?|the|its|one of (?:those|these|the)|those|these)"
                           r"\s+(?:[a-z]+\s+){0,3}?(?P<container>" + "|".join(CONTAINER_NOUNS) + r")s?\b")


def _drink(goods: str) -> bool:
    """Whether the goods' last word (or last two) names a drink: a word of DRINK_WORDS or a WordNet beverage."""
    words = goods.split()
    if not words:
        return False
    if words[-1] in DRINK_WORDS or " ".join(words[-2:]) in DRINK_WORDS:
        return True
    return any(a.name == "beverage" for s in wordnet().senses(words[-1])[:2] for a in wordnet().ancestors(s))


def _stuff(goods: str) -> bool:
    """Whether the goods' last word is, by its most frequent WordNet sense, a food or a substance (what a container
    holds: 'honey', 'shower gel'; not 'gift', 'felt')."""
    words = goods.split()
    senses = wordnet().senses(words[-1]) if words else []
    return bool(senses) and senses[0].lexname in ("noun.food", "noun.substance")


def _goods(words: str) -> str:
    """The goods words: up to what is said after them, less container-kind words, numbers and units."""
    words = _GOODS_END.split(words, maxsplit=1)[0]
    kept = [w for w in re.findall(r"[a-z']+", words) if w not in KIND_WORDS]
    return " ".join(kept[-3:])


def container_of_goods(text: str, head: str | None, before_head: list[str]) -> tuple[str, str] | None:
    """(the container's lexicon noun, the goods) for a request whose object is a container of goods: the head is a
    container word with 'of <goods>' after it or goods words before it ('a squeezy honey bottle'), or the goods are the
    head and lie 'in' a container ('honey in one of those squeezy bear bottles'); None otherwise."""
    low = text.lower().strip()
    container, goods = None, ""
    single = (head or "").lower().rstrip("s") if (head or "").lower() not in CONTAINER_NOUNS else (head or "").lower()
    if single in CONTAINER_NOUNS:
        container = single
        m = re.search(rf"\b{single}s?\s+of\s+(.+)", low)
        goods = _goods(m.group(1)) if m else _goods(" ".join(before_head))
        if m is None and not _stuff(goods):
            return None  # ('a felt gift box' is a box, not one of felt gifts)
    else:
        m = _IN_CONTAINER.match(re.sub(r"^(?:a|an|some|the)\s+", "", low))
        if m is not None and m.group("container") in CONTAINER_NOUNS and _stuff(_goods(m.group("goods"))):
            container, goods = m.group("container"), _goods(m.group("goods"))
    if container is None or not goods:
        return None  # (a bare 'bottle' stays unknown: a photo of one is drawn as the lathe of its silhouette)
    food, drink = CONTAINER_NOUNS[container]
    return (drink if _drink(goods) else food), goods
