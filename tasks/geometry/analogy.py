"""Unknown nouns by meaning: WordNet says what a noun is a kind of, and the first kind the lexicon knows lends its
shape, material and mass; failing that, the definition's shape, material, size and colour words build it
(contracts/vocab/wordnet.yaml). The chain of reasoning is kept, to be printed and recorded."""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


from tasks.geometry.wordnet import Sense, wordnet
from contracts.yaml_io import load_yaml

VOCAB_FILE = Path(__file__).resolve().parents[2] / "contracts" / "vocab" / "wordnet.yaml"
MAX_ANCESTORS = 8  # hypernym steps walked before giving up on the lexicon and the categories


@dataclass
class Analogy:
    """How WordNet explained an unknown noun: the sense used, the chain, and what it gives the build."""

    noun: str
    sense: Sense
    chain: list[str] = field(default_factory=list)
    concept: str | None = None  # lexicon key: a named donor (level 'hypernym') or a generic_* (level 'category')
    named_donor: bool = False
    kind: str | None = None  # the word of the kind that decided it ('dog' for a spaniel, 'bag' for a tote)
    shape_word: str | None = None  # a SHAPE_WORDS key read from the definition (level 'gloss')
    material_words: list[str] = field(default_factory=list)
    color_words: list[str] = field(default_factory=list)

    @property
    def level(self) -> str:
        """'hypernym' (a lexicon object's kind), 'category' (a generic class), 'gloss' (the definition's words)."""
        return "hypernym" if self.named_donor else "category" if self.concept else "gloss"


@functools.lru_cache(maxsize=1)
def vocab() -> dict[str, Any]:
    """contracts/vocab/wordnet.yaml."""
    return load_yaml(VOCAB_FILE.read_text(encoding="utf-8"))


def _words(text: str) -> list[str]:
    return re.findall(r"[a-z]+", text.lower())


def _overlap(sense: Sense, context: set[str]) -> int:
    """Words of the request found in a sense's definition and its nearest kinds (simplified Lesk): 'an arm sling' is
    the bandage that supports a forearm, not the drink."""
    text = " ".join([sense.definition, *(a.name for a in wordnet().ancestors(sense, 3))]).lower()
    return sum(1 for w in context if len(w) > 2 and w not in _LESK_STOP and w in text)


# words of a request that say nothing of which sense is meant ('the used gown' matched 'used for official occasions':
# the ceremonial robe, built as a 1.2 kg bathrobe)
_LESK_STOP = frozenset({"used", "use", "the", "and", "for", "with", "from", "off", "put", "that", "this", "its", "one",
                        "pick", "grab", "hand", "pass", "take", "get", "into", "onto", "out", "please", "pls", "can",
                        "you", "made", "make", "new", "old", "some", "any", "all"})


# words that say a noun is eaten: 'ground beef on a foam tray', 'a raw whole chicken' are meat, not the animal
FOOD_CUES = frozenset({"raw", "cooked", "ground", "minced", "mince", "frozen", "thawed", "sliced", "diced", "roast",
                       "roasted", "grilled", "fried", "boiled", "smoked", "marinated", "tray", "deli", "butcher",
                       "fillet", "fillets", "boneless", "skinless", "plucked", "shrink", "wrapped", "lb", "pound"})


def best_sense(noun: str, context: set[str] | None = None) -> Sense | None:
    """The physical sense of a noun: the one whose definition shares most words with the request, then one whose
    first word is the noun itself, else the most frequent; artifacts, food, animals and plants before natural objects
    and substances ('mould' the container, not soil)."""
    senses = wordnet().physical_senses(noun)
    if not senses:
        return None
    own = noun.replace(" ", "_").lower()
    ctx = (context or set()) - set(own.split("_"))
    tier = {"noun.artifact": 0, "noun.food": -1 if ctx & FOOD_CUES else 0, "noun.animal": 0, "noun.plant": 0,
            "noun.object": 1, "noun.substance": 2}
    ranked = sorted(enumerate(senses), key=lambda p: (_is_group(p[1]), -_overlap(p[1], ctx), p[1].lemmas[0] != own,
                                                      tier.get(p[1].lexname, 3), p[0]))
    return ranked[0][1]


def _is_group(sense: Sense) -> bool:
    """A taxonomic or other group filed among physical nouns ('pan', the chimpanzee genus), never an object a user
    asks for while another sense is one ('a rubber feed pan' is the vessel)."""
    return any(a.lemmas[0] in ("group", "taxonomic_group") for a in wordnet().ancestors(sense))


def domain_of_sense(sense: Sense) -> str:
    """'animal', 'food' or 'thing': the kind of object a WordNet sense names."""
    return {"noun.animal": "animal", "noun.food": "food", "noun.plant": "food"}.get(sense.lexname, "thing")


def explain(candidates: list[str], lexicon_nouns: dict[str, Any], shape_words: dict[str, Any],
            material_words: dict[str, str], color_words: dict[str, Any],
            lexicon_domain: Callable[[str], str] | None = None, context: str = "") -> Analogy | None:
    """The analogy for the longest candidate WordNet knows (e.g. 'yoga mat', then 'mat').

    lexicon_nouns: surface noun -> (concept key, ...) of the lexicon; shape_words: the shape words the grammar
    builds; material_words: material word -> class; color_words: colour word -> RGB; lexicon_domain(key): 'animal',
    'food' or 'thing' for a lexicon concept, so that a word of another sense lends nothing (a washer is a kind of
    seal, the gasket, not the lexicon's plush seal); context: the request, to choose among a noun's senses."""
    v = vocab()
    context_words = set(_words(context))
    too_general = set(v["too_general"])
    for noun in candidates:
        if noun in lexicon_nouns and noun != candidates[0]:  # 'a spatula head': the part of a spatula
            own = best_sense(noun, context_words) or Sense(0, (noun,), "", "noun.artifact", (), (), ())
            out = Analogy(noun=candidates[0], sense=own, concept=lexicon_nouns[noun][0], named_donor=True,
                          kind=noun)
            out.chain.append(f"a part or kind of '{noun}', which the lexicon knows")
            return out
        found = best_sense(noun, context_words)
        if found is None:
            continue
        sense = found
        out = Analogy(noun=noun, sense=sense)
        out.chain.append(f"WordNet: {sense.name} = '{sense.definition}'")
        # the sense itself first: 'a phone case' is a case (a class of its own), 'a cardboard box' a box
        path = [sense, *wordnet().ancestors(sense, MAX_ANCESTORS)]
        kinds: list[str] = []
        for anc in path[:MAX_ANCESTORS + 1]:
            words = [w.replace("_", " ") for w in anc.lemmas]
            if words[0] in too_general:
                continue
            if anc is not sense:
                kinds.append(words[0])
            what = f"a kind of {' < '.join(kinds)}" if kinds else f"WordNet's '{sense.name}'"
            donor = next((w for w in words if w in lexicon_nouns and (
                lexicon_domain is None or lexicon_domain(lexicon_nouns[w][0]) == domain_of_sense(anc))), None)
            if donor is not None:
                out.concept, out.named_donor, out.kind = lexicon_nouns[donor][0], True, donor
                out.chain.append(f"{what}; the lexicon knows '{donor}'")
                break
            generic = next((v["ancestors"][w] for w in words if w in v["ancestors"]), None)
            if generic is not None:
                out.concept, out.named_donor, out.kind = generic, not generic.startswith("generic_"), words[0]
                out.chain.append(f"{what}: the class '{words[0]}'"
                                 + (f", built like the lexicon's {generic.replace('_', ' ')}" if out.named_donor else ""))
                break
        gloss = _words(sense.definition)
        out.material_words = [w for w in gloss if w in material_words]
        out.color_words = [w for w in gloss if w in color_words]
        shape = next((v["gloss_shapes"][w] for w in gloss if w in v["gloss_shapes"]), None)
        if shape is not None and shape in shape_words:
            out.shape_word = shape
        if out.concept is None:
            said = [f"shape '{shape}'" if out.shape_word else None,
                    f"material '{out.material_words[0]}'" if out.material_words else None,
                    f"colour '{out.color_words[0]}'" if out.color_words else None]
            said_ = [s for s in said if s]
            if not said_:
                continue
            out.chain.append("its definition gives " + ", ".join(said_))
        return out
    return None


_AGE_SEX = re.compile(r"\b(young|male|female|adult|baby|castrated|uncastrated|immature|juvenile)\b")


def _sense_words(s: Sense) -> set[str]:
    return {lemma.replace("_", " ").lower() for lemma in s.lemmas}


@functools.lru_cache(maxsize=4096)
def kin_of(first: str, noun: str) -> str | None:
    """When a lexicon entry named ``first`` also lists ``noun`` and WordNet files the two as different kinds of one
    thing ('heron' and 'stork', both wading birds; 'camel' and 'deer'), the nearest kind they share; None when
    ``noun`` names the entry's object: a synonym, a kind of it or its kind, a word of it ('sea otter'), a noun whose
    definition names it ('kitten: young domestic cat'), a listed same object, or one WordNet does not know."""
    a, b = first.lower().strip(), noun.lower().strip()
    pairs = {frozenset(p) for p in vocab().get("same_object", [])}
    if a == b or set(a.split()) & set(b.split()) or frozenset((a, b)) in pairs:
        return None
    wn = wordnet()
    sa, sb = wn.senses(a), wn.senses(b)
    if not sa or not sb:
        return None
    a_off, b_off = {s.offset for s in sa}, {s.offset for s in sb}
    anc_a = {s.offset: wn.ancestors(s) for s in sa}
    anc_b = {s.offset: wn.ancestors(s) for s in sb}
    if a_off & b_off or any(a_off & {x.offset for x in v} for v in anc_b.values()) \
            or any(b_off & {x.offset for x in v} for v in anc_a.values()):
        return None
    def names(text: str, words: set[str]) -> bool:
        return any(re.search(rf"\b{re.escape(n)}s?\b", text) for n in words)

    own_a = set().union(*(_sense_words(s) for s in sa))
    parent_a = set().union(*(_sense_words(v[0]) for v in anc_a.values() if v))
    own_b = set().union(*(_sense_words(s) for s in sb))
    for s in sb:  # 'kitten: young domestic cat'; 'calf: young of domestic cattle' (the young, male or female of it)
        d = s.definition.lower()
        if names(d, own_a) or (_AGE_SEX.search(d) and names(d, parent_a)):
            return None
    if any(names(s.definition.lower(), own_b) for s in sa):
        return None
    best: tuple[int, str] | None = None
    for s in sb[:2]:
        chain = [x.offset for x in anc_b[s.offset]]
        for t in sa[:2]:
            shared = {x.offset: x for x in anc_a[t.offset]}
            common = next((i for i, o in enumerate(chain) if o in shared), None)
            if common is not None and (best is None or common < best[0]):
                best = (common, shared[chain[common]].name)
    return best[1] if best else "thing"
