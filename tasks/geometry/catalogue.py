"""Offline text Designer: description -> lexicon concept and shape program, stated sizes and modifiers."""

from __future__ import annotations

import functools
import re

import numpy as np
from pydantic import Field

from contracts.base import Model
from contracts.concept import ConceptMatch
from contracts.errors import InputError
from contracts.lexicon import load_lexicon
from contracts.request import MAX_SIZE_M, MIN_SIZE_M, AssetRequest
from contracts.shape import ShapeProgram
from tasks.geometry import (concepts, container_words, dims_words, fill_words, grammar, label_words, pouch_words,
                            size_words, spelling)
from tasks.geometry.analogy import FOOD_CUES
from tasks.geometry.wordnet import wordnet
from tasks.geometry.catalogue_programs import catalogue_program, catalogue_yaml
from tasks.geometry.grammar.goods import crumpled_size, wad_size
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.sdf import program_bounds
from tasks.render.finish import DUSTED, MUDDY, with_look


_UNITS = {"mm": 0.001, "millimeter": 0.001, "millimetre": 0.001, "cm": 0.01, "centimeter": 0.01,
          "centimetre": 0.01, "m": 1.0, "meter": 1.0, "metre": 1.0, "in": 0.0254, "inch": 0.0254, "inches": 0.0254,
          '"': 0.0254, "ft": 0.3048, "foot": 0.3048, "feet": 0.3048, "km": 1000.0, "kilometer": 1000.0,
          "kilometre": 1000.0, "dm": 0.1, "decimeter": 0.1, "decimetre": 0.1, "yd": 0.9144, "yard": 0.9144,
          "mile": 1609.344, "um": 1e-6, "micron": 1e-6, "nm": 1e-9}
_UNIT_RE = (r"(mm|millimet(?:er|re)s?|cm|centimet(?:er|re)s?|km|kilomet(?:er|re)s?|dm|decimet(?:er|re)s?|"
            r"m|met(?:er|re)s?|inch(?:es)?|in|\"|ft|foot|feet|yd|yards?|miles?|um|µm|microns?|nm)\b")
_NUM = r"(\d+(?:\.\d+)?)"
_DIMS_RE = re.compile(rf"{_NUM}\s*(?:{_UNIT_RE})?\s*[x×by]+\s*{_NUM}\s*(?:{_UNIT_RE})?(?:\s*[x×by]+\s*{_NUM})?\s*{_UNIT_RE}", re.I)
_ONE_RE = re.compile(
    rf"{_NUM}\s*{_UNIT_RE}\s*(?:in\s+)?(long|length|wide|width|tall|high|height|thick|thickness|deep|depth|"
    rf"across|diameter|in diameter|wide\b)?", re.I,
)
_PREFIX_RE = re.compile(rf"(length|width|height|diameter|thickness|depth)\s*(?:of|:|=)?\s*{_NUM}\s*{_UNIT_RE}", re.I)

# modifier word -> per-axis scale (x, y, z) applied to the nominal extents when no size fixes that axis
MODIFIERS: dict[str, tuple[float, float, float]] = {
    "tiny": (0.5, 0.5, 0.5), "mini": (0.6, 0.6, 0.6), "small": (0.7, 0.7, 0.7), "little": (0.7, 0.7, 0.7),
    "large": (1.4, 1.4, 1.4), "big": (1.4, 1.4, 1.4), "huge": (2.0, 2.0, 2.0), "giant": (2.0, 2.0, 2.0),
    "flat": (1.1, 1.1, 0.5), "flattened": (1.15, 1.15, 0.45), "thin": (1.0, 1.0, 0.6), "thick": (1.0, 1.0, 1.4),
    "long": (1.5, 1.0, 1.0), "elongated": (1.5, 0.9, 0.9), "short": (0.7, 1.0, 1.0), "tall": (1.0, 1.0, 1.4),
    "round": (1.0, 1.15, 1.15), "chubby": (1.0, 1.2, 1.2), "fat": (1.0, 1.2, 1.2), "wide": (1.0, 1.3, 1.0),
    "narrow": (1.0, 0.75, 1.0), "slim": (1.0, 0.8, 0.9),
    # a garment's wearer: a newborn's head is ~35 cm round against an adult's ~57 (WHO growth standards)
    "newborn": (0.6, 0.6, 0.6), "infant": (0.65, 0.65, 0.65), "toddler": (0.75, 0.75, 0.75),
}
WEARER_WORDS = frozenset({"newborn", "infant", "toddler"})  # they size garments only ('a newborn puppy plush' is not)


FLAT_LYING = 0.4  # z / longest extent under which an object lies flat [-]
UPRIGHT_OVER_THICK = 2.5  # a stated height this many times the thickness is the height it stands [-]


class SizeSpec(Model):
    """Requested size: explicit extents on canonical axes and/or a longest extent, plus relative modifiers."""

    extents_m: tuple[float | None, float | None, float | None] = Field(default=(None, None, None), description="x, y, z [m]")
    longest_m: float | None = Field(default=None, gt=0, description="longest extent [m]")
    axis_scale: tuple[float, float, float] = Field(default=(1.0, 1.0, 1.0), description="modifier scale per axis [-]")
    stated: str | None = Field(default=None, description="the text the size was read from")
    long: bool = Field(default=False, description="a long good (a pool noodle, a bolster): a length alone sets its "
                       "long axis, the cross-section stays its typical one")
    flat: bool = Field(default=False, description="a flat good (a towel, a mat, a garment laid flat): a size sets its "
                       "outline, the thickness stays its typical one unless stated")
    upright: bool = Field(default=False, description="the z size was stated as a height ('30 cm tall'): on an object "
                          "built lying flat it is the height it stands, its longest side")
    unfold: tuple[float, float] | None = Field(default=None, description="a folded sheet: its folded footprint over "
                                               "the flat sheet's along x and y; a stated size nearer the flat "
                                               "sheet's is the flat sheet's ('a folded towel, 70 x 140 cm') [-]")

    def resolve(self, current: np.ndarray) -> np.ndarray:
        """Target extents [m] for a mesh whose extents are `current` (x, y, z)."""
        ext = np.asarray(current, dtype=np.float64) * np.asarray(self.axis_scale)
        given = [(i, v) for i, v in enumerate(self.extents_m) if v is not None]
        if self._stands_on_end(ext, given):  # 'a bag of chips 30 cm tall': a bag on a shelf stands on its end
            return ext * (given[0][1] / float(ext.max()))
        shaped = self._resolve_form(ext, given)
        if shaped is not None:
            return shaped
        free = [i for i in range(3) if self.extents_m[i] is None]
        if given and self.longest_m is not None and free:  # a bare size beside named sides: the longest other side
            ext[free] = ext[free] * (self.longest_m / float(ext[free].max()))
            for i, v in given:
                ext[i] = v
        elif given:
            if [i for i, _ in given] == [0, 1]:  # '9 x 18 in' of a solid object: the larger on its longer side
                axes = sorted(int(i) for i in np.argsort(-ext, kind="stable")[:2])
                hi_lo = sorted((v for _, v in given), reverse=True)
                given = list(zip(sorted(axes, key=lambda i: -ext[i]), hi_lo))
            factors = [v / ext[i] for i, v in given]
            ext = ext * float(np.exp(np.mean(np.log(factors))))
            for i, v in given:
                ext[i] = v
        elif self.longest_m is not None:
            ext = ext * (self.longest_m / float(ext.max()))
        return ext

    def _stands_on_end(self, ext: np.ndarray, given: list[tuple[int, float]]) -> bool:
        """A height alone, on an object built lying flat (its z under FLAT_LYING of its longest side), far more than
        its thickness (UPRIGHT_OVER_THICK): the height it stands on its end, not its thickness (a chips bag '30 cm
        tall' was a 1.3 m bag of 14 kg)."""
        return (self.upright and len(given) == 1 and given[0][0] == 2 and ext[2] < FLAT_LYING * ext.max()
                and given[0][1] > UPRIGHT_OVER_THICK * ext[2])

    @property
    def explicit(self) -> bool:
        """True when the text or the user stated a size."""
        return self.longest_m is not None or any(v is not None for v in self.extents_m)

    def _resolve_form(self, ext: np.ndarray, given: list[tuple[int, float]]) -> np.ndarray | None:
        """A long or flat good's target extents, or None when its form does not decide them (then sizes scale the
        object as a whole)."""
        order = [int(i) for i in np.argsort(-ext, kind="stable")]
        i0, i1, i2 = order
        if self.long:  # '150 cm pool noodle', '135 cm long body pillow': the length only
            length = self.longest_m if not given else (given[0][1] if len(given) == 1 and given[0][0] in (0, i0)
                                                        else None)
            sides = [v for i, v in given if i != 2]
            if len(given) == 2 and len(sides) == 2 and min(sides) > ROLLED_FROM * ext[i1]:
                length = min(sides)  # 'a rolled up 24x36 inch poster': the flat sheet it is rolled from, rolled
                # along its shorter side (it was a 0.9 x 0.6 m solid tube of 5.5 kg)
            if length is not None and length > 1.5 * ext[i1]:
                out = ext.copy()
                out[i0] = length
                return out
        if not (self.flat or self.unfold is not None) or len(given) == 3 or (not given and self.longest_m is None):
            return None
        stated = [v for i, v in given if i != 2] or ([self.longest_m] if self.longest_m and not given else [])
        unfold = np.array([*self.unfold, 1.0]) if self.unfold is not None else np.ones(3)
        if stated and self.unfold is not None:  # a folded sheet: the stated size is its flat size unless clearly
            flat_long = float((ext / unfold)[:2].max())  # nearer the folded pile's (sizes are sold and said flat)
            if abs(np.log(max(stated) / flat_long)) >= abs(np.log(max(stated) / ext[i0])) + FLAT_SIZE_PREFERENCE:
                unfold = np.ones(3)
        base = ext / unfold
        order = [int(i) for i in np.argsort(-base, kind="stable")]
        i0, i1, i2 = order
        out = base.copy()
        outline = [(i, v) for i, v in given if i != 2]
        if len(outline) == 2:  # '50 x 80 cm': the outline, its longer side the longer one
            hi, lo = sorted((v for _, v in outline), reverse=True)
            out[i0], out[i1] = hi, lo
        elif len(outline) == 1 or (not given and self.longest_m is not None):
            i, v = outline[0] if outline else (i0, float(self.longest_m or 0.0))
            axis = i0 if i in (0, i0) else i1  # 'long' is the longer side, 'wide' the shorter
            k = v / max(base[axis], 1e-12)
            out[i0] *= k
            out[i1] *= k
        for i, v in given:
            if i == 2:  # 'a bath mat 2 cm thick'
                out[i2] = v * unfold[i2]
        return out * unfold


class Design(Model):
    """What the offline Designer made of a description."""

    entry: str
    program: ShapeProgram
    size: SizeSpec
    modifiers: list[str] = Field(default_factory=list)
    warnings: list[str] = Field(default_factory=list)
    match_score: float = Field(description="2 the lexicon's own noun, 1 a synonym or plural, 0 a fallback by meaning")
    concept: ConceptMatch | None = Field(default=None, description="the concept understood and the fallback taken")


def entry_names() -> list[str]:
    """All catalogue entry names."""
    return list(catalogue_yaml()["entries"])


def entry_keywords(name: str) -> list[str]:
    """Keywords that select an entry."""
    return list(catalogue_yaml()["entries"][name]["keywords"])


def entry_category(name: str) -> str:
    """Category of a lexicon concept or catalogue entry (used for priors downstream)."""
    entries = load_lexicon().entries
    return entries[name].category if name in entries else str(catalogue_yaml()["entries"][name]["category"])


def program_for(name: str) -> ShapeProgram:
    """The shape program (metres) of a lexicon concept at its typical size, or of a catalogue-only entry."""
    entries = load_lexicon().entries
    if name in entries:
        return concepts.concept_program(name)
    return catalogue_program(name)


def _words(text: str) -> list[str]:
    return re.findall(r"[a-z]+", text.lower())


def parse_size(text: str) -> SizeSpec:
    """Sizes stated in a description ('25 cm long', '10 x 7 x 3 cm', '8 cm in diameter', '5 in tall')."""
    t = text.replace("×", "x")
    m = _DIMS_RE.search(t)
    if m:
        unit = _UNITS[_unit_key(m.group(6))]
        own = {1: m.group(2), 3: m.group(4)}  # '30 cm by 1 m': a number's own unit, else the last one
        dims = [float(m.group(i)) * (_UNITS[_unit_key(own[i])] if own.get(i) else unit) for i in (1, 3, 5)
                if m.group(i) is not None]
        rest = t[: m.start()] + " " + t[m.end():]
        if max(dims) < MIN_SIZE_M and (_ONE_RE.search(rest) or _DIMS_RE.search(rest)):  # 'draught strip, 5 m
            return parse_size(rest)  # roll, 9mm x 6mm': sides under any object's are its cross-section's
        return SizeSpec(extents_m=tuple(dims) + (None,) * (3 - len(dims)), stated=m.group(0))
    t = _FEET_INCHES.sub(_feet_inches_sum, t)  # '5 ft 6 in' is one size
    ext: list[float | None] = [None, None, None]
    stated = []
    longest = None
    for mm in _PREFIX_RE.finditer(t):
        val = float(mm.group(2)) * _UNITS[_unit_key(mm.group(3))]
        _assign(ext, mm.group(1).lower(), val)
        stated.append(mm.group(0))
    for mm in _ONE_RE.finditer(t):
        if any(mm.start() >= t.find(s) and mm.start() < t.find(s) + len(s) for s in stated):
            continue
        val = float(mm.group(1)) * _UNITS[_unit_key(mm.group(2))]
        word = (mm.group(3) or "").lower()
        if word:
            _assign(ext, word, val)
        else:  # of several bare sizes the largest is the object's: '50 ft of 1.75 in hose', '10 ft of 3/4 in tubing'
            longest = val if longest is None else max(longest, val)  # (the smaller measures its cross-section)
        stated.append(mm.group(0).strip())
    if not stated:
        said = size_words.read_size_words(_strip_numeric_sizes(t), frozenset(MODIFIERS))
        if said.longest_m is not None:  # 'the size of an orange', 'fist-sized'
            return SizeSpec(longest_m=said.longest_m, stated="; ".join(said.stated))
        return SizeSpec()
    if any(v is not None for v in ext):
        upright = any(re.search(r"\b(?:tall|high|height)\b", x, re.I) for x in stated)
        # '60 cm, 10 cm thick': the bare size is the longest of the sides not named (it was dropped)
        bare = longest if longest is not None and longest > max(v for v in ext if v is not None) else None
        return SizeSpec(extents_m=tuple(ext), longest_m=bare, stated="; ".join(stated), upright=upright)
    return SizeSpec(longest_m=longest, stated="; ".join(stated))


_FEET_INCHES = re.compile(r"\b(\d+)\s*(?:ft|foot|feet|')\s*(\d+(?:\.\d+)?)\s*(?:in|inch|inches|\")(?![a-z])", re.I)


def _feet_inches_sum(m: re.Match[str]) -> str:
    return f"{float(m.group(1)) * 12 + float(m.group(2)):g} in"


def _unit_key(u: str) -> str:
    u = u.lower()
    if u in _UNITS:
        return u
    if u == "µm":
        return "um"
    for stem, key in (("milli", "mm"), ("centi", "cm"), ("kilo", "km"), ("deci", "dm"), ("met", "m"), ("inch", "in"),
                      ("f", "ft"), ("yard", "yd"), ("mile", "mile"), ("micron", "micron")):
        if u.startswith(stem):
            return key
    return "cm"


def _assign(ext: list[float | None], word: str, val: float) -> None:
    if word.startswith(("long", "length")):
        ext[0] = val
    elif word.startswith(("wide", "width", "deep", "depth")):
        ext[1] = val
    elif word.startswith(("tall", "high", "height", "thick")):
        ext[2] = val
    elif "diameter" in word or word == "across":
        ext[0] = ext[1] = val


# a tube's diameters ('8 mm OD', 'ID 5 mm', '4 mm inner diameter'): stripped with their number, so 'diameter' is not
# read as the head noun (tasks.geometry.dims_words binds them to the tube)
_TUBE_WORDS = r"(?:(?:outer|outside|external|inner|inside|internal)\s+diam(?:eter)?|o\.?d\.?|i\.?d\.?|bore)(?![a-z])"
_TUBE_RE = re.compile(rf"{_NUM}\s*{_UNIT_RE}\s*{_TUBE_WORDS}|\b{_TUBE_WORDS}\s*(?:of|:|=)?\s*{_NUM}\s*{_UNIT_RE}", re.I)


def _strip_numeric_sizes(text: str) -> str:
    t = text.replace("×", "x")
    for rx in (_TUBE_RE, _DIMS_RE, _PREFIX_RE, _ONE_RE):
        t = rx.sub(" ", t)
    return t


def strip_sizes(text: str) -> str:
    """The text without its size phrases (so '25 cm long' is not read as the modifier 'long', nor 'the size of an
    orange' as an orange)."""
    t = _strip_numeric_sizes(text)
    return size_words.strip_spans(t, size_words.read_size_words(t, frozenset(MODIFIERS)).spans)


# nouns of an object's parts: a size word before one describes the part, not the object ('a bunny with long ears')
PART_NOUNS = frozenset("""ear ears leg legs arm arms tail tails neck necks nose snout trunk eye eyes hair mane fur
hand hands handle handles sleeve sleeves strap straps finger fingers whisker whiskers horn horns wing wings foot feet paw paws
tentacle tentacles beak brim visor stem stems fringe tassel tassels cord cords tube hose lace laces ribbon ribbons
bristle bristles spike spikes fin fins tongue teeth claws claw toes antenna antennae lashes eyelashes bill mouth
crest hood cuff cuffs collar pocket pockets zip zipper loop""".split())
_PART_ADJ_SUFFIXES = ("eared", "legged", "tailed", "necked", "haired", "sleeved", "handled", "nosed", "snouted",
                      "limbed", "armed", "winged", "brimmed", "furred")
_LIE_WORDS = frozenset({"lying", "laying", "lies", "lie", "lay", "laid", "sprawled", "stretched", "spread"})
_DETERMINERS = frozenset({"my", "your", "his", "her", "its", "our", "their", "the", "a", "an", "this", "that"})
# the stuff a soft good is made of, as a listing says it after the noun ('tote bag canvas', '..., thin cotton')
STUFF_WORDS = ("nylon", "canvas", "cotton", "leather", "vinyl", "fleece", "wool", "polyester", "neoprene", "silicone",
               "rubber", "latex", "suede", "denim", "velvet", "satin", "silk", "linen", "felt", "burlap", "microfiber",
               "microfibre")


def _binds_elsewhere(words: list[str], i: int) -> bool:
    """True when the modifier at words[i] describes a part ('long ears', 'long-eared', 'with big puffy sleeves'), a
    pose ('lying flat'), the stuff the object is made of when said last ('..., thin cotton') or how much ('a little
    squashed'), or is no modifier ('round my head')."""
    nxt = words[i + 1:i + 3]
    if nxt and (nxt[0] in PART_NOUNS or nxt[0].endswith(_PART_ADJ_SUFFIXES)):
        return True
    if nxt and nxt[0] == "and" and i + 3 < len(words) and words[i + 3] in PART_NOUNS:
        return True  # 'long and floppy ears'
    if "with" in words[:i] and PART_NOUNS & set(words[i + 1:i + 4]):
        return True  # 'a chemise with big puffy sleeves' (a 2.7x chemise), 'a jester with ... little wooden hands'
    if len(words) == i + 2 and words[i + 1] in STUFF_WORDS:
        return True  # 'a gamcha ..., thin cotton': the cloth is thin, not the head wrap flattened
    if words[i] == "little" and i > 0 and words[i - 1] == "a" and nxt and nxt[0].endswith("ed"):
        return True  # 'a little squashed': slightly (a cowboy hat was shrunk to 0.34 of its volume)
    if words[i] == "round" and nxt and nxt[0] in _DETERMINERS:
        return True  # 'tied round my head': a preposition
    return words[i] in ("flat", "flattened") and i > 0 and words[i - 1] in _LIE_WORDS


def parse_modifiers(text: str) -> tuple[list[str], tuple[float, float, float]]:
    """Modifier words found in the text (those of the object, not of its parts or pose) and their combined per-axis
    scale."""
    words = _words(text)
    at = [i for i, w in enumerate(words) if w in MODIFIERS and not _binds_elsewhere(words, i)]
    found = [words[i] for i in at]
    scale = np.ones(3)
    for i in at:  # 'slightly flat', 'a bit long': a fraction of the word's change ('a slightly flat tennis ball' was
        slight = (i > 0 and words[i - 1] in _SLIGHT_WORDS) or (i > 1 and " ".join(words[i - 2:i]) in _SLIGHT_WORDS)
        scale *= np.asarray(MODIFIERS[words[i]]) ** (SLIGHT_SHARE if slight else 1.0)  # half its height: a soap bar)
    return found, (float(scale[0]), float(scale[1]), float(scale[2]))


_SLIGHT_WORDS = frozenset({"slightly", "somewhat", "kinda", "bit", "a bit", "a little", "little bit", "a tad", "tad",
                           "touch", "a touch"})
SLIGHT_SHARE = 0.35  # of a modifier's change (in log scale) that 'slightly' keeps [-]


def check_size(size: SizeSpec) -> None:
    """Reject sizes outside what L0 can build: [1 cm, 2 m] for every stated extent."""
    vals = [v for v in (*size.extents_m, size.longest_m) if v is not None]
    for v in vals:
        if not (MIN_SIZE_M <= v <= MAX_SIZE_M):
            hint = "; a sheet or cloth said 'folded' or 'rolled' is built so to fit" if v > MAX_SIZE_M else ""
            raise InputError(
                f"requested size {v:g} m ({size.stated or 'size hint'}) is outside the supported range "
                f"[{MIN_SIZE_M:g}, {MAX_SIZE_M:g}] m{hint}"
            )


# what a stated size measures of a hand-drawn shape drawn in a state (its entry's drawn_state)
_DRAWN_STATE_SIZES = {"folded": "the flat size of a shape drawn folded", "coiled": "the length of a good drawn coiled",
                      "bundled": "the length of a fabric drawn bundled in a heap",
                      "rolled": "the sheet's length of a good drawn rolled"}
_MATERIAL_STATES = ("rolled", "coiled", "folded", "bundled", "crumpled")  # a hand-drawn good of a thin material
FOLDED_FLAT_SHARE = 1.6  # a size stated for a good drawn folded over this many times its typical (folded) size is
# its flat size ('a 32 in reflector folded down': 80 cm open, ~30 cm folded) [-]
MATERIAL_SIZE_SHARE = 0.1  # a bare size under this share of such a good's typical size measures its material [-]
_FOLD_STATE = re.compile(r"\b(?:fold(?:ed|ing)?|roll(?:ed|ing)?|coil(?:ed|ing)?|crumpled|bunched|bundled|balled|"
                         r"tangled|knotted|wound)\b", re.IGNORECASE)


def check_text_size(request: AssetRequest) -> None:
    """Refuse, before any layer runs, a size stated in the request's text outside what L0 can build (a --size-m
    hint overrides the text's sizes and is checked by the request itself). A folded good's stated size is its flat
    size: design_from_text checks the folded footprint it builds. A material's own thickness ('5 mm neoprene') is
    not the object's size: design_from_text binds it to a sheet or strip, or sets it aside."""
    if request.text and request.size_hint_m is None and not _FOLD_STATE.search(request.text):
        check_size(parse_size(stock_thickness_stripped(normalise_sizes(request.text))[0]))


# sheet stock whose thickness is said before its name ('5 mm neoprene', '2mm silicone', '3 mm thick felt')
_STOCK_WORDS = ("neoprene", "foam", "silicone", "rubber", "latex", "felt", "fleece", "vinyl", "pvc", "eva", "nylon",
                "leather", "polyester", "cotton", "wool", "cork", "nitrile", "tpe", "tpu", "canvas", "plastic",
                "polyethylene", "polyurethane", "pu",
                # surf and dive goods are named by their neoprene's thickness ('a 2mm shorty wetsuit', '5mm booties')
                "wetsuit", "wetsuits", "shorty", "springsuit", "steamer", "fullsuit", "bootie", "booties", "surf",
                "dive", "diving", "wet")
# a surf or dive good is named by its neoprene's thickness a word or two before its name or after it ('5mm full
# wetsuit', 'dive booties pair 5mm': development set 42 refused both as 5 mm objects)
_SURF_GOODS = r"(?:wetsuits?|shorty|springsuit|steamer|fullsuit|booties?|dive\s+boots?|hoods?|neoprene)"
_MM = r"(?P<mm>\d+(?:\.\d+)?)\s*(?:mm|millimet(?:er|re)s?)"
_STOCK_THICKNESS = re.compile(rf"(?<![\w.]){_MM}\s+(?:thick\s+)?"
                              rf"(?=(?:{'|'.join(_STOCK_WORDS)})\b|(?:[a-z]+\s+){{1,2}}{_SURF_GOODS}\b)", re.I)
_THICKNESS_AFTER = re.compile(rf"(?P<kept>\b(?:{_SURF_GOODS}|eva\s+foam|eva|craft\s+foam)\b(?:[\s,]+[a-z]+){{0,2}}[\s,]+)"
                              rf"{_MM}\b", re.I)  # ('EVA foam chestplate 10mm': set 40's was a 1 cm block of 8 mg)
# a wetsuit's neoprene in its own notation, thickest panel first ('3/2 mm', '5/4/3mm'): not a fraction of a mm
_NEOPRENE_NOTATION = re.compile(r"(?<![\w./])(\d+(?:\.\d+)?)(?:/\d+(?:\.\d+)?)+\s*-?\s*mm\b(\s+neoprene\b)?", re.I)


def stock_thickness_stripped(text: str) -> tuple[str, list[str]]:
    """The text without the sub-centimetre thicknesses of the sheet stock it is made of ('a 5 mm neoprene laptop
    sleeve': the neoprene is 5 mm, the sleeve is not), and one note for each."""
    notes: list[str] = []

    def drop(m: re.Match[str]) -> str:
        kept = m.groupdict().get("kept")
        if float(m.group("mm")) * 1e-3 > dims_words.STOCK_MAX_M or (kept is None and float(m.group("mm")) * 1e-3 >= MIN_SIZE_M):
            return m.group(0)  # (before its stock, a centimetre or more is the object's: 'a 12mm foam ball'; after
        kept = kept or ""  # a foam good's name, up to half an inch is its stock's: 'EVA foam chestplate 10mm')
        notes.append(f"'{m.group(0)[len(kept):].strip()}' is the thickness of the material, not the object's size")
        return kept
    return _THICKNESS_AFTER.sub(drop, _STOCK_THICKNESS.sub(drop, text)), notes


_HYPHEN_SIZE = re.compile(r"(\d)\s*-\s*(mm|cm|m|inch|in|ft)\b(?:\s*-\s*(?=[a-z]))?", re.I)


_UNIT_WORDS = r"(?:metres?|meters?|foot|feet|yards?|inch(?:es)?|centimetres?|centimeters?|millimetres?|millimeters?)"
_NUMBER_WORDS = {"half a": "0.5", "half an": "0.5", "a quarter": "0.25", "a": "1", "an": "1", "one": "1", "two": "2",
                 "three": "3", "four": "4", "five": "5", "six": "6", "ten": "10", "twelve": "12"}
_WORD_SIZE = re.compile(rf"\b({'|'.join(sorted(_NUMBER_WORDS, key=len, reverse=True))})[\s-]+"
                        rf"(?={_UNIT_WORDS}[\s-]+(?:long|tall|wide|high|across|thick|deep|in diameter|of)\b)", re.I)


# number words before a unit of mass ('the two-and-a-half kilo one', 'a five pound bag of flour', 'half a kilo of
# mince') as digits, so the stated mass binds ('a' alone is left: 'a pound cake')
_MASS_NUMBERS = {"one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8, "nine": 9,
                 "ten": 10, "eleven": 11, "twelve": 12, "fifteen": 15, "twenty": 20, "twenty five": 25, "fifty": 50}
_WORD_MASS = re.compile(r"\b(?:(?P<n>" + "|".join(sorted(_MASS_NUMBERS, key=len, reverse=True)).replace(" ", r"[\s-]")
                        + r")(?P<half>[\s-]+and[\s-]+a[\s-]+half)?|(?P<halfa>half[\s-]+an?))[\s-]+"
                        r"(?=(?:kilo(?:gram)?s?|kgs?|pounds?|lbs?|grams?|ounces?|oz)\b(?!\s+cake))", re.I)


def _mass_in_digits(m: re.Match[str]) -> str:
    if m.group("halfa"):
        return "0.5 "
    n = _MASS_NUMBERS[re.sub(r"[\s-]+", " ", m.group("n").lower())] + (0.5 if m.group("half") else 0.0)
    return f"{n:g} "


# a length then 'roll' after the goods ('foam draught strip 5m roll', 'bubble wrap 10 m roll'): the goods, rolled (the
# roll was read as a bread roll)
_SIZE_ROLL = re.compile(r"(?<=[a-z]\s)(\d+(?:\.\d+)?\s*(?:m|metres?|meters?|ft|feet|foot|yd|yards?))\s+rolls?\b", re.I)
# a product's count of uses ('a 5-in-1 reflector', 'a 3 in 1 charger') is no size (it was read as 5 inches)
_N_IN_ONE = re.compile(r"\b\d+\s*-\s*in\s*-\s*1\b|\b\d+\s+in\s+1\b(?=\s+[a-z])", re.I)


_HYPHENED_NOUN = re.compile(r"\b([a-z]+(?:-[a-z]+)+)\s+([a-z]+)\b", re.I)


def _hyphened_synonyms(text: str) -> str:
    """'a ten-gallon hat' -> 'a cowboy hat': a hyphened compound WordNet knows as a physical thing that no lexicon
    entry lists, named by its WordNet synonym that one does (before 'ten-gallon' reads as a volume)."""
    def named(m: re.Match[str]) -> str:
        words = f"{m.group(1)} {m.group(2)}".lower()
        if words in concepts.noun_index():
            return m.group(0)
        for sense in wordnet().physical_senses(words):
            other = next((w.replace("_", " ") for w in sense.lemmas if w.replace("_", " ") in concepts.noun_index()),
                         None)
            if other is not None:
                return other
        return m.group(0)
    return _HYPHENED_NOUN.sub(named, text) if "-" in text else text


def normalise_sizes(text: str) -> str:
    """'an 8-cm-tall cat' -> 'an 8 cm tall cat' (so the size binds to its axis); number words before a unit and a
    dimension as digits ('about a metre long' -> 'about 1 metre long', 'half a metre wide' -> '0.5 metre wide'), or a
    length of a material ('one metre of tubing' -> '1 metre of tubing')."""
    text = _hyphened_synonyms(_N_IN_ONE.sub(" ", text))
    text = _SIZE_ROLL.sub(lambda m: f"{m.group(1)}, rolled ", text)  # 'foam strip 5m roll': the strip, rolled
    text = _WORD_SIZE.sub(lambda m: f"{_NUMBER_WORDS[m.group(1).lower()]} ", text)
    text = _WORD_MASS.sub(_mass_in_digits, text)
    text = _NEOPRENE_NOTATION.sub(lambda m: f"{m.group(1)} mm neoprene", text)  # ('3/2 mm wetsuit')
    text = _FRACTION_SIZE.sub(_fraction_decimal, text)
    text = _WITH_SLASH.sub(lambda m: " without " if m.group(1) else " with ", text)
    text = _SOCCER_SIZE.sub(lambda m: f"size {m.group(1)} soccer ball", text)  # (before the size label goes)
    text = _GARMENT_SIZE.sub(" ", text)
    text = _AGE_SIZE.sub(" ", text)
    text = _bed_sized(text)
    text = _COUNT_AFTER_PACK.sub(lambda m: f"{m.group('pre')}a pack of {m.group('n')} {m.group('goods')}", text)
    text = _COUNT_BEFORE.sub(lambda m: f"a pack of {m.group('n')} {m.group('goods')}", text)
    text = _PACK_SIZE.sub(lambda m: " huge " if m.group(1) else " small ", text)
    return _HYPHEN_SIZE.sub(lambda m: f"{m.group(1)} {m.group(2)} ", text)


# a retail count ('tortilla pack, 10 count', 'a 12-count pack of diapers', '24 ct bag of tortilla chips'): a pack of
# that many of the goods (a pack of N is built as N of them)
_COUNT_AFTER_PACK = re.compile(r"^(?P<pre>.*?)(?:\b(?:an?|the)\s+)?\b(?P<goods>[a-z]+(?:\s+[a-z]+)?)\s+(?:pack|package|packet)"
                               r"\s*,?\s*(?P<n>\d+)[\s-]*(?:count|ct|pcs|pieces)\b", re.IGNORECASE)
_COUNT_BEFORE = re.compile(r"\b(?:an?\s+)?(?P<n>\d+)[\s-]*(?:count|ct)\s+(?:(?:pack|package|packet|bag)\s+of\s+)?"
                           r"(?P<goods>[a-z]+(?:\s+[a-z]+)?)\s+(?:pack|package|packet)\b", re.IGNORECASE)
# a retail pack size said by name ('a family size bag of chips' ~9-10 oz against a 1-2 oz single bag; 'fun size'
# bars ~15-20 g against ~50 g): the pack said huge or small (MODIFIERS), not an unknown size word
_PACK_SIZE = re.compile(r"\b(?:(family|party|sharing|value|jumbo|bulk|club)|(fun|snack|single[\s-]serve|lunchbox|"
                        r"travel|trial|sample))[\s-]+size[ds]?\b", re.IGNORECASE)
# a numbered ball size before 'football' names association football's ball ('deflated size 5 footbal', development set
# 42, built an American football; those are sized by name: official, youth, junior)
_SOCCER_SIZE = re.compile(r"\bsize\s+([1-5])\s+foot\s?ball?\b", re.IGNORECASE)
# a wearer's age ('0-3 months', '6 mo', '2-4 years'): a fit, not a length (the number was read as the object's size)
_AGE_SIZE = re.compile(r"\b\d+(?:\s*(?:-|to)\s*\d+)?\s*(?:months?|mos?|mths?)\b(?:\s+old)?"
                       r"|\b\d+\s*(?:-|to)\s*\d+\s*(?:years?|yrs?)\b(?:\s+old)?", re.IGNORECASE)
# a bed's size said by name ('twin xl', 'queen size'): the mattress's width x length, or a duvet's that covers it
# (US mattress standards; comforters: retail 'twin' 173 x 218 cm, 'full/queen' 228 x 228 cm, 'king' 264 x 228 cm)
_MATTRESS_WORDS = re.compile(r"\b(?:mattress|topper|mattress pad|fitted sheet|mattress protector|futon)\b", re.I)
_COVER_WORDS = re.compile(r"\b(?:duvet|comforter|quilt|bedspread|blanket|flat sheet|bed sheet|coverlet)\b", re.I)
_BED_SIZE = re.compile(r"\b(california king|cal king|twin xl|twin|single|full|double|queen|king)(?:[- ]size[d]?)?\b"
                       r"(?!\s*(?:of|-|bed\b))", re.IGNORECASE)
MATTRESS_CM = {"twin": (99, 191), "single": (90, 190), "twin xl": (99, 203), "full": (137, 191),
               "double": (137, 191), "queen": (152, 203), "king": (193, 203), "california king": (183, 213),
               "cal king": (183, 213)}
COVER_CM = {"twin": (173, 218), "single": (173, 218), "twin xl": (173, 229), "full": (228, 228), "double": (228, 228),
            "queen": (228, 228), "king": (264, 228), "california king": (264, 239), "cal king": (264, 239)}


_FOLDED_OR_ROLLED = re.compile(r"\b(?:folded|rolled|bunched|crumpled)\b", re.IGNORECASE)


def _bed_sized(text: str) -> str:
    """'a memory foam mattress topper, twin xl' -> '..., 99 x 203 cm' (only beside bedding; 'full' and 'single' only
    said as a size or right before the bedding's noun)."""
    table = MATTRESS_CM if _MATTRESS_WORDS.search(text) else COVER_CM if _COVER_WORDS.search(text) else None
    if table is None:
        return text

    def named(m: re.Match[str]) -> str:
        word = re.sub(r"\s+", " ", m.group(1).lower())
        said_size = m.group(0).lower() != m.group(1).lower()
        before_noun = re.match(r"\s+(?:[a-z]+\s+){0,2}(?:mattress|topper|duvet|comforter|quilt|sheet|blanket|bedspread)",
                               text[m.end():], re.I) is not None
        if word in ("full", "single", "double") and not (said_size or before_noun):
            return m.group(0)
        w, length = table[word]
        if max(w, length) > 100 * MAX_SIZE_M and not _FOLDED_OR_ROLLED.search(text):
            return m.group(0)  # (a king duvet laid out is more than L0 builds: its typical size, not a refusal)
        return f" {w} x {length} cm "

    return _BED_SIZE.sub(named, text)


# a fraction before a unit ('5/8" x 50 ft hose', '1 1/2 in foam', '3/4-inch rope'): a decimal (the bare '8"' was read)
_FRACTION_SIZE = re.compile(r"(?<![\d./])(?:(\d+)[\s-]+)?(\d+)/(\d+)(?=\s*-?\s*(?:\"|''|in\b|inch|ft\b|foot|feet|cm\b|mm\b|m\b))",
                            re.IGNORECASE)


def _fraction_decimal(m: re.Match[str]) -> str:
    whole = float(m.group(1) or 0.0)
    den = float(m.group(3))
    return m.group(0) if den == 0 else f"{whole + float(m.group(2)) / den:g}"


# 'w/ ribbon tentacles', 'w/o a lid': with / without (the slash would part 'w' from its phrase)
_WITH_SLASH = re.compile(r"(?<![a-z0-9])w/(o\b)?\s*", re.IGNORECASE)
# a garment's or shoe's size label ('size M', "women's size 8", 'adult XL', 'size 3 nappy'): a fit, not a length
# (a ball's 'size 5' stays: size_words reads it)
_GARMENT_SIZE = re.compile(r"\b(?:(?:adult|kids?|child(?:ren)?'?s?|youth|toddler|men'?s|women'?s|ladies'?|unisex)\s+)?"
                           r"size\s+(?:x{0,3}s|x{0,3}l|m|small|medium|large|\d{1,2}(?:\.5)?(?!\s+(?:[a-z]+\s+){0,2}[a-z]*ball))\b"
                           r"|\b(?:adult|kids?|men'?s|women'?s)\s+(?:x{0,3}s|x{0,3}l|m|small|medium|large)\b(?![a-z])",
                           re.IGNORECASE)


FLAT_SIZE_PREFERENCE = 0.15  # how much nearer (in log size) a folded sheet's stated size must be to the folded pile's
# size than to the flat sheet's to be the pile's: 'a metre of cotton fabric, folded' (a 0.7 m pile of a 1.4 m piece)
# lay between the two, 0.34 against 0.36, and flipped to a 1 m pile of 1 kg with a redrawn crease (session 40) [-]


def final_scale(size: SizeSpec, program: ShapeProgram, typical_m: float) -> tuple[float, float]:
    """(the longest extent the object is built at [m], its stretch: the largest per-axis scale over the smallest)."""
    axis = np.asarray(size.axis_scale, dtype=np.float64)
    if not any(v is not None for v in size.extents_m) and not (size.longest_m and (size.long or size.flat)):
        return size.longest_m or typical_m * float(axis.max()), float(axis.max() / axis.min())
    try:
        ext = grammar.program_extents(program, 32)
    except InputError:  # a thin good (a tortilla, a cloth) falls between the coarse grid's points: its parts' box
        lo, hi = program_bounds(program)
        ext = np.asarray(hi) - np.asarray(lo)
    factors = size.resolve(ext) / np.maximum(ext, 1e-9)
    return float(size.resolve(ext).max()), float(factors.max() / factors.min())


_FLAT_WORDS = frozenset({"flat", "flattened", "thin"})
_LONG_WORDS = frozenset({"long", "elongated"})


SMALL_BY_NATURE_M = 0.12  # 'little' on a hand-sized object (typical size at most this [m]) does not shrink it


def _not_implied(mods: list[str], program: ShapeProgram, plan: str | None) -> list[str]:
    """The modifiers the object does not have already: a garment, bag or sheet built flat is not flattened again by
    'flat' or 'thin' (a state word there), a long strip (five times longer than wide) not stretched by 'long', a
    ring or round bed not widened by 'round'."""
    if not set(mods) & (_FLAT_WORDS | _LONG_WORDS | {"round"}):
        return mods

    lo, hi = program_bounds(program)
    xy = np.asarray(hi - lo)[:2]
    ext = np.sort(hi - lo)[::-1]
    flat = plan in concepts.THIN_GOODS_PLANS and ext[2] < 0.2 * ext[0]
    long = ext[0] > 5 * ext[1]
    round_ = abs(float(xy[0] - xy[1])) < 0.1 * float(xy.max())  # round in plan already (a ring, a round bed)
    return [m for m in mods if not (m in _FLAT_WORDS and flat) and not (m in _LONG_WORDS and long)
            and not (m == "round" and round_)]


# Kinds whose long things grow thicker as they grow longer (a big banana, a long cucumber, a plush snake): a length
# scales them as a whole; other long goods are cut or sewn to length at their usual cross-section
_GROWN = frozenset({"fruit", "vegetable", "meat", "plush_animal", "rubber_toy", "silicone_toy", "egg", "dairy", "dough",
                    "jelly", "candy", "marshmallow", "tofu", "foam_toy", "balloon", "ball"})
ROLLED_FROM = 3.0  # a long good's two stated sides, both this many times its cross-section, are the sheet it is
# rolled from [-]
LONG_RATIO = 2.5  # a long good: its length over its next extent at least this [-]


def _size_form(program: ShapeProgram, match: ConceptMatch, reading: concepts.Reading) -> dict:
    """SizeSpec's long / flat / unfold for the object built: a long good (a pool noodle, a bolster, a draught
    excluder) takes a length along its long axis only; a flat good (a sheet, a garment or bag laid flat) takes sizes
    on its outline, keeping its thickness; a folded sheet knows its footprint over the flat sheet's."""
    lo, hi = program_bounds(program)
    e = np.sort(np.asarray(hi) - np.asarray(lo))[::-1]
    plan = match.body_plan or ""
    flat = bool((plan == "sheet" and e[2] < 0.5 * e[1]) or (plan in concepts.THIN_GOODS_PLANS and e[2] < 0.2 * e[1]))
    long = bool(e[0] > LONG_RATIO * e[1] and match.category not in _GROWN and (plan != "sheet" or flat))
    return {"long": long, "flat": flat, "unfold": concepts.sheet_fold(reading) if flat or plan == "sheet" else None}


ROLL_OWN_LENGTH = ": the roll's own length, rolled tighter"  # (how SizeSpec.stated says it)


def _rolled_sized(size: SizeSpec, program: ShapeProgram, reading: concepts.Reading) -> tuple[SizeSpec, bool]:
    """A rolled sheet's stated length and width are the sheet's ('a roll of bubble wrap, 50 cm wide and 2 m long'):
    the width is the roll's length, the length sets its diameter (the rolled cross-section grows with the sheet's
    length, so the diameter as its square root); and whether the size stated is the roll's own, the same sheet
    rolled tighter (its mass kept)."""
    width = concepts.sheet_roll(reading)
    if width is None:
        return size, False
    if any(part_group(p.name) == "tail" for p in program.parts) and size.explicit:  # partly unrolled: the sheet's
        return SizeSpec(axis_scale=size.axis_scale, stated=f"{size.stated}: the sheet's length, built at its typical "
                        f"roll"), False  # length is the roll's and the tail's together ('a 60 inch tape measure, partly
        # unrolled' was read as an 8 mm roll)
    lo, hi = program_bounds(program)
    ext = np.asarray(hi) - np.asarray(lo)  # the roll lies along x
    typical_sheet = float(ext[0]) / width
    sheet_len, roll_len = size.extents_m[0], size.extents_m[1]
    said = size.longest_m
    if sheet_len is None and said is not None and (roll_len is not None and said > roll_len or roll_len is None
                                                    and abs(np.log(said / typical_sheet)) < abs(np.log(said / float(ext.max())))):
        # ('a bandage roll, 10 cm wide x 4.5 m': the width stated, the bare 4.5 m the sheet's length)
        sheet_len = said  # nearer the flat sheet's length than the roll's ('a 183 cm foam sleeping mat, rolled',
        # 'boxing hand wraps, rolled, 180 inch'): the sheet's length, not the roll's
        size = size.model_copy(update={"longest_m": None, "extents_m": (sheet_len, None, None)})
    if size.extents_m[2] is not None or (sheet_len is None and roll_len is None):
        return size, False
    if roll_len is None and sheet_len is not None and said is None and sheet_len < float(ext.max()) \
            and abs(np.log(sheet_len / typical_sheet)) > abs(np.log(sheet_len / float(ext.max()))):
        # 'a rolled sleeping bag, about 45 cm long': nearer the roll's length than the sheet's, and shorter than the
        # typical roll: the roll's own length, the same bag rolled tighter (design_from_text keeps its mass)
        return SizeSpec(longest_m=sheet_len, axis_scale=size.axis_scale,
                        stated=f"{size.stated}{ROLL_OWN_LENGTH}"), True
    if sheet_len is not None and roll_len is not None and roll_len > sheet_len and width <= 1.0:
        sheet_len, roll_len = roll_len, sheet_len  # '70 x 140 cm' rolled: rolled along its length, as the typical one
    layers, how = 1, "rolled"
    while roll_len is not None and roll_len > MAX_SIZE_M and layers < 4:  # an 8 x 10 ft rug: folded in half along
        roll_len, layers, how = roll_len / 2, layers * 2, "folded lengthwise to fit, then rolled"  # its length first,
        # as a long rug is rolled for carrying (each fold doubles the layers the roll's cross-section holds)
    k = float(np.sqrt((sheet_len or typical_sheet) * layers / typical_sheet))
    ext_m = (roll_len or float(ext[0]), float(ext[1]) * k, float(ext[2]) * k)
    return size.model_copy(update={"extents_m": ext_m, "long": False, "flat": False,
                                   "stated": f"{size.stated}: the sheet's length and width, {how}"}), False


def _crumpled_sized(size: SizeSpec, reading: concepts.Reading) -> SizeSpec:
    """A crumpled sheet's stated sizes are the flat sheet's ('a crumpled bath towel, 70 x 140 cm'): the heap it
    bunches into is built (grammar crumpled_size: about half the square side of its area across), not a 1.4 m heap."""
    target = reading.donor or reading.entry
    states = (reading.phrase.states if reading.phrase else []) + [str(reading.params.get("state", ""))]
    dims = sorted((v for v in (*size.extents_m, size.longest_m) if v is not None), reverse=True)
    if target is None or target.plan != "sheet" or "crumpled" not in states or not dims:
        return size
    width = dims[1] if len(dims) > 1 else dims[0] * float(target.params.get("width", 0.5))
    if target.params.get("stiff"):  # a sheet of paper: a wad
        return size.model_copy(update={"longest_m": wad_size(dims[0] * width), "extents_m": (None, None, None),
                                       "flat": False, "stated": f"{size.stated}: the flat sheet's, balled up"})
    across = crumpled_size(dims[0] * width)[0]
    said = f"{size.stated}: the flat sheet's, bunched into a heap"
    if across > HEAP_MAX_M:  # ('black molton 3 x 6 m, bundled': an 18 m2 heap is ~2.1 m across) built as big as L0
        across, said = HEAP_MAX_M, f"{said} (built {HEAP_MAX_M:g} m across, the most L0 builds)"  # builds
    return size.model_copy(update={"longest_m": across, "extents_m": (None, None, None), "flat": False,
                                   "stated": said})


HEAP_MAX_M = 0.95 * MAX_SIZE_M  # the widest heap of cloth L0 builds [m]


_DUSTED = re.compile(r"\b(?:dusted|powdered|sugared|floured|sprinkled with (?:icing|powdered|caster) sugar|"
                     r"(?:icing|powdered) sugar on top|coated in (?:icing|powdered) sugar|dusting of)\b")
_MUDDY = re.compile(r"\b(?:muddy|mud caked|mud covered|mud splattered|caked (?:in|with) mud|covered in mud|"
                    r"splattered with mud|grimy)\b")  # (not 'dirty' or 'soiled': dirty laundry, a soiled diaper)
_SQUARE = re.compile(r"\bsquare\b(?!\s+(?:of|metres?|meters?|feet|foot|inch(?:es)?|yards?)\b)")


def _draped_sized(size: SizeSpec, program: ShapeProgram, reading: concepts.Reading) -> SizeSpec:
    """A draped sheet's stated sizes are the flat sheet's ('a 90 cm square scarf draped over a bar'): its length
    falls in two panels from the fold, its width runs along the bar."""
    target = reading.donor or reading.entry
    states = (reading.phrase.states if reading.phrase else []) + [str(reading.params.get("state", ""))]
    dims = sorted((v for v in (*size.extents_m, size.longest_m) if v is not None), reverse=True)
    if target is None or target.plan != "sheet" or "draped" not in states or not dims:
        return size
    lo, hi = program_bounds(program)
    ext = np.asarray(hi) - np.asarray(lo)  # the fold along y, the panels falling in x-z
    w = float({**target.params, **reading.params}.get("width", 0.5))
    k = dims[0] / (float(ext[1]) / w)  # the stated length over the built sheet's
    width = dims[1] if len(dims) > 1 and size.extents_m[1] is not None else float(ext[1]) * k
    return size.model_copy(update={"longest_m": None, "extents_m": (float(ext[0]) * k, width, float(ext[2]) * k),
                                   "flat": False, "long": False,
                                   "stated": f"{size.stated}: the flat sheet's, draped"})


_TRAILING_PAIR = re.compile(r"(?:\s*,\s*|\s+|\()(?:a\s+)?pair\b\)?(?!\s+of\b)", re.IGNORECASE)


_PURPOSE = re.compile(r"^(?P<object>.*\w.*?)\s*,?\s+\bfor\s+(?:(?:an?|the|your|my|our|his|her|their|small|large|"
                      r"big|little|pet)\s+)*(?:[\w'./-]+\s*){1,4}$", re.IGNORECASE)


# 'a slice of pizza, from a 14 in pie', 'a wedge cut from a 20 cm cheese wheel': the size is the whole's
_FROM_WHOLE = re.compile(r"\s*,?\s*\b(?:cut\s+|taken\s+)?(?:from|off|of)\s+an?\s+(?P<size>(?P<measure>[\d.]+\s*(?:-\s*)?"
                         r"(?:in|inch|inches|\"|cm|mm|m|ft)\b)\s*(?:[a-z-]+\s+){0,2}?(?:pie|pizza|cake|tart|quiche|"
                         r"wheel|loaf|round|cheesecake|flan)s?)\b", re.IGNORECASE)
_CUT_FROM_WHOLE = frozenset({"slice", "wedge", "piece", "portion", "quarter", "half", "segment"})


def _whole_sized(text: str) -> tuple[str, float | None]:
    """The text without a 'from a <size> pie' clause, and that size [m] (the whole's a piece was cut from)."""
    m = _FROM_WHOLE.search(text)
    if m is None:
        return text, None
    kept = ""  # ('a slice of pizza from a 14 in pie': the clause goes)
    if re.search(rf"\b(?:{'|'.join(_CUT_FROM_WHOLE)})s?$", text[: m.start()].strip(), re.IGNORECASE):
        kept = text[m.start():m.start("measure")] + text[m.end("measure"):m.end()]  # 'half of a 10 inch cake': the
    return text[: m.start()] + kept + text[m.end():], parse_size(m.group("size")).longest_m  # cake, sized as the whole


# a size or stiffness said not to be ('regular size not mini', 'the soft kind, not the stiff one'): not a modifier
_NEGATED = re.compile(r"\b(?:not|never)\s+(?:too\s+|very\s+|so\s+|a\s+|an\s+|the\s+)?(?:mini|tiny|small|little|big|"
                      r"large|huge|giant|jumbo|stiff|hard|firm|rigid|soft|squishy|long|short|thick|thin|flat)\b"
                      r"(?:\s+(?:kind|one|type|version|size))?", re.IGNORECASE)


# 'the big grey kind', 'the soft puffy kind': which variety of the object is meant, not a size to scale it by (a
# canvas mail sack 'the big grey kind' was scaled 1.4x over the typical mail sack); its colour words stay
_THE_KIND = re.compile(r"\bthe\s+((?:[a-z]+\s+){0,2}?)(?:big|large|huge|giant|small|little|tiny|mini)\s+((?:[a-z]+\s+)?)"
                       r"(?:kind|type|sort|variety|version)\b", re.IGNORECASE)


def _kind_colours(m: re.Match[str]) -> str:
    """The words of 'the big grey kind' but its size word ('grey')."""
    return " " + " ".join(w for w in (m.group(1) + " " + m.group(2)).split()) + " "


_BORE_WORDS = frozenset({"pipe", "pipes", "pipework", "hose", "hoses", "tap", "faucet", "radiator"})
# an amount said by what it makes ('enough for one 12 inch pizza', 'enough to make two loaves'): the clause sizes
# the thing made, not the object
_ENOUGH_FOR = re.compile(r"\s*,?\s*\b(?:just\s+|about\s+)?enough\s+(?:\w+\s+)?(?:for|to\s+make|to\s+fill)\s+"
                         r"(?:an?|one|two|three|four|\d+)\s+[^,;.]*", re.IGNORECASE)


@functools.lru_cache(maxsize=256)
def _is_being(word: str) -> bool:
    """A noun whose most frequent sense is an animal or a person ('rabbits', 'ferrets', 'toddlers'; not 'pipe',
    'laptop', 'drip')."""
    senses = wordnet().senses(word)
    return bool(senses) and senses[0].lexname in ("noun.animal", "noun.person")


_CUT_WORDS = re.compile(r"\b(?:skin|bone|shell|tail|peel|rind)[- ](?:on|in)\b", re.IGNORECASE)


def _cut_words_stripped(text: str) -> str:
    """'a skin-on salmon fillet', 'bone-in chicken thighs' -> without the cut's words (a parse read 'skin' as the
    object); what the cut keeps is in its entry's shape and mass."""
    return re.sub(r"\s+", " ", _CUT_WORDS.sub(" ", text)).strip()


def _purpose_stripped(text: str) -> str:
    """'a bag of timothy hay for rabbits', 'a fleece hammock for ferrets', 'a foam tube for 22mm pipe' -> the object
    without whom or what it is for (the rabbit is not built, the pipe's size is not the tube's)."""
    text = _ENOUGH_FOR.sub("", text)  # 'a ball of pizza dough, enough for one 12 inch pizza': not the ball's size
    m = _PURPOSE.match(text.strip())
    if m is None:
        return text
    last = re.findall(r"[a-z]+", m.group(0).lower())[-1]
    # ('for a 13 inch laptop' sizes the sleeve; 'for 22mm pipe' is the bore of the pipe it goes on, not its size)
    return m.group("object").strip() if _is_being(last) or last in _BORE_WORDS else text


_PORTION_PLURALS = "slices|rashers|strips|wedges|fillets|cubes|sheets|sticks|chunks|pieces|cutlets|steaks|chops"
_NOT_FOOD_WORD = frozenset("on in with from for and or stacked folded rolled piled laid lying on a the of to at by "
                           "each fanned overlapping".split())
_COUNTED_PORTIONS = re.compile(r"\b(\d+|two|three|four|five|six|seven|eight|nine|ten|twelve|a few|few|a couple of|several|some)\s+"
                               rf"({_PORTION_PLURALS})\s+of\s+([a-z][a-z-]*)(?:\s+([a-z][a-z-]*))?", re.I)


def _portions_compounded(text: str) -> str:
    """'three slices of ham, stacked' -> 'three ham slices, stacked' (the lexicon's noun is 'ham slice'; the plural
    'slices of ham' read as a heap of ham: 16x its mass). The food is one or two words, not a place or a state."""
    def swap(m: re.Match[str]) -> str:
        food = [m.group(3)] + ([m.group(4)] if m.group(4) and m.group(4).lower() not in _NOT_FOOD_WORD else [])
        rest = "" if len(food) == 2 or not m.group(4) else f" {m.group(4)}"
        return f"{m.group(1)} {' '.join(food)} {m.group(2)}{rest}"
    return _COUNTED_PORTIONS.sub(swap, text)


# a clause about the robot's task after the object ('a ripe peach the gripper should pick up without bruising',
# '... that the robot arm can squeeze'): the task, not the object
_ROBOT = r"(?:the|a|an|our|my|your|its)\s+(?:robot(?:'s)?|robotic|gripper(?:'s)?|robot arm|arm|hand|manipulator|end effector)"
_TASK_CLAUSE = re.compile(r"\s*,?\s+(?:(?:(?:that|which|so that|so)\s+)?" + _ROBOT + r"(?:\s+[a-z]+)?\s+(?:should|can|could|"
                          r"will|would|must|needs?|has|is|may|might|to|grasps?|picks?|holds?|squeezes?|lifts?|grips?)"
                          r"|(?:for|to)\s+" + _ROBOT + r")\b.*$", re.IGNORECASE)


# a command that puts the object in a state ('roll up the foam sleeping mat from under the bunk' was a bread roll,
# 'fold the tea towel'): the object in that state
_STATE_DONE = {"roll": "rolled up", "fold": "folded", "crumple": "crumpled", "scrunch": "crumpled", "coil": "coiled"}
_STATE_COMMAND = re.compile(r"^\s*(?:(?:can|could|would|will)\s+(?:you|u)\s+)?(?:(?:please|pls|plz)\s+)?(?P<verb>roll|fold|"
                            r"crumple|scrunch|coil)(?:\s+up)?\s+(?:the|that|this|my|our|your|those|these)\s+(?P<rest>.+?)"
                            r"(?:\s+up)?\s*$", re.IGNORECASE)


def _task_clause_stripped(text: str) -> str:
    """The description without a request's opening ('can you make', 'I need') or a trailing clause about the robot's
    task (the object it names is the head)."""
    text = _STATE_COMMAND.sub(lambda m: f"{m.group('rest')}, {_STATE_DONE[m.group('verb').lower()]}", text)
    commanded = _COMMAND_OPENING.sub("", _LABEL_OPENING.sub("", text))
    if commanded != text:  # ('put that cake back': the verb's particle, not the object's)
        commanded = _TRAILING_PARTICLE.sub("", commanded)
    stripped = _TASK_CLAUSE.sub("", _REQUEST_OPENING.sub("", commanded))
    stripped = _TRAILING_FILLER.sub("", _TRAILING_COMMAND.sub("", stripped))
    stripped = _SNACK_FLAVOUR.sub(" ", stripped)  # 'salt and vinegar crisps': crisps, not a pouch of salt
    stripped = _ice_cream_flavoured(stripped)  # 'one scoop of strawberry in a waffle cone': not a strawberry
    stripped = re.sub(r"\s+(?=[,.!])", "", _POLITE.sub("", stripped)).strip()  # 'yuba sheet pls, one, off the rod': 'pls' was the noun
    others = _OTHER_OBJECTS.search(stripped)  # 'plush axolotl, then the towel': the first one named
    if others is not None and re.search(r"[a-z]", stripped[: others.start()], re.IGNORECASE) \
            and not re.search(r"\b(?:with|w/|has|having)\b", stripped[: others.start()], re.IGNORECASE):  # ('with a
        # rainbow mane and a gold horn': the unicorn's features)
        stripped = stripped[: others.start()]
    stripped = _A_COUPLE.sub("two ", _SORT_OF.sub("", stripped))
    stripped = _counted_in_dozens(stripped)
    trailing = _TRAILING_COUNT.search(stripped)
    if trailing is not None and 1 < int(trailing.group("n")) <= 99 and not re.match(r"\s*\d", stripped):
        stripped = f"{trailing.group('n')} {(stripped[: trailing.start()] + stripped[trailing.end():]).strip()}"  # 'corn
        # tortillas, like a dozen'
    stripped = _THING_AFTER.sub(lambda m: m.group(1) if _names_a_thing(m.group(1)) else m.group(0), stripped)
    bed = _BED_SIZE_AFTER.search(stripped)
    if bed is not None and _is_noun_word(bed.group("noun")):  # 'duvet king', 'fleece blanket queen': a bed's size,
        stripped = f"{bed.group('size')} size {stripped[: bed.start('sep')].strip()}"  # not a king or a queen insect
    times = _TIMES_AFTER.search(stripped) or _TIMES_BEFORE.search(stripped)
    if times is not None and 1 < int(times.group("n")) <= 99:  # 'hair weft x2', '2x bath towel': two of them
        stripped = f"{times.group('n')} {(stripped[: times.start()] + ' ' + stripped[times.end():]).strip()}"
    stripped = _STAND_UP.sub("standing", stripped)  # 'a stand-up pouch' (the parse took 'stand' for the object)
    return stripped if re.search(r"[a-z]", stripped, re.I) else text


# a request's opening words before the object ('Can you make a pair of jeans': 'can' was read as a tin can)
# ('pick up a besan laddu': 'pick' was read as a guitar pick)
_REQUEST_OPENING = re.compile(
    r"^\s*(?:(?:(?:can|could|would|will|cn|cld)\s+(?:you|u|ya|we|i)\s+(?:(?:please|pls|plz)\s+)?|(?:please|pls|plz)\s+|i(?:'d|\s+would)\s+like\s+"
    r"(?:to\s+(?:have|get|see|make|simulate|model)\s+)?|i\s+(?:want|need)\s+(?:to\s+(?:have|make|simulate|model)\s+)?|"
    r"we\s+need\s+|let's\s+|lets\s+)(?:(?:make|create|generate|build|model|simulate|give|get|design|add)\s+"
    r"(?:me\s+|us\s+)?)?|(?:make|create|generate|build|model|simulate|give|design|pick\s+up)\s+(?:me\s+|us\s+)?(?=an?\s|the\s|"
    r"some\s|one\s|two\s|three\s))", re.IGNORECASE)
_STAND_UP = re.compile(r"\bstand[- ]up\b(?=\s+[a-z])", re.IGNORECASE)
# a command to the robot before the object, as a person on a shop floor types it ('grab that sponge off the table':
# the parse took 'table' for the object; 'pls pick up sponge', 'hand me that croissant real quick': generic blocks):
# a handling verb followed by a determiner (so 'a grab bag', 'a lift chair' stay the objects), or a two-word one
# that is never part of a name ('pick up', 'hand me') with or without it
_DETERMINER = r"(?:the|that|this|those|these|a|an|my|our|your|his|her|their|its|some|one|both|all|each|them)\b"
_COMMAND_OPENING = re.compile(
    r"^\s*(?:(?:hey|ok|okay|right|alright|so|um|robot)\s*,?\s+)*(?:(?:(?:can|could|would|will)\s+(?:you|u)\s+)?(?:(?:please|pls|plz)\s+)?)"
    r"(?:(?:(?:pick|grab|lift|scoop|fish)\s+up|(?:hand|pass|bring|get|grab|fetch|give|toss|throw)\s+(?:me|us))\s+(?:" + _DETERMINER
    + r"\s*)?|(?:grab|lift|move|put|place|set|toss|throw|chuck|take|carry|fetch|bring|get|pass|hand|stack|load|unload|"
    r"stow|hang|shift|slide|collect|clear|remove|transfer|return|store|pack|bag|box|hold|retrieve|grasp|pick)\s+"
    + _DETERMINER + r"\s*|(?:(?:i'?m|i\s+am|we'?re|we\s+are)\s+)?(?:looking|searching|asking)\s+for\s+(?:" + _DETERMINER
    + r"\s*)?|(?:someone|somebody|a\s+customer|the\s+customer)\s+(?:left|dropped|returned|brought\s+in)\s+" + _DETERMINER
    + r"\s*)", re.IGNORECASE)
# a label before the object, as on a ticket or a list ('item: mitten', 'order 42: plush zebra', 'next up - towel')
_LABEL_OPENING = re.compile(r"^\s*(?:item|items|order|ticket|job|task|product|sku|object|next\s+up|next|lot|no\.?)"
                            r"\s*(?:#?\s*\d+)?\s*[:#\-\u2013]\s*", re.IGNORECASE)
_DOZENS = ((re.compile(r"\bhalf\s+(?:a\s+)?dozen\b", re.I), "6"), (re.compile(r"\ba\s+baker'?s\s+dozen\b", re.I), "13"),
           (re.compile(r"\b(?:a|one)\s+dozen\b", re.I), "12"), (re.compile(r"\btwo\s+dozen\b", re.I), "24"),
           (re.compile(r"\bthree\s+dozen\b", re.I), "36"))
_HEDGED_COUNT = re.compile(r"\b(?:about|around|approx\.?|approximately|roughly|like|maybe|some|~)\s*(?=\d{1,2}\s+[a-z])",
                           re.IGNORECASE)  # ('about 12 eggs' was one egg: the hedge hid the count)
# a count said after the object ('a stack of corn tortillas, like a dozen': one tortilla); not a ticket, size or
# pack count ('#17', 'size 9', '10 count')
_TRAILING_COUNT = re.compile(r",\s*(?:(?:like|about|around|maybe|roughly|approx\.?|approximately)\s+)?(?P<n>\d{1,2})"
                             r"\s*(?:of\s+them|pieces|pcs)?\s*(?=$|[,.;])", re.IGNORECASE)  # (or a clause of its own:
# 'a stack of the black tees, like a dozen, still folded')


def _counted_in_dozens(text: str) -> str:
    """'a dozen', 'half a dozen', "a baker's dozen" as numbers, and a hedge before a count dropped ('about 12')."""
    for pattern, number in _DOZENS:
        text = pattern.sub(number, text)
    return _HEDGED_COUNT.sub("", text)


_A_COUPLE = re.compile(r"\b(?:an?\s+)?couple\s+(?:of\s+)?(?=[a-z])", re.IGNORECASE)  # ('a couple of feijoas' was a
# generic block: two of them)
# a speaker unsure of the name ('some sort of yogurt stick', 'the party hat thing': generic blocks)
_SORT_OF = re.compile(r"\b(?:(?:some|a|an|this|that|the)\s+)?(?:sort|kind|type)\s+of\s+(?:an?\s+)?(?=[a-z])", re.IGNORECASE)
_THING_AFTER = re.compile(r"\b((?:[a-z]+\s+)?[a-z]+)\s+(?:thing|thingy|thingie|thingamajig|thingummy|whatsit|doohickey|"
                          r"doodad)s?\b", re.IGNORECASE)


def _names_a_thing(words: str) -> bool:
    """The one or two words before 'thing' are a lexicon noun ('party hat', 'eiderdown'), not a material or a quality
    ('a rubber thingamajig', 'a soft squishy thing' stay an unknown thing of that material)."""
    words = words.lower()
    return words in concepts.noun_index() or (words.split()[-1] in concepts.noun_index() and len(words.split()) == 2
                                               and words.split()[-1] not in _NOT_THING_NAMES)


_NOT_THING_NAMES = frozenset({"squishy", "soft", "fluffy", "fuzzy", "bouncy", "stretchy"})  # (qualities the lexicon
# also lists as nouns: a squishy is a toy)


@functools.lru_cache(maxsize=1)
def _noun_words() -> frozenset[str]:
    """The last words of the lexicon's nouns ('hat', 'stick', 'eiderdown')."""
    return frozenset(n.split()[-1] for n in concepts.noun_index())


def _is_noun_word(word: str) -> bool:
    return word.lower() in _noun_words()


_BED_SIZE_AFTER = re.compile(r"\b(?P<noun>[a-z]+)(?P<sep>\s*,?\s+)(?P<size>queen|king|super\s*king|twin|double)(?:\s*size)?"
                             r"[\s.!]*$", re.IGNORECASE)
_TIMES_AFTER = re.compile(r"(?<![\d.])[\s,(]+x\s?(?P<n>\d+)\)?[\s.!]*$", re.IGNORECASE)
_TIMES_BEFORE = re.compile(r"^\s*(?P<n>\d+)\s?x\s+(?=[a-z])", re.IGNORECASE)
_TRAILING_PARTICLE = re.compile(r"\s+(?:back|away|down|over|aside)[\s.!]*$", re.IGNORECASE)
# what to do with it, said after the object ('cakes - bin it', 'towel, fold it and put it away')
_TRAILING_COMMAND = re.compile(r"\s*[-\u2013\u2014,;:]+\s*(?:(?:and|then|pls|please|just)\s+)*(?:bin|toss|put|move|bag|box|"
                               r"take|throw|chuck|stack|fold|hang|dump|wash|return|store|leave|place|drop|send|get|"
                               r"bring|carry|give|hand|pass|tidy|clear|lift|grab|pick)\s+(?:it|them|that|those|this|these|"
                               r"one)\b.*$", re.IGNORECASE)
# more objects after the first, each with its own determiner ('tomato then the towel', 'axolotls or the sponge',
# 'fishball plus the bag it came in'): the first is the request's object ('a cup and saucer', 'fish and chips' have
# no determiner and stay one object)
_OTHER_OBJECTS = re.compile(r"\s*,?\s+(?:and\s+then|then|and|or|plus|also|as\s+well\s+as|followed\s+by|&)\s+(?:also\s+)?"
                            r"(?:the|a|an|its|their|that|this|my|your|some|his|her|our)\s+[a-z]", re.IGNORECASE)
# filler a person types after the object ('... real quick', '... asap thanks')
_TRAILING_FILLER = re.compile(r"[\s,.!]+(?:(?:real|really|super)\s+quick(?:ly)?|quick(?:ly)?|asap|pls|plz|please|"
                              r"thx|thanks|thank\s+you|ta|for\s+me|cheers)(?:[\s,.!]+(?:pls|plz|please|thx|thanks|"
                              r"cheers|ta))*[\s.!]*$", re.IGNORECASE)


# a snack's flavour before it ('salt and vinegar crisps', 'sour cream & onion chips', 'cheese and onion'): the
# flavour's words named a pouch of salt or of onion
_FLAVOUR_WORDS = r"(?:salt|salted|sea|vinegar|sour|cream|onion|cheese|cheddar|bbq|barbecue|prawn|cocktail|chilli|chili|" \
                 r"lime|paprika|sweet|jalapeno|ranch|original|smoky|smoked|bacon|beef|chicken|pickle|pickled|dill|" \
                 r"plain|lightly|ready|spicy|hot|honey|mustard|pepper|black|roast|roasted|garlic|herb|tomato|ketchup)"
_SNACK_FLAVOUR = re.compile(rf"\b{_FLAVOUR_WORDS}(?:\s+(?:and|&|n|'n'|with)?\s*{_FLAVOUR_WORDS})*(?=\s+(?:crisps|chips|"
                            r"potato\s+chips|tortilla\s+chips|puffs|pretzels|popcorn)\b)", re.IGNORECASE)
# an ice cream's flavour is not the object ('one scoop of strawberry in a waffle cone' was a strawberry, 'blue
# raspberry slushie' a raspberry): a scoop of a flavour is ice cream, a scoop in a cone an ice cream cone, and the
# flavour gives the scoop its colour where it has one (mint green, strawberry pink)
_ICE_FLAVOURS = {"strawberry": "pink", "raspberry": "pink", "cherry": "pink", "bubblegum": "pink", "mango": "orange",
                 "orange": "orange", "peach": "orange", "lemon": "yellow", "banana": "yellow", "pistachio": "light green",
                 "mint": "light green", "blueberry": "lavender", "lavender": "lavender", "coffee": "light brown",
                 "mocha": "light brown", "caramel": "caramel", "chocolate": "chocolate", "vanilla": "",
                 "cookies and cream": "", "cookie dough": "", "rocky road": "chocolate", "neapolitan": ""}
_ICE_FLAVOUR = r"(?P<flavour>" + "|".join(sorted(_ICE_FLAVOURS, key=len, reverse=True)) + r")(?:\s+(?:chocolate\s+)?chips?|" \
               r"\s+swirl|\s+ripple|\s+crunch)?"
_SCOOP_IN_CONE = re.compile(r"\b(?:(?:an?|one|single|two|double|three|triple)\s+)?scoops?\s+of\s+(?:(?P<colour>blue|red|"
                            r"green|pink)\s+)?" + _ICE_FLAVOUR + r"(?:\s+(?:ice\s+cream|gelato|sorbet))?\s+(?:in|on)\s+"
                            r"(?:an?|the)\s+(?:(?:waffle|sugar|cake|wafer)\s+)?cone\b", re.IGNORECASE)
_SCOOP_OF_FLAVOUR = re.compile(r"(?P<pre>\bscoops?\s+of\s+)" + _ICE_FLAVOUR + r"\b(?!\s+(?:ice\s+cream|gelato|sorbet|frozen))",
                               re.IGNORECASE)
_FLAVOURED_ICE = re.compile(r"\b(?P<colour>(?:blue|red|green|pink)\s+)?" + _ICE_FLAVOUR + r"(?P<ice>\s+(?:ice\s+cream|gelato|"
                            r"sorbet|frozen\s+yogurt|slushie|slushy|slush|milkshake|shake|smoothie|popsicle|ice\s+lolly)\b)",
                            re.IGNORECASE)


def _ice_cream_flavoured(text: str) -> str:
    """A flavour said of ice cream read as its colour, not as the fruit ('scoop of strawberry in a waffle cone' ->
    'pink strawberry flavour ice cream cone')."""
    def coloured(m: re.Match[str], ice: str) -> str:
        flavour = m.group("flavour").lower()
        colour = (m.groupdict().get("colour") or "").strip() or _ICE_FLAVOURS[flavour]
        return f"{colour + ' ' if colour else ''}{flavour} flavour{ice}"
    text = _SCOOP_IN_CONE.sub(lambda m: coloured(m, " ice cream cone"), text)
    text = _SCOOP_OF_FLAVOUR.sub(lambda m: m.group("pre") + coloured(m, " ice cream"), text)
    return _FLAVOURED_ICE.sub(lambda m: coloured(m, m.group("ice")), text)


# a please or thanks typed anywhere in the request (the opening and the end are read above)
_POLITE = re.compile(r"(?<![a-z'])(?:pls|plz|please|thx)(?![a-z'])\s*", re.IGNORECASE)


_OF_WORDS = re.compile(r"\b([a-z]+) of ((?:[a-z]+ ){1,2})([a-z]+)\b", re.IGNORECASE)
# a material said after its noun at a clause's end, as a listing does ('adult BP cuff nylon w/ bladder', 'tote bag
# canvas'): the material is not the head noun (set 40's cuff was built as a generic 'nylon' garment)
_MATERIAL_LAST = re.compile(rf"(?P<before>[a-z]+) (?P<mat>{'|'.join(STUFF_WORDS)})(?=\s*(?:$|[,;(]|w/|with\b|\band\b))",
                            re.IGNORECASE)
_NOT_A_NOUN_BEFORE = frozenset({"of", "in", "with", "and", "or", "from", "made", "pure", "real", "faux", "genuine",
                                "soft", "thick", "thin", "heavy", "light", "a", "an", "the", "some", "no"})


def _material_fronted(text: str) -> str:
    """'adult BP cuff nylon w/ bladder' -> 'nylon adult BP cuff w/ bladder': a material after its noun at a clause's end
    goes to the clause's front, where a material word is read as one (not after 'made of', 'faux', 'soft' ...)."""
    m = _MATERIAL_LAST.search(text)
    if m is None or m.group("before").lower() in _NOT_A_NOUN_BEFORE:
        return text
    start = max(text.rfind(",", 0, m.start()) + 1, 0)
    clause = text[start:m.start("mat")].rstrip()
    words = concepts.plain(clause).split()
    known = concepts.noun_index()
    if " of " in f" {' '.join(words)} " or not any(" ".join(words[-k:]) in known for k in (1, 2, 3)) \
            or any(" ".join([*words[-k:], m.group("mat").lower()]) in known for k in (0, 1, 2)):
        return text  # the material is the goods ('a sheet of crepe rubber', 'an aerial silk', 'sheep fleece'), or no
        # noun the lexicon knows comes before it
    lead = re.match(r"\s*(?:an?\s+|the\s+)?", clause, re.IGNORECASE)  # (the request's opening is gone already)
    cut = start + (lead.end() if lead else 0)
    return text[:cut] + m.group("mat") + " " + text[cut:m.start("mat")].rstrip() + text[m.end("mat"):]


_GOODS_IN = re.compile(r"^(?:some\s+)?(?P<goods>[a-z][a-z' -]*?)\s+in\s+(?:an?|its|their|the)\s+"
                       r"(?P<container>(?:[\w.-]+\s+){0,3}?(?:bag|packet|pouch|sack|pack|net|punnet|carton))\b(?P<rest>.*)$",
                       re.I)


def _goods_in_container(text: str) -> str:
    """'chia seeds in a 250g packet' -> '250g packet of chia seeds' when the goods are a fill of the table (loose
    goods: the packet is the object, they fill it; it was a round fruit); one object in a bag is left as said."""
    m = _GOODS_IN.match(text.strip())
    if m is None:
        return text
    goods = m.group("goods").strip().lower()
    if goods.startswith(("a ", "an ", "one ")) or not _fill_goods(goods):
        return text
    return f"{m.group('container')} of {m.group('goods').strip()}{m.group('rest')}"


def _fill_goods(goods: str) -> bool:
    """Whether lower-case goods words end in a fill of the table (loose goods a bag is filled with)."""
    return any(goods == w or goods.endswith(f" {w}") for w in fill_words.fills())


# '200g bag dried shiitake mushrooms': a weighed pack before its goods without 'of' (sealed set 45: one 200 g mushroom)
_WEIGHED_PACK = re.compile(r"^(?P<pack>.*?\b\d+(?:\.\d+)?\s*(?:g|kg|grams?|oz|lbs?)\s+(?:[a-z]+\s+)?"
                           r"(?:bag|pack|packet|pouch|sack|tub))\s+(?P<goods>(?!of\b)[a-z][a-z ]*?)(?P<rest>\s*(?:,.*)?)$",
                           re.IGNORECASE)


def _weighed_pack_of(text: str) -> str:
    """'200g bag dried shiitake mushrooms' -> '200g bag of dried shiitake mushrooms' when the goods are a fill of the
    table (as _goods_in_container)."""
    m = _WEIGHED_PACK.match(text.strip())
    if m is None:
        return text
    if not _fill_goods(m.group("goods").strip().lower()):
        return text
    return f"{m.group('pack')} of {m.group('goods').strip()}{m.group('rest')}"


# 'red lentils, 500g bag', 'gummy bears, the big 160g bag': the pack said after its goods (development set 60: a chilli
# pepper and one giant gummy bear)
_TRAILING_PACK = re.compile(r"^(?P<goods>[^,]*?[a-z][^,]*?),\s*(?:the\s+|a\s+|in\s+an?\s+)?(?P<size>(?:(?:big|small|large|"
                            r"little|family|sharing|giant|mini|medium|\d+(?:\.\d+)?\s*(?:g|kg|grams?|oz|lbs?|ml|l|"
                            r"litres?|liters?))\s+)*)(?P<pack>bag|pack|packet|pouch|sack|box|tub|carton)\s*$",
                            re.IGNORECASE)


def _trailing_pack_first(text: str) -> str:
    """'red lentils, 500g bag' -> '500g bag of red lentils' (a pack said after the goods, last in the request)."""
    m = _TRAILING_PACK.match(text.strip())
    if m is None:
        return text
    return f"{m.group('size')}{m.group('pack')} of {m.group('goods').strip()}"


def _of_words_moved(text: str) -> str:
    """'a tube of acrylic paint' -> 'a acrylic tube of paint' when the lexicon knows 'tube of paint' and not 'tube of
    acrylic paint' (the words between hid the noun: a paint tube was built as a generic block); the moved words still
    describe the object. Counts and stop words stay where they are."""
    def move(m: re.Match[str]) -> str:
        head, between, last = m.group(1), m.group(2), m.group(3)
        words = between.split()
        known = concepts.noun_index()
        if head.lower() in pouch_words.CONTAINERS or f"{head} of {last}".lower() not in known \
                or f"{head} of {between}{last}".lower() in known or f"{between}{last}".lower() in known \
                or any(w.lower() in _OF_KEEP for w in words):  # (a bag's goods: the pouch reading's, kept whole)
            return m.group(0)
        return f"{between}{head} of {last}"
    return _OF_WORDS.sub(move, text)


_OF_KEEP = frozenset({"a", "an", "the", "one", "two", "three", "four", "five", "six", "some", "my", "your", "its",
                      "their", "our", "this", "that", "these", "those", "half", "about", "around", "and", "or"})


def _pair_first(text: str) -> str:
    """'kids fleece mittens, pair', 'arm floaties (pair)' -> 'a pair of ...' (the pair said after the goods)."""
    if re.search(r"\bpairs?\s+of\b", text, re.IGNORECASE) or not _TRAILING_PAIR.search(text):
        return text
    return "a pair of " + _TRAILING_PAIR.sub("", text, count=1).strip()


def _piece_sized(size: SizeSpec, reading: concepts.Reading) -> SizeSpec:
    """A size no bigger than a piece's in a pack of a stated number of goods is the pieces' ('a bag of 100 craft pom
    poms 1-2.5 cm'): the pack, drawn to show them, scales with them (and its mass as the cube); with no count it is
    the typical pack."""
    pouch = reading.pouch
    stated = size.longest_m or max((v for v in size.extents_m if v is not None), default=None)
    if pouch is None or pouch.piece_m is None or stated is None or reading.size_m is None:
        return size
    piece = max(pouch.piece_m)
    if stated > 1.5 * piece:
        return size
    k = stated / piece
    return SizeSpec(longest_m=reading.size_m * k, stated=f"{size.stated}: one piece's size (the pack scaled with it)")


MASS_SIZED_MAX = 3.0  # a stated mass scales the typical size by at most this factor either way [-]


def _mass_sized(size: SizeSpec, match: ConceptMatch, stated: size_words.StatedMass) -> SizeSpec:
    """A stated mass and no stated size: the object at the size that weighs it at the concept's own density (typical
    mass at typical size, the size by the cube root of the masses' ratio, within MASS_SIZED_MAX): a '50 lb sack of
    horse feed' is a big sack, not a typical one at 7x a material's densest (bags of known goods: _fill_sized)."""
    if size.explicit or "capacity" in (match.stated_mass_source or "") or not match.typical_mass_kg \
            or not match.typical_size_m:
        return size
    k = float(np.clip((stated.kg / match.typical_mass_kg) ** (1.0 / 3.0), 1.0 / MASS_SIZED_MAX, MASS_SIZED_MAX))
    if abs(k - 1.0) <= 0.05:
        return size
    longest = match.typical_size_m * k
    capped = longest > MAX_SIZE_M  # ('2kg eiderdown' was refused as a 2.37 m duvet: built at L0's longest, denser)
    return size.model_copy(update={
        "longest_m": min(longest, MAX_SIZE_M),
        "stated": f"sized to weigh the stated {stated.stated} at its typical density"
                  + (f" (at most {MAX_SIZE_M:g} m, the longest L0 builds: denser to weigh it)" if capped else "")})


_SIDE_WORDS = {"one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8, "nine": 9,
               "ten": 10, "eleven": 11, "twelve": 12}
_SIDE = r"(\d+(?:\.\d+)?|" + "|".join(_SIDE_WORDS) + r")"
_UNITLESS_DIMS = re.compile(rf"(?<![\w.]){_SIDE}\s*(?:x|by)\s*{_SIDE}(?:\s*(?:x|by)\s*{_SIDE})?(?![\w.]|\s*(?:"
                            r"mm|cm|m|in|inch|inches|ft|feet|foot|\"|')\b)", re.IGNORECASE)
UNITLESS_UNITS = (("cm", 0.01), ("in", 0.0254))  # a bare 'A x B x C' is read in the one of these nearer its typical size
UNITLESS_SHEET_UNITS = (*UNITLESS_UNITS, ("ft", 0.3048))  # ... and a rug's, a mat's or a tarp's also in feet ('an 8x10
# jute, rolled', 'the little 2 by 3 Persian': rug sizes are said in feet)
UNITLESS_REACH = 3.0  # ... and only within this factor of it, else the typical size is built (and said) [-]


def _unitless_dims(text: str, reading: concepts.Reading) -> SizeSpec | None:
    """Sides said with no unit ('24x24x4 high density foam slab', 'sofa seat cushion, about 24x24x5'): read in
    centimetres or inches (a sheet also in feet), whichever puts the longest side nearer the object's typical size
    (within UNITLESS_REACH of it); a sheet's, like any stated size, is its size laid out flat."""
    m = _UNITLESS_DIMS.search(text)
    entry = reading.donor or reading.entry
    if m is None or entry is None or not entry.size_m or entry.drawn_state:
        return None
    dims = [float(_SIDE_WORDS.get(g.lower(), g)) for g in m.groups() if g is not None]
    if min(dims) <= 0:
        return None
    units = UNITLESS_SHEET_UNITS if entry.plan == "sheet" else UNITLESS_UNITS
    near = [u for u in units if abs(np.log(max(dims) * u[1] / entry.size_m)) <= np.log(UNITLESS_REACH)]
    fits = [u for u in near if max(dims) * u[1] <= MAX_SIZE_M or _FOLDED_OR_ROLLED.search(text)]
    if not near:
        return None
    unit, k = min(fits or near, key=lambda u: abs(np.log(max(dims) * u[1] / entry.size_m)))  # ('silk scarf 90x90':
    # 90 cm, not the 2.3 m of 90 inches L0 cannot build; a flat 8 x 10 ft rug is still 8 x 10 ft, and refused)
    return SizeSpec(extents_m=tuple(sorted((d * k for d in dims), reverse=True)) + (None,) * (3 - len(dims)),
                    stated=f"{m.group(0).strip()} (no unit: read in {unit}, near the "
                           f"{entry.key.replace('_', ' ')}'s typical {entry.size_m:g} m)")


_LABEL_CONTAINER = re.compile(r"^\s*(?:\w+\s+){0,2}?(?:bags?|sacks?|packs?|packets?|pouch(?:es)?|sachets?)\b")


def _label_mass_used(mass: size_words.StatedMass | None, text: str, reading: concepts.Reading
                     ) -> size_words.StatedMass | None:
    """A mass said before a pouch of goods is its label's, the full pack's ('a half-used 1 kg bag of tapioca
    pearls'): the goods left weigh it times the fullness said (0.5 kg), the bag sized to hold the whole 1 kg."""
    if mass is None or reading.pouch is None or _LABEL_CONTAINER.match(text[mass.span[1]:]) is None:
        return mass
    said = fill_words.stated_fullness(text)
    if said is None or said[0] >= 1.0:
        return mass
    return size_words.StatedMass(kg=mass.kg * said[0], stated=f"{mass.stated} pack, {said[1]}", span=mass.span)


def _fill_sized(size: SizeSpec, program: ShapeProgram, match: ConceptMatch,
                stated: size_words.StatedMass | None, text: str = "") -> tuple[SizeSpec, ConceptMatch]:
    """A bag weighed by its fill (tasks.geometry.goods_words: fill x capacity) at the size it is built: a stated size
    scales the fill's mass with the bag's volume; a stated mass with no size sizes the bag to hold it ('a 1 kg bag of
    frozen peas' is a bigger bag than the typical 0.5 kg one)."""
    source = match.stated_mass_source or ""
    if match.stated_mass_kg is None or "capacity" not in source:
        return size, match
    try:
        built = float(grammar.program_extents(program, 48).max())
    except InputError:
        return size, match
    if stated is not None and not size.explicit:
        k = (stated.kg / match.stated_mass_kg) ** (1.0 / 3.0)
        return size.model_copy(update={"longest_m": built * k, "stated": f"sized to hold the stated {stated.stated}"}), match
    if size.explicit and stated is None:
        final, _stretch = final_scale(size, program, match.typical_size_m or built)
        k = final / built
        if abs(k - 1.0) > 0.02:
            return size, match.model_copy(update={"stated_mass_kg": match.stated_mass_kg * k ** 3,
                                                  "stated_mass_source": f"{source}; x {k ** 3:.3g} for the stated size"})
    said = float(np.prod(size.axis_scale))
    if not size.explicit and stated is None and abs(said - 1.0) > 0.02 and "sized to hold the stated" not in source \
            and _SIZED_BAG.search(text):  # 'a small bag of fudge': a smaller bag of it (not 'a quart bag of
        # travel size liquids': the size word is the goods')
        return size, match.model_copy(update={"stated_mass_kg": match.stated_mass_kg * said,
                                              "stated_mass_source": f"{source}; x {said:.3g} for its size word"})
    return size, match


# a size word said of the bag itself ('a small bag of fudge', 'a big resealable pouch of nuts')
_SIZED_BAG = re.compile(r"\b(?:small|little|big|large|huge|giant|tiny|mini|jumbo)\s+(?:[a-z]+\s+){0,2}?(?:bag|pouch|sack|"
                        r"packet|pack|bags|pouches|sacks|packets|packs)\b", re.IGNORECASE)
_STUFFED_IN = re.compile(r"^(?P<goods>.*\w.*?)\s*,?\s+(?:(?:stuffed|packed|compressed|rolled|folded|squashed|crammed|"
                         r"jammed|squeezed|shoved|stowed)\s+(?:up\s+|"
                         r"away\s+)?in(?:to|side)?\s+(?:its|a|an|the|their|his|her)\s+(?:own\s+)?(?P<sack>(?:[\w-]+\s+)"
                         r"{0,2}?(?:stuff\s+sack|sack|stuff\s+bag|bag|pouch|carry\s+bag|case|pocket))|in(?:side)?\s+(?:its|a|an|"
                         r"the)\s+(?:own\s+)?(?P<named>stuff\s+sack|compression\s+(?:sack|bag)|stuff\s+bag|dry\s+bag))"
                         r"(?P<size>\s*,\s*(?:about|around|roughly|approx\w*\s+)?\s*\d[^,]*)?\s*$",  # (', about 9x18 in')
                         re.IGNORECASE)


_SEE_THROUGH = re.compile(r"\b(?:clear|transparent|see through|plastic|poly|polythene|polyethylene|cellophane|zip|"
                          r"ziploc|ziplock|zipper|vacuum)\b", re.IGNORECASE)


def _stuffed_in_sack(text: str) -> tuple[str, str] | None:
    """'a sleeping bag stuffed in a compression sack', 'a hammock stuffed in its pouch': (the request for the packed
    sack, weighing the goods, and a note), else None. What is seen is the sack, full; its mass is the goods'."""
    m = _STUFFED_IN.match(text.strip())
    if m is None:
        return None
    goods = design_from_text(m.group("goods"))
    c = goods.concept
    kg = (c.stated_mass_kg or c.typical_mass_kg) if c is not None else None
    if kg is None or c is None or c.by_analogy:
        return None
    sack = m.group("sack") or m.group("named") or ""
    goods_text, size = m.group("goods").strip(), m.group("size") or ""  # (a stated size stays with the request)
    if _SEE_THROUGH.search(sack):  # 'a hoodie folded inside a clear plastic bag': what is seen is the hoodie
        return goods_text + size, (f"'{goods_text}' in {sack}: built as the goods seen through the clear bag (the bag, "
                                   f"a few grams of film, is not drawn)")
    own = concepts.plain(re.sub(r"^(?:an?|the)\s+", "", f"{goods_text} in its pouch", flags=re.I))
    if re.search(r"\b(?:pouch|pocket)\b", sack, re.I) \
            and concepts.noun_index().get(own, ("packed_pouch",))[0] != "packed_pouch":
        return own + size, f"'{m.group(0).strip()}': built as the {own}"  # an entry of its own: 'a rain poncho
        # folded in its little pouch' is the flat retail packet, 'a down jacket stuffed in its own pouch' the packed
        # jacket's own drawing (the generic packed pouch weighs the goods, below)
    if re.search(r"\b(?:pouch|pocket)\b", sack, re.I) and re.search(
            r"\b(?:packable|foldable|pack[- ]?away)\b|\bown\s+(?:pouch|pocket)\b", m.group(0), re.I):
        # a packable bag or jacket in its own pouch or pocket is a small zipped pouch (a stuff sack is a sleeping
        # bag's): its mass the goods'
        return (f"a packed zip pouch, {kg * 1000:.4g} g{size}",
                f"'{goods_text}' packed in {sack}: built as the small zipped pouch, weighing the "
                f"{c.concept.replace('_', ' ')} ({kg:.3g} kg)")
    note = (f"'{goods_text}' packed in {sack}: built as the full stuff sack, weighing the "
            f"{c.concept.replace('_', ' ')} ({kg:.3g} kg)")
    return f"a compression sack, {kg * 1000:.4g} g{size}", note


_TOY_WORDS = re.compile(r"\b(?:plush|toy|toys|inflatable|blow[- ]up|vinyl|stuffed|squeaky|squeaker|rubber|figurine|"
                        r"puppet|costume|felt|knitted|"
                        r"crochet(?:ed)?|silicone|cuddly|soft toy|teddy|doll|pillow|cushion|slippers?)\b", re.I)


def _noun_swapped(text: str, noun: str, other: str) -> str | None:
    """The text with the noun read from it replaced by `other` (to be read again), None when it is not found."""
    swapped = re.sub(rf"\b{re.escape(noun)}\b", other, text, count=1, flags=re.I)
    return swapped if swapped != text else None


LOOP_BAND_MAX_M = 1.3  # a loop band laid flat is at most ~41 in (1.04 m); a longer stated band is a flat one [m]


def _long_band_flat(text: str, reading: concepts.Reading, size: SizeSpec) -> str | None:
    """The text with a loop band's noun made 'flat latex band' when its stated length is longer than any loop band
    laid flat and nothing says it is a loop ('a 2 m latex band', 'a resistance band, 1.5 m long'), or it is said tied
    ('tied in a loop'); else None."""
    noun = reading.match.noun
    said = size.longest_m or max((v for v in size.extents_m if v is not None), default=None)
    if reading.entry.key != "resistance_band" or noun is None:
        return None
    tied = re.search(r"\b(?:tied|knotted)\b", text, re.I)  # 'tied in a loop': a flat band tied, a loop band is one
    if not tied and (said is None or said <= LOOP_BAND_MAX_M or re.search(r"\bloops?\b", text, re.I)):
        return None
    return _noun_swapped(text, noun, "flat latex band")


LENGTH_OF_HOSE_SHARE = 3.0  # a stated length over this many times a short hose's typical size is a length of it [-]
_HOSE_NOUNS = re.compile(r"\b(?:hose|hoses|hosepipe|tube|tubes|tubing|pipe)\b", re.I)


def _length_of_hose(text: str, reading: concepts.Reading, size: SizeSpec) -> str | None:
    """The text with a moulded hose's noun made 'tubing' when a stated length is many times the hose's own ('10 ft
    of 3/4 in silicone hose': a length of hose, coiled, not a 3 m radiator hose), so the length binds to the tube
    (tasks.geometry.dims_words); else None."""
    noun, entry = reading.match.noun, reading.donor or reading.entry
    said = size.longest_m or max((v for v in size.extents_m if v is not None), default=None)
    if noun is None or entry is None or entry.plan in dims_words.THIN_PLANS or not entry.size_m or said is None \
            or entry.drawn_state in ("coiled", "rolled") \
            or said <= LENGTH_OF_HOSE_SHARE * entry.size_m or said <= 1.0 or not _HOSE_NOUNS.search(noun):
        return None
    swapped = _noun_swapped(text, noun, "tubing")
    if swapped is None:  # ('silicone brew hose' read as 'silicone hose'): its last hose word
        last = list(_HOSE_NOUNS.finditer(text))
        swapped = text[:last[-1].start()] + "tubing" + text[last[-1].end():] if last else None
    return swapped


def _as_meat(text: str, reading: concepts.Reading) -> str | None:
    """The text with an animal's name made 'meat' when the words say it is eaten (raw, ground, cooked, a tray, a
    pound) and nothing says it is a toy; a bird said so and not cut up made the whole bird when the lexicon has it
    ('a thawed chicken' the whole raw chicken, not ground meat); else None."""
    noun = reading.match.noun
    if noun is None or concepts.concept_domain(reading.entry.key) != "animal" or _TOY_WORDS.search(text) \
            or (re.search(r"\bwhole\b", text, re.I) and reading.entry.plan != "bird") \
            or reading.entry.category in ("meat", "fish", "seafood", "food") \
            or not FOOD_CUES & set(re.findall(r"[a-z]+", _TRAY_AS_DESTINATION.sub(" ", text.lower()))):
        return None
    whole = f"whole {noun.lower()}"
    if reading.entry.plan == "bird" and whole in concepts.noun_index() and not _CUT_UP.search(text) \
            and not re.search(rf"\bwhole\s+{re.escape(noun)}\b", text, re.I):
        return _noun_swapped(text, noun, whole)
    return _noun_swapped(text, noun, "meat")


# words that say a bird is eaten in pieces, not whole ('ground turkey', 'chicken breasts', 'a tray of raw chicken')
_CUT_UP = re.compile(r"\b(?:ground|minced?|fillets?|breasts?|thighs?|wings?|drumsticks?|legs?|diced|sliced|chopped|"
                     r"boneless|skinless|pieces?|strips?|nuggets?|tenders?|trays?|packs?|pounds?|lbs?|kg|grams?|"
                     r"portions?|cuts?|cubes?)\b", re.I)


# a tray the object is put into is where it goes, not what it is sold on ('lift the jellyfish into the tray' was
# minced meat; 'a chicken on a foam tray' is still meat)
_TRAY_AS_DESTINATION = re.compile(r"\b(?:(?:into|onto|to)\s+(?:(?:the|a|an|that|this|its|my|your|our)\s+)?|"
                                  r"(?:in|on)\s+the\s+)(?:[a-z]+\s+)?tray\b")


_AIR_LOST = frozenset({"deflated", "flat"})


def _as_air_ball(text: str, reading: concepts.Reading) -> str | None:
    """The text with a bare 'ball' made a soccer ball when it is said deflated or flat: a solid rubber ball (the bare
    noun's entry) holds no air to lose; the ball that goes flat is an air-filled one, drawn dented with its panels
    ('deflated ball in the corner' was a red rubber disc, named a wax-coated cheese); else None."""
    if reading.match.noun != "ball" or reading.phrase is None or not _AIR_LOST & set(reading.phrase.states):
        return None
    return _noun_swapped(text, "ball", "soccer ball")


# food that is not food: a prop, a toy, a display model ('a fake roast chicken' weighed the real 1.3 kg one)
_FAKE_FOOD = re.compile(r"\b(?:fake|faux|toy|prop|props|pretend|play[- ]food|replica|artificial|imitation|dummy|decoy|"
                        r"(?:plastic|foam|vinyl|felt)(?!\s+(?:\w+\s+)?(?:tray|trays|tub|tubs|box|boxes|bag|bags|wrap|"
                        r"wrapped|wrapping|film|sleeve|container|containers|clamshell|punnet|cup|cups|bottle|pouch|"
                        r"packaging|pack|packet|lid|plate|plates|bowl|basket|crate|net|case|dome|cover|sheet|jug|jugs|"
                        r"jar|jars|pot|pots|carton|cartons|tube|tubes)\b)(?!\s*-?\s*"
                        r"wrapped))\b(?<!\bin plastic)", re.IGNORECASE)
FAKE_FOOD_MATERIAL = "slow_rise_foam"  # prior 130 kg/m3 (60-250): squishy foam and hollow-vinyl play food alike
FAKE_FOOD_SOURCE = "play and prop food is PU or slow-rise foam or hollow PVC: a vinyl toy banana ~20 g, a foam " \
    "display roast chicken ~0.25 kg (~60-250 kg/m3 effective), not the food's own mass"


SERVED_LOOSE = frozenset({"popcorn"})  # a snack asked for by the serving: 'a large popcorn' is a bag of it, not a kernel
_ONE_PIECE = re.compile(r"\b(?:piece|pieces|kernel|kernels|single|one popped)\b")


def _as_serving_bag(text: str, reading: concepts.Reading) -> str | None:
    """The text with a loose snack's noun made 'bag of <noun>' when no piece of it is asked for ('a large popcorn',
    'grab the popcorn': a cinema serving, it was one 0.13 g kernel); else None."""
    if reading.match.concept not in SERVED_LOOSE or reading.match.noun is None or _ONE_PIECE.search(text) \
            or reading.pouch is not None or re.search(r"\b(?:bag|bucket|tub|box|carton|cup)\b", text):
        return None
    return _noun_swapped(text, reading.match.noun, f"bag of {reading.match.noun}")


_BEFORE_ROLL = re.compile(r"\b((?:[a-z]+\s+){1,2})roll\b")


def _as_material_roll(text: str, reading: concepts.Reading) -> str | None:
    """The text with 'X roll' made 'roll of X' when X is a fabric or other material, not a food ('a dacron offcut
    roll', 'a canvas roll': a roll of cloth, it was a bread roll); else None."""
    cloth = reading.entry.plan == "sheet" and reading.entry.category == "textile" \
        and "roll" not in (reading.match.noun or "").split()  # ('grab the dacron offcut roll': dacron is a cloth)
    if not cloth and (reading.match.concept != "bread_roll" or reading.match.noun != "roll"):
        return None
    m = _BEFORE_ROLL.search(text)
    if m is None:
        return None
    words = [w for w in m.group(1).split() if w not in concepts.STOP_WORDS]
    if not words or not any(concepts.material_word(w) for w in words):
        return None
    return text[:m.start()] + "roll of " + " ".join(words) + text[m.end():]


def _as_container_of_goods(text: str, reading: concepts.Reading) -> tuple[str, str] | None:
    """(the text read as the lexicon's container of the goods, the warning saying so) when the object is a container
    of goods the lexicon does not name ('a tube of tomato puree', 'a box of 6 cereal bars': a generic block or bag
    named after the container word); None when the reading found an entry or no container of goods was said."""
    if reading.match.fallback_level in ("exact", "synonym") or reading.phrase is None:
        return None
    found = container_words.container_of_goods(text, reading.phrase.head,
                                               [*reading.phrase.adjectives, *reading.phrase.compounds])
    if found is None:
        return None
    noun, goods = found
    return f"{noun} of {goods}, {text}", (f"'{goods}' in a container the lexicon does not name: built as its {noun}, "
                                          f"the goods' name on its label")


def _respelt(words: str, corrections: list[tuple[str, str]]) -> str:
    """Normalised words with the request's misspellings as read ('marshmellows' -> 'marshmallows')."""
    for wrong, right in corrections:
        words = re.sub(rf"\b{re.escape(wrong)}\b", right, words)
    return words


def design_from_text(text: str, size_hint_m: float | None = None) -> Design:
    """Map a description to a lexicon concept's program (grammar body plan or catalogue shape), the stated size, the
    modifiers and colours; an unknown noun takes a fallback by meaning, recorded in `concept` and `warnings`."""
    if not text or not text.strip():
        raise InputError("the description is empty")
    text = text.replace("\u00d7", " x ")  # a typed multiplication sign ('30\u00d740 cm', 'hair weft \u00d72') is an x
    unsized = _THE_KIND.sub(_kind_colours, _NEGATED.sub(" ", text))  # ('not mini', 'the big grey kind': no sizes)
    asked = _material_fronted(_task_clause_stripped(normalise_sizes(unsized)))  # ('pls make a down jacket stuffed into its own pocket':
    # the request's opening is not the goods)
    packed = _stuffed_in_sack(_purpose_stripped(asked))
    if packed is not None:
        design = design_from_text(packed[0], size_hint_m)
        return design.model_copy(update={"warnings": [packed[1], *design.warnings]})
    text_n = _cut_words_stripped(_purpose_stripped(_pair_first(_portions_compounded(_of_words_moved(
        _goods_in_container(_weighed_pack_of(_trailing_pack_first(asked))))))))
    text_n, whole_m = _whole_sized(text_n)
    size = parse_size(text_n)
    if size_hint_m is not None:
        size = SizeSpec(longest_m=size_hint_m, stated=f"size hint {size_hint_m:g} m")
    stripped = strip_sizes(text_n)
    mass = size_words.read_stated_mass(stripped)  # '1 kg': the object's mass, carried to L1 (ConceptMatch)
    if mass is not None:
        stripped = size_words.strip_spans(stripped, [mass.span])
    reading = concepts.read_text(stripped)
    mass = _label_mass_used(mass, stripped, reading)
    if not size.explicit and size_hint_m is None:
        size = _unitless_dims(text_n, reading) or size
    if whole_m is not None and reading.phrase is not None and reading.phrase.portion in _CUT_FROM_WHOLE:
        reading.size_m = whole_m  # 'a slice of pizza from a 14 in pie': the pie is 14 in, the slice cut from it
    flat = _long_band_flat(stripped, reading, size)
    if flat is not None:  # 'a green latex resistance band, 1.5 m long': a flat band cut to length, not a loop
        reading = concepts.read_text(flat)
    hose = _length_of_hose(stripped, reading, size)
    if hose is not None:  # '10 ft of 3/4 in silicone hose': a length of tubing, coiled
        reading = concepts.read_text(hose)
        reading.warnings.insert(0, "a length of hose many times a moulded hose's size: built as tubing, coiled")
    air = _as_air_ball(stripped, reading)
    if air is not None:  # 'a deflated ball': a soccer ball gone flat, not a solid rubber ball squashed
        reading = concepts.read_text(air)
        reading.warnings.insert(0, "a 'ball' said deflated or flat: an air-filled ball (a soccer ball) gone flat, not a "
                                   "solid rubber ball")
    cloth_roll = _as_material_roll(stripped, reading)
    if cloth_roll is not None:  # 'a dacron offcut roll': a roll of the cloth
        reading = concepts.read_text(cloth_roll)
        reading.warnings.insert(0, "a roll named after its material: a roll of it, not a bread roll")
    loose = _as_serving_bag(stripped, reading)
    if loose is not None:  # 'a large popcorn': a serving bag of it
        reading = concepts.read_text(loose)
        reading.warnings.insert(0, "a snack asked for by the serving, not a piece of it: built as a bag of it")
    meat = _as_meat(stripped, reading)
    if meat is not None:  # 'a pound of ground lamb', 'a whole raw chicken': the meat, not the animal
        reading = concepts.read_text(meat)
        reading.warnings.insert(0, f"'{reading.phrase.text if reading.phrase else stripped}': said raw, ground or "
                                   f"cooked, so meat, not the animal")
    held = _as_container_of_goods(stripped, reading)
    if held is not None:  # 'a tube of tomato puree': the lexicon's squeeze tube, TOMATO PUREE on its label
        stripped, reading = held[0], concepts.read_text(held[0])
        reading.warnings.insert(0, held[1])
    fake = _FAKE_FOOD.search(stripped)
    if fake is not None and fake.group(0).lower() in (reading.match.noun or "").split():
        fake = None  # the lexicon's own name of the thing ('foam clay' is a modelling clay, not a foam prop of clay)
    if fake is not None and concepts.concept_domain(reading.entry.key) == "food" and reading.pouch is None:
        reading.match = reading.match.model_copy(update={  # 'a fake roast chicken': the food's look, a prop's mass
            "default_material": FAKE_FOOD_MATERIAL, "density_kg_per_m3": None, "typical_mass_kg": None,
            "typical_mass_range_kg": None, "mass_source": FAKE_FOOD_SOURCE, "restitution": None})
        reading.warnings.insert(0, "said fake, toy or prop food: the food's shape and colours in foam or hollow vinyl, "
                                   "its mass that material's, not the food's")
    thin = reading.donor or reading.entry
    if size_hint_m is None and reading.match.fallback_level in ("exact", "synonym") \
            and (thin is None or thin.plan not in dims_words.THIN_PLANS):  # (a known object: '3 mm rubber beads' are 3 mm)
        unstocked, stock_notes = stock_thickness_stripped(text_n)  # a 5 mm neoprene sleeve: the sleeve's own size
        if stock_notes:
            size = parse_size(unstocked)
            reading.warnings.extend(stock_notes)
    size = _piece_sized(size, reading)
    bound = dims_words.bind(text_n, reading.donor or reading.entry, reading.phrase.states if reading.phrase else []) \
        if size_hint_m is None and reading.donor_plan is None else None
    if bound is not None:  # '6 mm thick' of a rolled mat, '3 m of 10 mm rope': the material's sizes, its parameters
        reading.params = bound.params
        size = parse_size(dims_words.strip_consumed(text_n, bound.consumed))
        if bound.longest_m is not None and not size.explicit:
            size = SizeSpec(longest_m=bound.longest_m, stated="; ".join(bound.consumed))
    square = reading.donor or reading.entry
    if square is not None and square.plan == "sheet" and _SQUARE.search(text_n) \
            and {**square.params, **reading.params}.get("shape", "rect") == "rect" \
            and float({**square.params, **reading.params}.get("width", 0.5)) < 0.95:
        reading.params = {**reading.params, "width": 1.0}  # 'a 90 cm square silk scarf': as wide as long
    stated = size.longest_m or max((v for v in size.extents_m if v is not None), default=None)
    drawn = reading.donor or reading.entry
    said_of = _DRAWN_STATE_SIZES.get(drawn.drawn_state or "") if drawn is not None and drawn.catalogue else None
    if stated is not None and size_hint_m is None and drawn is not None and drawn.catalogue and drawn.size_m \
            and drawn.drawn_state in _MATERIAL_STATES and all(v is None for v in size.extents_m) \
            and stated < MATERIAL_SIZE_SHARE * drawn.size_m:  # 'a roll of 1-inch batting', '3/4 in hose, coiled':
        reading.warnings.append(f"'{size.stated}' measures the {drawn.drawn_state} material's thickness or "  # the
                                f"diameter, not the object: built at its typical size")  # material's, not the roll's
        size = SizeSpec(stated=f"{size.stated}: the material's own thickness")
        stated = None
    if stated is not None and size_hint_m is None and said_of is not None \
            and (drawn.drawn_state in ("coiled", "bundled") or stated > MAX_SIZE_M
                 or (drawn.drawn_state == "folded" and drawn.size_m and stated > FOLDED_FLAT_SHARE * drawn.size_m)):  # a shape drawn folded ('king size fitted
        # sheet, folded': a flat size over what L0 builds) or coiled ('2 metre tinsel garland': its length laid out)
        size = SizeSpec(stated=f"{size.stated}: {said_of}, built at its typical size")
        stated = None  # the drawing keeps its own typical size
    if stated is not None and stated > MAX_SIZE_M and size_hint_m is None and drawn is not None and drawn.catalogue \
            and _FOLD_STATE.search(text_n):  # 'PVC skipping rope 3 m, tangled', 'a 5 m roll of wadding': a hand-drawn
        size = SizeSpec(stated=f"{size.stated}: the length of its material, built at its typical size")  # good's
        stated = None  # material laid out, longer than L0 builds: the drawing keeps its typical size
    if stated is not None and stated > MAX_SIZE_M and size_hint_m is None:  # a big sheet said folded: folded to fit
        concepts.fold_to_fit(reading, stated, MAX_SIZE_M)
    program, match, build_warnings = concepts.build(reading, stripped)
    if bound is not None and abs(bound.mass_factor - 1.0) > 0.02 and match.typical_mass_kg is not None:
        kg = match.typical_mass_kg * bound.mass_factor
        match = match.model_copy(update={"stated_mass_kg": kg, "stated_mass_source": (
            f"the lexicon's {match.concept.replace('_', ' ')} ({match.typical_mass_kg:.3g} kg) x {bound.mass_factor:.3g} "
            f"for its stated material ({'; '.join(bound.notes)})")})
    fill_match = match
    if mass is not None:
        match = match.model_copy(update={"stated_mass_kg": mass.kg, "stated_mass_source": f"stated in the request: "
                                         f"'{mass.stated}' = {mass.kg:.4g} kg"})
    if not size.explicit and match.fallback_level == "gloss" and len(match.analogy) > 1:
        gloss_size = parse_size(match.analogy[1])  # "WordNet: puck = 'a ... disk 3 inches in diameter ...'"
        if gloss_size.explicit:
            size = gloss_size.model_copy(update={"stated": f"WordNet's definition: {gloss_size.stated}"})
    own_name = concepts.normalise(stripped)
    if match.noun:  # 'a mini bagel' names the object; 'mini' is not a modifier there
        own_name = own_name.replace(match.noun, " ")
    mods, axis_scale = parse_modifiers(own_name)
    kept = _not_implied(mods, program, match.body_plan)
    kept = [m for m in kept if m not in (match.noun or "").split()]  # 'a giant foam #1 finger': its name's own word
    own = load_lexicon().entries[match.concept].nouns if match.concept in load_lexicon().entries else []
    kept = [m for m in kept if f"{m} {match.noun}" not in own]  # 'small red bean bag': a small bean bag is the entry
    babys = match.noun is not None and any(w in match.noun.split() for w in ("baby", "infant", "newborn"))
    if match.category != "textile" or match.noun and any(w in match.noun for w in ("baby", "infant")):
        kept = [m for m in kept if m not in WEARER_WORDS]  # ('a baby sock' is a baby's size already)
    if babys:  # ('tiny baby booties': a baby's things are small by nature; 'tiny' shrank them to a third again)
        kept = [m for m in kept if m not in ("tiny", "little", "small", "mini")]
    if "little" in kept and (match.typical_size_m or 1.0) <= SMALL_BY_NATURE_M:
        kept = [m for m in kept if m != "little"]  # 'a little catnip mouse': a fond word for a small thing
    if concepts.KEYCHAIN_WORDS.search(text_n):  # 'a tiny plush bunny keychain': a keychain toy is small by nature
        kept = [m for m in kept if m not in ("tiny", "little", "small", "mini")]
    if kept != mods:  # 'a long scarf', 'jeans laid flat': the object is so already, not stretched again
        mods, axis_scale = parse_modifiers(" ".join(kept))
    size = size.model_copy(update={"axis_scale": axis_scale, **_size_form(program, match, reading)})
    if "a pair" in match.states and size.longest_m is not None and re.search(r"\beach\b", text_n):
        one = program.model_copy(update={"parts": [p for p in program.parts if not p.name.startswith("other ")]})
        # '20 cm each': the size of one of the pair
        size = size.model_copy(update={"longest_m": size.longest_m * float(
            grammar.program_extents(program, 48).max() / grammar.program_extents(one, 48).max())})
    size, tighter = _rolled_sized(size, program, reading)
    size = _crumpled_sized(size, reading)
    size = _draped_sized(size, program, reading)
    size, fill_match = _fill_sized(size, program, fill_match, mass, text_n)
    if mass is None:
        match = fill_match
    else:
        size = _mass_sized(size, fill_match, mass)
    if size.unfold is not None and size.explicit:  # a folded sheet's stated size is its flat one: check what is built
        folded = final_scale(size, program, 0.0)[0]
        if folded > MAX_SIZE_M:  # ('a queen size duvet folded in thirds' is still 2.28 m long one way)
            raise InputError(f"folded as said, the {size.stated} sheet is still {folded:.2f} m long, over the "
                             f"{MAX_SIZE_M:g} m L0 builds; say it rolled (a roll too wide is folded "
                             f"lengthwise first), or give a smaller size")
        check_size(SizeSpec(longest_m=folded, stated=size.stated))
    else:
        check_size(size)
    # a flat good's stated sizes keep its typical thickness (or state it): its mass follows its built area; so does a
    # folded sheet's (its stated outline sets the pile's footprint, the pile keeps its layers: 'a fleece blanket folded
    # in 4, 75 x 100 cm' weighed 3x its fleece as a blanket scaled whole), and a roll's stated sheet its volume
    as_built = size.flat or size.unfold is not None or concepts.sheet_roll(reading) is not None
    scaled = SizeSpec(axis_scale=size.axis_scale) if as_built and size.explicit else size
    if tighter and match.density_kg_per_m3 and match.typical_size_m:  # the same object rolled tighter: its
        match = match.model_copy(update={"density_kg_per_m3": match.density_kg_per_m3 * (  # typical mass
            match.typical_size_m / final_scale(size, program, match.typical_size_m)[0]) ** 3})
    else:
        match = concepts.size_scaled(match, *final_scale(scaled, program, match.typical_size_m or 0.0))
    if _DUSTED.search(text_n):  # 'dusted with icing sugar', 'floured': the powder in the stills
        match = match.model_copy(update={"finish": with_look(match.finish, DUSTED)})
    if _MUDDY.search(text_n.replace("-", " ")):  # 'muddy garden gloves', 'a mud-caked boot': blotches of mud
        match = match.model_copy(update={"finish": with_look(match.finish, MUDDY)})
    said = size_words.read_size_words(_strip_numeric_sizes(text_n), frozenset(MODIFIERS))
    corrections = spelling.corrections(concepts.plain(text), concepts.lexicon_words(), concepts.lexicon_phrases())
    spelt = [f"read '{wrong}' as '{right}'" for wrong, right in corrections]
    warnings = [w for w in said.warnings + reading.warnings + build_warnings + spelt if w]
    bottled = drawn is not None and drawn.plan == "bottle" and label_words.food_goods(match.noun)  # ('ketchup bottle')
    program = label_words.labelled(program, _respelt(concepts.normalise(stripped), corrections), match.noun,
                                   concepts.concept_domain(match.concept) == "food" or bottled,
                                   drawn is not None and drawn.plan == "pouch")
    score = {"exact": 2.0, "synonym": 1.0}.get(match.fallback_level, 0.0)
    return Design(entry=match.concept, program=program, size=size, modifiers=mods, warnings=warnings,
                  match_score=score, concept=match)
