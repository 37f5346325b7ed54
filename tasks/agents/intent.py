"""Material intent -> TargetBehaviour: vocabulary words and explicit numbers, overridable by the request."""

from __future__ import annotations

import functools
import math
import re

from pydantic import ValidationError

from contracts.agents import TargetBand, TargetBehaviour
from contracts.concept import ConceptMatch
from contracts.errors import InputError, validation_message
from contracts.lexicon import load_lexicon
from contracts.request import AssetRequest
from tasks.agents.vocab import MaterialVocab, load_material_vocab

_NUM = r"([-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)"
_SEP = r"\s*(?:=|:|~|≈|of|is|at|around|about)?\s*"
_PA_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9}

# metric -> phrase regex; the number follows the phrase (ratios accept a trailing % sign)
_RATIO_PHRASES: dict[str, str] = {
    "rebound_ratio": r"(?:rebound(?:\s+ratio)?|bounce(?:\s+ratio)?|restitution)",
    "recovery_ratio": r"(?:recovery(?:\s+ratio)?|recovers?)",
    "sag_ratio": r"(?:sag(?:\s+ratio)?|sags?)",
    "max_impact_strain": r"(?:impact\s+strain|max(?:imum)?\s+impact\s+strain)",
}
_MODULUS = re.compile(
    r"(?:\bE\b|young'?s\s+modulus|elastic\s+modulus|effective\s+modulus|modulus|stiffness)" + _SEP + _NUM
    + r"\s*(gpa|mpa|kpa|pa)\b", re.IGNORECASE)
_DENSITY = re.compile(r"(?:density|\brho\b)" + _SEP + _NUM + r"\s*kg\s*/\s*m(?:\^?3|³)", re.IGNORECASE)
_POISSON = re.compile(r"(?:poisson(?:'s)?(?:\s+ratio)?|\bnu\b)" + _SEP + _NUM, re.IGNORECASE)


def _contains_phrase(text: str, phrase: str) -> bool:
    return re.search(r"(?<![a-z])" + re.escape(phrase.lower()) + r"(?![a-z])", text) is not None


def check_deformable(text: str, vocab: MaterialVocab) -> None:
    """InputError when the text names a rigid material (steel, glass, wood, ...) and no deformable one. A rigid
    material said of an attachment ('a rolled bandage with a metal clip', 'a plush toy next to a steel bowl') does not
    make the object rigid: only the words before 'with', 'next to', 'beside' ... count."""
    named = [w for entry in vocab.materials.values() for w in entry.words if _contains_phrase(text, w)]
    own = re.split(r"\s+(?:with|next to|beside|besides|on|in|inside|under|plus|and a|and an)\s+", text, maxsplit=1)[0]
    rigid = [w for w in vocab.rigid_words if _contains_phrase(own, w)]
    if rigid and not named:
        soft = ", ".join(sorted({entry.words[0] for entry in vocab.materials.values()})[:8])
        raise InputError(
            f"'{max(rigid, key=len)}' is a rigid material (Young's modulus ~1e9-1e11 Pa): DeformSmith makes deformable "
            f"objects. Name a deformable material (e.g. {soft}) in the text or with --intent"
        )


# what may follow an object noun that is the head of its phrase ('a mug', 'a mug 9 cm tall', 'a mug with a handle');
# another noun after it makes it a modifier ('pot holder', 'jar opener', 'mug rug', 'chair cushion')
_HEAD_END = r"(?=\s*$|\s*[^\w\s]|\s+(?:of|on|in|with|and|or|from|that|which|for|at|by|is|was|to|about|\d)\b)"


def _names_object(text: str, noun: str) -> bool:
    """True when the text names the object noun as the head of a phrase (not as the modifier of another noun)."""
    end = "" if noun.endswith(" of") else _HEAD_END
    return re.search(r"(?<![a-z])" + re.escape(noun) + r"(?![a-z])" + end, text) is not None


# where the object is, or what it is for, not what it is: 'a cardigan draped over an office chair', 'a rag on the
# workbench', 'a plastic tablecloth for a long table' (set 40's was refused as a rigid table), or what comes with it
# ('a little pot of pasta salad with a fork in the lid': sealed set 46's was refused as a rigid fork)
_PLACE = re.compile(r"\s+(?:on top of|next to|on|onto|in|into|inside|under|underneath|over|across|against|atop|"
                    r"behind|beside|besides|near|from|off|at|for|with)\s+(?:an?|the|its|his|her|their|my|your|some)\s")


def _own_words(text: str) -> str:
    """The words of the object itself: the text before a place it is put in, on or over ('... over a chair')."""
    return _PLACE.split(text, maxsplit=1)[0]


@functools.lru_cache(maxsize=1)
def _soft_lexicon_nouns() -> tuple[str, ...]:
    """The lexicon's nouns that hold a rigid object's word ('baby spoon', 'sack chair', 'melon pan'): the lexicon
    names deformable objects only, so naming one of them is naming something soft."""
    rigid = load_material_vocab().rigid_objects
    nouns = {" ".join(n.lower().replace("-", " ").split()) for e in load_lexicon().entries.values() for n in e.nouns}
    # (the plain substring test first: each _names_object builds a new pattern, and ~3,000 nouns x ~200 rigid words
    # of them were ~1.3 s of every process that reads a text naming a rigid object)
    return tuple(sorted(n for n in nouns if any(w in n and _names_object(n, w) for w in rigid)))


# measure words that, before 'of', shape the goods named after them: 'a vacuum brick of hop pellets' is the pellets
# ('a pot of pasta salad': a plastic food pot, sealed set 46)
MEASURE_OF_WORDS = frozenset({"brick", "block", "bar", "slab", "cube", "stick", "log", "sheet", "roll", "pot"})


def _measures_goods(text: str, word: str) -> bool:
    """True when the rigid word is a measure of the goods after it ('a brick of coffee', 'a block of tofu')."""
    return word in MEASURE_OF_WORDS and re.search(rf"(?<![a-z]){re.escape(word)}s?\s+of\s+[a-z]", text) is not None


def rigid_object(text: str, vocab: MaterialVocab | None = None, also: tuple[str, ...] = ()) -> str | None:
    """The rigid object noun a text (or one of the texts `also` read beside it: a photo's file name) names ('a can',
    'teacup', 'figurine') when none of them names a deformable material, soft object word, soft word or a lexicon
    object whose noun holds the rigid word ('a baby spoon'); None otherwise. Each text is read on its own (a noun is
    the head of a phrase within its own text)."""
    vocab = vocab or load_material_vocab()
    texts = [" ".join(t.lower().replace("_", " ").replace("-", " ").split()) for t in (text, *also) if t]
    rigid = [w for t in texts for w in vocab.rigid_objects if _names_object(_own_words(t), w)
             and not _measures_goods(_own_words(t), w)]
    if not rigid:
        return None
    soft = [w for entry in vocab.materials.values() for w in entry.words] + list(vocab.objects) + vocab.soft_words
    soft += _soft_lexicon_nouns()
    if any(_soft_outside(t, w, rigid) for t in texts for w in soft):
        return None
    return max(rigid, key=len)


def _soft_outside(text: str, soft: str, rigid: list[str]) -> bool:
    """True when the soft word is in the text other than as a word of a rigid noun found there: the 'ball' of 'a
    bowling ball' says nothing soft, the 'plush' of 'a plush bowling ball' does ('a baby spoon' is a lexicon noun
    holding 'spoon': it contains the rigid word, not the other way round)."""
    if not _contains_phrase(text, soft):
        return False
    inside = [r for r in rigid if r != soft and _contains_phrase(r, soft)]
    for r in inside:
        text = re.sub(rf"(?<![a-z]){re.escape(r)}(?![a-z])", " ", text)
    return _contains_phrase(text, soft)


def check_rigid_object(text: str, vocab: MaterialVocab | None = None, where: str = "",
                       also: tuple[str, ...] = ()) -> None:
    """InputError (one line) when the text (or the texts `also`) names a rigid object and nothing soft (see
    rigid_object)."""
    vocab = vocab or load_material_vocab()
    noun = rigid_object(text, vocab, also)
    if noun is not None:
        noun = noun.removeprefix("a ").removeprefix("the ").removeprefix("this ").removeprefix("one ")
        noun = noun.removesuffix(" of")
        soft = ", ".join(m for m in ("plush", "foam", "silicone", "rubber", "gel") if m in {
            w for entry in vocab.materials.values() for w in entry.words}) or "plush"
        raise InputError(
            f"'{noun}'{where} is a rigid object as usually made (metal, glass, ceramic, wood or hard plastic): "
            f"DeformSmith makes deformable objects. Name a deformable material (e.g. {soft}) in the text or with "
            "--intent, e.g. 'a plush " + noun + "'"
        )


def image_words(request: AssetRequest) -> str:
    """A photo's file name as words ('soda_can-2.jpg' -> 'a soda can 2'); empty for other requests."""
    if request.image_path is None:
        return ""
    stem = re.sub(r"[_\-.]+", " ", request.image_path.stem).strip()
    return f"a {stem}" if stem else ""


def check_request_object(request: AssetRequest, vocab: MaterialVocab | None = None) -> None:
    """The request's words (text, intent and a photo's file name together) name no rigid object, unless a soft word
    is named among them (InputError, one line)."""
    vocab = vocab or load_material_vocab()
    words = " ".join(w for w in (request.text, request.material_intent) if w)
    stem = image_words(request)
    if stem:  # 'glass_vase.jpg' names a rigid material as the text 'a glass vase' does
        check_deformable(" ".join(f"{words} {stem}".lower().split()), vocab)
    check_rigid_object(words, vocab, "" if not stem or rigid_object(words, vocab) else " (the photo's file name)",
                       also=(stem,))


# words that name a family of material classes rather than one: 'a foam kneeling pad' is the closed-cell foam of the
# kneeling pad L0 built, 'a latex balloon' the balloon's inflated latex, 'a plush pillow' the plush toy pillow
FAMILY_WORDS: dict[str, frozenset[str]] = {
    "foam": frozenset({"pu_foam", "pe_foam", "sponge", "slow_rise_foam"}),
    "rubber": frozenset({"rubber", "inflatable", "silicone"}),
    "latex": frozenset({"rubber", "inflatable"}),
    # a soft surface, not a stuffing: 'a fluffy pet bed' is the foam-filled bed, 'a fluffy sock' the knit sock
    "fluffy": frozenset({"plush", "pu_foam", "textile"}),
    "cuddly": frozenset({"plush", "pu_foam", "textile"}),
}


# a measure noun before 'of' is the amount of what follows, not its material ('a roll of tape', 'rolls of wrap')
_MEASURE_OF = re.compile(r"\b(?:roll|rolls)\s+of\b")
# food classes: 'stuffed' said of a food is its filling, not a stuffed toy's plush (sealed set 29's calzone weighed 40 g)
_FOOD_CLASSES = frozenset({"cheese", "processed_meat", "firm_produce", "bread", "fruit", "marshmallow", "dough", "gel"})
_STUFFED = re.compile(r"\b(?:stuffed|fluffy)\b")
# what comes with a food is a topping or side, not its material ('hot cocoa with marshmallows' is a drink, not a
# marshmallow); 'made with' still names it
_FOOD_WITH = re.compile(r"(?<!made )\bwith\b.*$")


# a material said of a surface only: a coating, dip, lining or trim ('rubber-coated', 'latex-dipped', 'fleece-lined',
# 'coated in latex'): not what the object is made of
_SURFACE_ONLY = re.compile(r"\b[a-z]+[\s-]+(?:coated|dipped|lined|trimmed|edged|palmed)\b|"
                           r"\b(?:coated|dipped|lined|trimmed|edged)\s+(?:in|with)\s+[a-z]+\b|"
                           r"\bwith\s+(?:[a-z]+\s+)?[a-z]+\s+(?:dots|grips?|palms?|soles?|patches|trim|piping)\b|"
                           # a part's material ('a blood pressure cuff with its rubber tube', 'a bag with plastic
                           # handles'): the part's, not the object's
                           r"\bwith\s+(?:(?:its|their|a|an|the|two)\s+)?(?:[a-z]+\s+)?[a-z]+\s+(?:tube|tubing|hose|"
                           r"cord|handles?|straps?|cap|lid|string|tag|valve|plug|nozzle|clip|buckle|zip|zipper|"
                           r"bulb|stem|spout|bell)\b|"
                           # what ties or holds it ('a bunch of kale tied with a rubber band'): not its material
                           r"\b(?:tied|held|bound|banded|secured|fastened|wrapped)(?:\s+(?:together|up|round|around))?"
                           r"\s+(?:with|by)\s+(?:(?:an?|its|the|two|a few)\s+)?(?:[a-z]+\s+){0,2}(?:bands?|string|"
                           r"twine|ribbons?|ties?|clips?|cord)\b")


_STATE_ONLY = frozenset({"inflated"})  # material words that only say a known object's state


def _match_material(text: str, vocab: MaterialVocab, concept_material: str | None = None,
                    own_words: frozenset[str] = frozenset(), hollow: bool = False) -> tuple[str, str | None]:
    """The material named by the longest matching word (materials first, then the concept L0 built, then object
    words); the default otherwise. The concept's own material wins when the text names it too ('a plush pillow' is
    plush, though 'pillow' is a foam word) or names only its family ('foam' for a closed-cell foam pad). A word of
    the concept's own nouns (own_words) names that object, not a material ('an inflatable arm cuff' is the blood
    pressure cuff's nylon sleeve, not an air-filled inflatable)."""
    best: tuple[int, str, str] | None = None
    named: dict[str, str] = {}
    text = _MEASURE_OF.sub(" ", text)  # 'a roll of bubble wrap' names no bread
    text = _SURFACE_ONLY.sub(" ", text)  # 'rubber-coated gloves' are knit gloves, not solid rubber
    if concept_material in _FOOD_CLASSES:
        text = _STUFFED.sub(" ", text)  # 'a calzone stuffed with ricotta', 'a stuffed pepper': a filling, not plush;
        # 'a fluffy pancake': a texture, not a plush toy's density (sealed set 43's pancake weighed a quarter)
        text = _FOOD_WITH.sub(" ", text)
    for name, entry in vocab.materials.items():
        for word in entry.words:
            if concept_material not in (None, name) and set(word.lower().split()) <= own_words:
                continue
            if hollow and concept_material is not None and word in _STATE_ONLY:
                continue  # 'an inflated balance cushion' is the cushion's rubber shell, blown up
            if _contains_phrase(text, word):
                named.setdefault(name, word)
                if best is None or len(word) > best[0]:
                    best = (len(word), name, word)
    if concept_material in vocab.materials and (best is None or _agrees(named, str(concept_material))):
        return str(concept_material), named.get(str(concept_material))
    if best is None:
        for word, name in vocab.objects.items():
            if _contains_phrase(text, word) and (best is None or len(word) > best[0]):
                best = (len(word), name, word)
    if best is None:
        return vocab.default_material, None
    return best[1], best[2]


def _agrees(named: dict[str, str], concept_material: str) -> bool:
    """True when the material words of a text (class -> word) include the concept's class, or every one is a family
    word that covers it."""
    return concept_material in named or all(concept_material in FAMILY_WORDS.get(w, ()) for w in named.values())


def match_material(text: str, vocab: MaterialVocab | None = None, concept_material: str | None = None,
                   own_words: frozenset[str] = frozenset(), hollow: bool = False) -> str:
    """The vocabulary material a text names (longest matching word; else the concept's default material; else the
    default material); own_words: the words of the concept's own nouns (see _match_material)."""
    vocab = vocab or load_material_vocab()
    return _match_material(text.lower(), vocab, concept_material, own_words, hollow)[0]


def _narrow(low: float, high: float, frac: tuple[float, float], log: bool) -> tuple[float, float]:
    """The [f0, f1] fraction of a band, measured in its scale."""
    if log:
        a, b = math.log10(low), math.log10(high)
        return 10 ** (a + frac[0] * (b - a)), 10 ** (a + frac[1] * (b - a))
    return low + frac[0] * (high - low), low + frac[1] * (high - low)


def _explicit_band(metric: str, value: float, vocab: MaterialVocab) -> tuple[float, float]:
    """A band around a stated number, with the vocabulary's tolerance."""
    tol = vocab.explicit_tolerance
    if vocab.metric(metric).scale == "log":
        return value / tol.log_factor, value * tol.log_factor
    return max(0.0, value - tol.linear_abs), value + tol.linear_abs


def explicit_numbers(text: str) -> tuple[dict[str, float], dict[str, float]]:
    """Numbers stated in the text: (metric -> value, prior field -> value), SI units."""
    metrics: dict[str, float] = {}
    priors: dict[str, float] = {}
    if m := _MODULUS.search(text):
        metrics["effective_modulus_pa"] = float(m.group(1)) * _PA_UNITS[m.group(2).lower()]
        priors["youngs_modulus_pa"] = metrics["effective_modulus_pa"]
    for metric, phrase in _RATIO_PHRASES.items():
        if m := re.search(r"(?<![a-z])" + phrase + _SEP + _NUM + r"\s*(%?)", text, re.IGNORECASE):
            value = float(m.group(1)) / (100.0 if m.group(2) == "%" else 1.0)
            metrics[metric] = value
    if m := _DENSITY.search(text):
        priors["density_kg_per_m3"] = float(m.group(1))
    if m := _POISSON.search(text):
        priors["poisson_ratio"] = float(m.group(1))
    return metrics, priors


def targets_from_intent(
    intent: str, overrides: dict[str, tuple[float, float]] | None = None, vocab: MaterialVocab | None = None,
    concept: ConceptMatch | None = None,
) -> TargetBehaviour:
    """Bands and priors for the words of an intent; explicit numbers beat words, overrides beat both. The concept L0
    built (if any) gives the material when the words name none."""
    vocab = vocab or load_material_vocab()
    text = " ".join(intent.lower().split())
    check_deformable(text, vocab)
    check_rigid_object(text, vocab)
    name, word = _match_material(text, vocab, concept.default_material if concept else None, own_nouns(concept),
                                 bool(concept and concept.hollow))
    entry = vocab.materials[name]
    by_concept = word is None and concept is not None and concept.default_material == name
    source = f"vocab:{word}" if word else f"concept:{concept.concept}({name})" if by_concept and concept else \
        f"vocab:default({name})"
    bands: dict[str, tuple[float, float, str]] = {m: (lo, hi, source) for m, (lo, hi) in entry.bands.items()}
    matched = [word] if word else []
    for mod in vocab.modifiers.values():
        hit = next((w for w in sorted(mod.words, key=len, reverse=True) if _contains_phrase(text, w)), None)
        if hit is None:
            continue
        matched.append(hit)
        text = re.sub(r"(?<![a-z])" + re.escape(hit.lower()) + r"(?![a-z])", " ", text)  # 'very soft' is not also 'soft'
        for metric, frac in mod.band_fraction.items():
            if metric in bands:
                lo, hi, _ = bands[metric]
                lo, hi = _narrow(lo, hi, frac, vocab.metric(metric).scale == "log")
                bands[metric] = (lo, hi, f"{source}+{hit}")
        for metric, (lo, hi) in mod.bands.items():
            bands[metric] = (lo, hi, f"vocab:{hit}")
    priors = dict(entry.priors)
    stated, stated_priors = explicit_numbers(intent)
    for metric, value in stated.items():
        lo, hi = _explicit_band(metric, value, vocab)
        bands[metric] = (lo, hi, f"request:{metric}={value:g}")
    priors.update(stated_priors)
    hard = concept.youngs_modulus_range_pa if concept is not None and concept.default_material == name else None
    if concept is not None and hard is not None and "effective_modulus_pa" in bands \
            and "effective_modulus_pa" not in stated and bands["effective_modulus_pa"][2] == source:
        # a published hardness (Gent's modulus band), where no word narrowed the band ('a soft racquetball')
        bands["effective_modulus_pa"] = (float(hard[0]), float(hard[1]), f"concept:{concept.concept}:hardness")
    if "effective_modulus_pa" in bands and "effective_modulus_pa" not in stated:
        lo, hi, _ = bands["effective_modulus_pa"]  # seed E inside the (possibly narrowed) modulus band
        priors["youngs_modulus_pa"] = math.sqrt(lo * hi)
    for metric, (lo, hi) in (overrides or {}).items():
        if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise InputError(f"target override {metric}: need finite low <= high, got ({lo}, {hi})")
        bands[metric] = (float(lo), float(hi), "override")
    out = []
    for metric, (lo, hi, src) in sorted(bands.items()):
        spec = vocab.metric(metric)
        scale = spec.scale if not (spec.scale == "log" and lo <= 0) else "linear"
        out.append(TargetBand(metric=metric, unit=spec.unit, low=lo, high=hi, weight=spec.weight, scale=scale, source=src))
    return TargetBehaviour(bands=out, priors=priors, matched_words=matched, intent=intent)


def targets_from_request(request: AssetRequest, vocab: MaterialVocab | None = None) -> TargetBehaviour:
    """The target behaviour of a request: material_intent (else the text) plus target_overrides."""
    intent = request.material_intent or request.text or ""
    check_request_object(request, vocab)  # a photo named 'teacup.jpg' is refused like the text 'a teacup'
    return targets_from_intent(intent, dict(request.target_overrides), vocab)


# -- the one path from an L0 asset record to its material (generate and the layer-by-layer commands alike) ----------
def concept_of(record: dict) -> ConceptMatch | None:
    """The concept L0 recorded for its request (geometry.json info.concept); None when the record has none."""
    raw = (record.get("info") or {}).get("concept")
    if not raw:
        return None
    try:
        return ConceptMatch.model_validate(raw)
    except ValidationError as exc:
        raise InputError(f"geometry.json info.concept is not a valid ConceptMatch: {validation_message(exc)}") from None


def stored_request(record: dict) -> AssetRequest | None:
    """The whole request L0 stored in its directory (geometry.json request); None for records written without it."""
    raw = record.get("request")
    if not raw:
        return None
    try:
        return AssetRequest.model_validate(raw)
    except ValidationError as exc:
        raise InputError(f"geometry.json request is not a valid request: {validation_message(exc)}") from None


def request_intent(request: AssetRequest | None, record: dict) -> str:
    """The words a material comes from: the request's material intent, else its text, else what L0 built (the
    name and category it recorded, for an image or mesh without text or an asset stored without its request)."""
    if request is not None and (request.material_intent or request.text):
        return str(request.material_intent or request.text)
    info = record.get("info") or {}
    return " ".join(str(x) for x in (info.get("name"), info.get("category")) if x)


def asset_targets(record: dict, given: AssetRequest | str | None = None,
                  vocab: MaterialVocab | None = None) -> TargetBehaviour:
    """The target behaviour of an L0 asset: from the request or intent given, else from the request L0 stored
    (words, modifiers and target overrides), with the material of the concept L0 built when the words name none.
    `generate` and `geometry` -> `physical` -> `material` both come through here, so they agree."""
    request = given if isinstance(given, AssetRequest) else stored_request(record) if not given else None
    intent = given if isinstance(given, str) and given.strip() else request_intent(request, record)
    overrides = dict(request.target_overrides) if request is not None else {}
    return targets_from_intent(str(intent), overrides, vocab, concept_of(record))


def asset_material(record: dict, targets: TargetBehaviour, vocab: MaterialVocab | None = None) -> str:
    """The vocabulary material of an asset's targets (the words of targets.intent, else the concept's material)."""
    concept = concept_of(record)
    return match_material(targets.intent, vocab, concept.default_material if concept else None, own_nouns(concept),
                          bool(concept and concept.hollow))


def own_nouns(concept: ConceptMatch | None) -> frozenset[str]:
    """The words of the nouns of the lexicon entry a concept names (none for a concept the lexicon lacks)."""
    entry = load_lexicon().entries.get(concept.concept) if concept is not None else None
    if entry is None or entry.material is None:
        return frozenset()
    return frozenset(w for noun in entry.nouns for w in noun.lower().split())
