"""Words that change how many of a good there are and what it holds: 'a pair of socks' (two, or one sock ball when
rolled), 'a zip bag half full of rice' (the fill's mass, tasks.geometry.fill_words), applied by concepts.build to
the object's body-plan parameters, its size and its mass."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from contracts.concept import ConceptMatch
from contracts.errors import InputError
from contracts.lexicon import LexiconEntry, load_lexicon
from contracts.shape import MAX_PARTS, Part, ShapeProgram
from tasks.geometry import fill_words, grammar
from tasks.geometry.grammar.goods import BAG_CAPACITY, PouchParams, net_capacity
from tasks.geometry.grammar.parts import ellipsoid, limb, part_group
from tasks.geometry.meshing import program_volume
from tasks.geometry.pouch_words import stated_volume_m3

FILLABLE_PLANS = frozenset({"bag", "pouch"})
PAIR_WORDS = frozenset({"pair"})
BUNCH_WORDS = frozenset({"bunch"})
PAIR_ITSELF_SHAPES = frozenset({"jeans_folded"})  # hand-drawn objects a pair of names once (its two legs)
BUNCH_PIECE_MAX_M = 0.025  # 'a bunch of' small round pieces (grapes, currants) is a cluster of them [m] (cherries
# on their long stems are a few, not a cluster)
BUNCH_LENGTH = 8.0  # a bunch of grapes lying on a table is ~8 grapes long (a 2.2 cm grape: ~18 cm) [-]
BUNCH_PACKING = 0.65  # the pieces' share of the cluster's envelope (random close packing of spheres ~0.64) [-]
BUNCHABLE_PLANS = frozenset({"round_fruit", "berry", "ball", "egg"})
BUNCH_MAX_PIECES = 54  # pieces drawn on the cluster's surface (a program holds at most 64 parts)
BUNCH_SEED = 7
BUNCH_CORES = 5  # ellipsoids along the cluster that fill in under its pieces
# how many parts a fold makes: 'folded in half' is one halving, 'in thirds' a letter fold, 'in quarters' two halvings
_FOLD_WORDS = re.compile(r"\b(?:in|into)\s+(half|halves|two|thirds|three|quarters|fourths|four|eighths)\b")
_FOLDS = {"half": (1, False), "halves": (1, False), "two": (1, False), "thirds": (1, True), "three": (1, True),
          "quarters": (2, False), "fourths": (2, False), "four": (2, False), "eighths": (3, False)}
# words for a quilted, down-filled good: a puffer jacket, a quilted vest, a down duvet
_PUFFY = re.compile(r"\b(?:puffy|puffer|puffa|quilted|padded|insulated|down[- ](?:filled|jacket|coat|vest|gilet|"
                    r"parka|winter|duvet|comforter|sleeping))\b")
PUFFER_BAFFLES = 7  # a puffer's baffles from hem to collar [-]
PUFFER_MASS = 1.3  # a down or padded garment over the same garment unpadded (retail: puffers 0.6-1.0 kg, fleece and
# rain jackets 0.35-0.9 kg) [-]

GENERIC_POUCH = "generic_pouch"  # the sealed pouch a container noun with goods is built as (tasks.geometry.concepts)


# 'a pack of 12 silicone muffin cups', 'a stack of cupcake liners': open cups sold nested one in another
_NESTED = re.compile(r"\b(?:pack|packet|stack|sleeve|set|box|tube|pile)s?\s+of\s+(?:(\d+|a dozen|dozen|two|three|four|"
                     r"five|six|seven|eight|nine|ten|twelve|twenty)\s+)?")
# a count said without a number, after an optional 'a' ('a few slices of ham' was one slice, a fifth of the six a
# deli folds) [-]
VAGUE_COUNTS = {"few": 3, "couple of": 2, "couple": 2, "several": 4}
_COUNT_WORDS = {"a dozen": 12, "dozen": 12, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7,
                "eight": 8, "nine": 9, "ten": 10, "twelve": 12, "twenty": 20, **VAGUE_COUNTS}
# a number that makes a compound adjective ('two-tone', 'three-layer', '2 ply'), not a count
_COMPOUND_AFTER = ("tone|toned|sided|layer|layered|ply|way|piece|seater|handed|legged|headed|colou?r|colou?red|step|"
                   "tier|tiered|wheeled|part|eyed|armed|pronged|lobed|fingered|toed|pointed|tailed")
# units and ages after a number: a size, a mass or a volume, not a count ('2 metre pool noodle', '5 pound bag')
_NOT_COUNTED = (r"(?:mm|cm|m|km|in|inch|inches|ft|foot|feet|yd|yards?|met(?:re|er)s?|\w*met(?:re|er)s?|lbs?|pounds?|"
                r"kg|kilos?|kilograms?|g|grams?|oz|ounces?|l|lit(?:re|er)s?|ml|\w*lit(?:re|er)s?|quarts?|qt|gallons?|"
                r"cups?|x|%|years?|months?|weeks?|days?|pack|pair|pairs|piece|pin|" + _COMPOUND_AFTER + r")\b")
# 'two overripe bananas', '3 tennis balls', 'a pack of 6 sponges', 'a 3-pack of scrub sponges': that many pieces
_COUNT = r"(\d+|" + "|".join(sorted(_COUNT_WORDS, key=len, reverse=True)) + r")"
_GROUP_COUNT = re.compile(r"\b(?:pack|packet|set|bundle|box|bag|net|tray|punnet|carton|pile|heap)\s+of\s+" + _COUNT
                          + r"(?:\s+(?!" + _NOT_COUNTED + r")|\s*$)|^\s*(?:a\s+)?" + _COUNT + r"\s+(?!" + _NOT_COUNTED
                          + r")|\b" + _COUNT + r"[- ]pack\b")  # ('rolls, a pile of 10': the count ends the text)
# an entry that is itself a pack of goods ('pack of baby wipes', 'bag of chips'): a count in its text is what it holds,
# unless the packs themselves are counted (an '80-pack of wipes' is one pack of 80)
# (a roll of toilet paper is one roll; 'a portion of onion rings, like 8 of them' is one portion of eight)
_PACK_NOUN = re.compile(r"^(?:pack|packet|bag|box|sack|pouch|tub|carton|portion|serving|pile|plate|basket)\s+of\s+")
_PACKS_COUNT = re.compile(r"\b" + _COUNT + r"\s+(?:[a-z]+\s+)?(?:packs|packets|bags|boxes|sacks|pouches|tubs|cartons|"
                          r"portions|servings|piles|plates|baskets)\b")
_COUNT_IN_NOUN = re.compile(r"\b" + _COUNT + r"\b")


def counted(text: str, match: ConceptMatch, target: LexiconEntry) -> int | None:
    """group_count, unless the count is the entry's own noun's ('two pack of kitchen roll' is the twin pack, drawn
    and weighed as two rolls: it weighed four) or is what a pack holds ('a pack of 80 baby wipes' is one pack: it was
    12 packs, 4.4 kg; 'a box of 6 chicken nuggets' one box; '3 packs of wipes' are three)."""
    if match.noun and _COUNT_IN_NOUN.search(match.noun):
        return None
    if is_pack(target) and not _PACKS_COUNT.search(text):
        return None
    return group_count(text)


def is_pack(target: LexiconEntry) -> bool:
    """An entry that is a pack of goods by its own nouns ('pack of baby wipes', 'bag of chips')."""
    return any(_PACK_NOUN.match(noun) for noun in target.nouns)


_HAND_COUNT = re.compile(r"\b(?:bunch|hand)\s+of\s+" + _COUNT + r"\b|^\s*(?:a\s+)?" + _COUNT + r"\s+(?:[a-z]+\s+)?bunch")
HAND_PLANS = frozenset({"elongated"})
PART_UNROLLED = re.compile(r"\b(?:partly|partially|part|half|a bit|a little|slightly|somewhat|loosely)\s+unrolled\b")
UNROLLED_TAIL = 1.5  # a partly unrolled roll's free end on the ground, in roll diameters [-]
_STRAW = re.compile(r"\b(?:with|and|plus)\s+(?:a\s+|its\s+|the\s+)?(?:\w+\s+)?straw\b|\bstraw\s+(?:in|stuck)\b")
# 'a stack of 5 pancakes', 'five stacked pancakes': the layers of a stacked disc (DiscParams.layers)
_STACK_COUNT = re.compile(r"\b(?:stack|pile|tower)\s+of\s+" + _COUNT + r"\b|^\s*(?:a\s+)?" + _COUNT
                          + r"\s+(?:[a-z]+\s+)?(?:stacked|piled)\b")
STACK_MAX = 8  # layers a stack is drawn with (DiscParams allows 12; a taller stack reads as a cylinder) [-]
HAND_DEFAULT = 5  # bananas in a retail hand (4-7) [-]
HAND_MAX = 5  # most a program's parts hold (with their stems' joins and crown) at 4 arcs each: 11 parts [-]
HAND_SEGMENTS = 5  # arcs each is swept in [-]
HAND_PITCH = 0.8  # their spacing / one's width: pressed together [-]
HAND_RISE = 0.35  # the middle one's lift / one's height [-]
GROUP_MAX = 12  # pieces drawn side by side at most [-]
GROUP_PER_ROW = 4  # pieces in a row before the next row [-]
GROUP_PITCH = 0.9  # the pieces' spacing / one piece's extent: touching, as the mesher keeps one body (as duplicated)
UNGROUPED_PLANS = frozenset({"sheet", "mould", "pouch", "bag", "garment", "glove", "sock"})  # (straps are grouped: 'a
# pack of 6 bungee cords' was one cord of one cord's mass)
STACKED_PLANS = frozenset({"garment"})  # a count of these is a pile, one on another (not laid side by side)
STACK_RISE = 0.9  # each stacked copy's rise over the one below, / one copy's height (soft goods settle a little) [-]
NEST_DEFAULT = 6  # cups in a pack or stack that gives no count [-]
NEST_STEP = 0.12  # the rise of each nested cup over the one below, / one cup's height [-]


@dataclass
class GoodsChange:
    """What the words changed: the plan parameters, the size to build at, the concept (mass), whether to build the
    object twice side by side, and the fill's colour (painted on the 'fill' parts)."""

    params: dict
    size_m: float
    match: ConceptMatch
    duplicate: bool = False
    count: int = 0
    bunch: bool = False
    hand: int = 0
    nested: int = 0
    stacked: int = 0
    fill_color: str | None = None
    notes: tuple[str, ...] = ()


def _unit_longest(plan: str, params: dict) -> float:
    """The longest extent of a plan's unit-frame solid [-]."""
    p = grammar.plan_parameters(plan, params)
    return float(grammar.program_extents(ShapeProgram(name=plan, category="unit", parts=grammar.PLANS[plan][1](p)),
                                         64).max())


def bag_capacity_m3(plan: str, params: dict, size_m: float) -> float:
    """What a bag or pouch of this plan and size holds when filled round [m^3]: BAG_CAPACITY x height x width x
    min(height, width), its height the unit frame's length 1."""
    p = grammar.plan_parameters(plan, {**params, "fill": 0.0})
    if isinstance(p, PouchParams) and p.form == "mesh":  # a net sack holds what its drawn body holds
        return net_capacity(p) * (size_m / _unit_longest(plan, p.model_dump())) ** 3
    height = size_m / _unit_longest(plan, p.model_dump())
    width = float(getattr(p, "width", 1.0)) * height
    return BAG_CAPACITY * height * width * min(height, width)


# a pouch's empty film or fabric per area of its two faces [kg/m^2]: ~100 um PE film; a cotton-duck bean bag
POUCH_SHELL_KG_PER_M2 = {"textile": 0.2, "default": 0.09}


def apply(target: LexiconEntry, portion: str | None, text: str, params: dict, size_m: float,
          match: ConceptMatch, fill: fill_words.Fill | None = None) -> GoodsChange:
    """The change 'a pair of' and a stated fill make to the object built from `target` (its plan and params);
    `fill` is one read already (a pouch of goods, tasks.geometry.pouch_words). A stated volume ('500 ml', '1 litre')
    of a fill sizes the bag to hold it."""
    out = GoodsChange(params=dict(params), size_m=size_m, match=match)
    plan = target.plan
    if plan is None or plan not in grammar.PLANS:
        if portion in PAIR_WORDS and target.key in PAIR_ITSELF_SHAPES:
            out.notes += ("a pair of trousers is one garment",)
        elif portion in PAIR_WORDS and target.drawn_state == "a pair":  # ('a pair of ballet flats': drawn as the pair
            out.notes += ("drawn as the pair it is sold as",)  # they are sold as, weighed as it)
        elif portion in PAIR_WORDS:  # a hand-written object ('a pair of plush bunnies'): two of it side by side
            out.duplicate = True
            out.match = match.model_copy(update={"typical_mass_kg": match.typical_mass_kg * 2
                                                 if match.typical_mass_kg else None})
            out.notes += ("a pair: two of them",)
        elif portion not in BUNCH_WORDS and (count := counted(text, match, target)) is not None and target.category == "textile":
            out.stacked = count  # '5 yellow mesh pinnies': cloth goods in a pile, one on another (laid side by side,
            out.notes += (f"{count} of them stacked",)  # five flat vests apart were five bodies, four of them dropped)
        elif portion not in BUNCH_WORDS and (count := counted(text, match, target)) is not None:
            out.count = count
            out.notes += (f"{count} of them side by side",)
        return out
    fields = grammar.PLANS[plan][0].model_fields
    if plan == "pouch" and _STRAW.search(text):  # 'a juice pouch with a straw'
        out.params["port"] = "straw"
        out.notes += ("a straw through its top",)
    _folds(out, plan, {**target.params, **out.params}, text)
    _puffy(out, plan, {**target.params, **out.params}, text)
    if portion in PAIR_WORDS and _is_pair_itself(plan, {**target.params, **out.params}):
        out.notes += ("a pair of trousers is one garment",)
    elif portion in PAIR_WORDS:
        mass = match.typical_mass_kg * 2 if match.typical_mass_kg else None
        if "pair" in fields:  # the plan draws its pair (two socks side by side, or one ball of both when rolled)
            base = {**target.params, **out.params}
            k = _unit_longest(plan, {**base, "pair": True}) / _unit_longest(plan, base)
            out.params["pair"] = True
            out.size_m = size_m * k
            out.match = match.model_copy(update={"typical_mass_kg": mass, "typical_size_m": out.size_m})
        else:
            out.duplicate = True
            out.match = match.model_copy(update={"typical_mass_kg": mass})
        out.notes += ("a pair: two of them",)
    nest = _NESTED.search(text)
    base = {**target.params, **out.params}
    if nest is not None and plan == "mould" and base.get("columns", 1) == 1 and base.get("rows", 1) == 1:
        word = nest.group(1)
        out.nested = int(word) if word and word.isdigit() else _COUNT_WORDS.get(word or "", NEST_DEFAULT)
        out.notes += (f"a stack of {out.nested}, nested",)
    layers = int({**target.params, **out.params}.get("layers", 1))
    stack = _STACK_COUNT.search(text) if plan == "disc" else None
    if stack is not None:  # 'a stack of 5 pancakes': the stacked disc's layers, its height and mass with them
        word = stack.group(1) or stack.group(2)
        n_layers = int(np.clip(int(word) if word.isdigit() else _COUNT_WORDS.get(word, layers), 2, STACK_MAX))
        height = float({**target.params, **out.params}.get("height", 0.1))
        out.params.update(layers=n_layers, height=height * n_layers / layers)
        mass = match.typical_mass_kg * n_layers / layers if match.typical_mass_kg else None  # (one disc's times n)
        out.match = out.match.model_copy(update={"typical_mass_kg": mass})
        out.notes += (f"a stack of {n_layers}",)
    rolled = plan == "sheet" and {**target.params, **out.params}.get("state") == "rolled"  # a roll object (toilet
    if rolled and PART_UNROLLED.search(text):  # paper, a bandage): 'partly unrolled', its end out on the ground
        out.params["tail"] = UNROLLED_TAIL
        out.notes += ("partly unrolled",)
    goods = plan not in UNGROUPED_PLANS or (plan == "pouch" and fill is None and not target.key.startswith("generic")) \
        or rolled  # ('two toilet rolls': two rolls side by side)
    goods = goods and stack is None
    # (a pouch is a good of its own, 'three juggling beanbags', unless it is the pack the count is inside of)
    count = counted(text, match, target) if goods and portion not in PAIR_WORDS | BUNCH_WORDS else None
    if count is not None:
        out.count = count
        out.notes += (f"{count} of them side by side",)
    elif plan in STACKED_PLANS and portion not in PAIR_WORDS and (many := counted(text, match, target)) is not None:
        out.stacked = many  # '12 folded t-shirts', 'a stack of the black tees, like a dozen': one on another (each
        out.notes += (f"{many} of them stacked",)  # was one garment of one garment's mass)
    if portion in BUNCH_WORDS and plan in HAND_PLANS and size_m > BUNCH_PIECE_MAX_M:
        # 'a bunch of bananas': a hand of them, side by side from one crown; 'a bunch of carrots' the same, their
        # leafy tops gathered
        hand = _HAND_COUNT.search(text)
        n = (int(hand.group(1)) if hand.group(1).isdigit() else _COUNT_WORDS.get(hand.group(1))) if hand else None
        out.hand = int(np.clip(n or HAND_DEFAULT, 2, HAND_MAX))
        out.params["segments"] = HAND_SEGMENTS if out.hand <= 4 else HAND_SEGMENTS - 1  # (five of 11 parts each)
        out.notes += (f"a bunch: a hand of {out.hand} from one crown",)
    if portion in BUNCH_WORDS and plan in BUNCHABLE_PLANS and size_m <= BUNCH_PIECE_MAX_M:
        out.bunch = True
        out.notes += ("a bunch: a cluster of them on a stem",)
    fill = fill or fill_words.read_fill(text)
    if fill is None and plan == "pouch" and target.material == "gel" and "capacity" not in (match.stated_mass_source or ""):
        if stated_volume_m3(text) is not None:  # 'a 2 l saline bag': the bag's own liquid, the stated volume of it
            fill = fill_words.Fill.of(fill_words.fills()["water"], "its liquid", float(target.params.get("fill", 0.6)))
    if fill is not None and plan in FILLABLE_PLANS and "fill" in fields \
            and not _named_with_fill(target, match):  # 'a bag of sugar' is its own entry
        out.params["fill"] = float(np.clip(fill.fraction, 0.05, 1.0))
        cap = bag_capacity_m3(plan, {**target.params, **out.params}, out.size_m)
        volume = stated_volume_m3(text)
        said = ""
        if volume is not None:  # '500 ml of saline': the bag that holds it; 'a half-full 40 litre bag': its capacity
            held = volume if fill_words.stated_fullness(text) is None else volume * fill.fraction
            k = (held / max(fill.fraction * cap, 1e-12)) ** (1.0 / 3.0)
            out.size_m *= k
            cap = bag_capacity_m3(plan, {**target.params, **out.params}, out.size_m)
            out.match = out.match.model_copy(update={"typical_size_m": out.size_m})
            said = f" (sized to hold the stated {volume * 1e3:g} l)"
        fill_kg = fill.mass_kg(cap)
        pack = _retail_pack(fill) if volume is None and target.key == GENERIC_POUCH else None
        full_kg = fill_kg / max(fill.fraction, 1e-9) * float(target.params.get("fill", fill.fraction))
        if pack is not None and full_kg > pack[0]:  # 'a bag of gummy sweets': the retail pack of them, ~150 g, as
            k = (pack[0] / full_kg) ** (1.0 / 3.0)  # sold (full); 'half full', half of it
            out.size_m *= k
            cap = bag_capacity_m3(plan, {**target.params, **out.params}, out.size_m)
            fill_kg = fill.mass_kg(cap)
            out.match = out.match.model_copy(update={"typical_size_m": out.size_m})
            said = f" (the usual retail pack: {pack[1]})"
        if plan == "pouch":  # a pouch entry's typical mass is filled: its empty film or fabric by area
            p = grammar.plan_parameters(plan, {**target.params, **out.params})
            area = 2.0 * out.size_m ** 2 * float(getattr(p, "width", 0.6)) / _unit_longest(plan, p.model_dump()) ** 2
            shell = area * POUCH_SHELL_KG_PER_M2.get(target.material, POUCH_SHELL_KG_PER_M2["default"])
        else:
            shell = out.match.typical_mass_kg or 0.0
        out.fill_color = fill.color
        source = (f"{fill.words}: {fill.fraction:g} of a {cap * 1e3:.3g} l capacity{said} x "
                  f"{fill.bulk_density_kg_per_m3:g} kg/m^3 ({fill.source}) = {fill_kg * 1e3:.3g} g, plus the empty "
                  f"{target.key.replace('_', ' ')} {shell * 1e3:.3g} g")
        out.match = out.match.model_copy(update={"stated_mass_kg": shell + fill_kg, "stated_mass_source": source})
    elif (fill is None or _named_with_fill(target, match)) and plan in FILLABLE_PLANS \
            and "fill" in fields and target.empty_mass_kg is not None \
            and (fullness := fill_words.stated_fullness(text)) is not None:
        _part_full(out, target, *fullness)
    return out


def _retail_pack(fill: fill_words.Fill) -> tuple[float, str] | None:
    """The retail pack of a fill (fill_words.retail_pack_kg): its own, or, for goods drawn as pieces ('a bag of
    almonds', pieces of almond), the pack of the fill its words name (nuts)."""
    pack = fill_words.retail_pack_kg(fill.key)
    if pack is None and fill_words.record(fill.key) is None:
        words = f" {fill.words} "
        named = next((rec["key"] for word, rec in fill_words.fills().items() if "pack_kg" in rec
                      and re.search(rf"\b{re.escape(word.removesuffix('s'))}s?\b", words)), None)
        pack = fill_words.retail_pack_kg(named) if named is not None else None
    return pack


def _named_with_fill(target: LexiconEntry, match: ConceptMatch) -> bool:
    """True when the noun the request matched names the bag with its fill ('a bag of sugar' is its own entry, its
    mass the entry's); 'a paper bag of popcorn' matched 'paper bag', so its fill is read."""
    noun = match.noun or ""
    return " of " in f" {noun} " or (not noun and any(" of " in f" {n} " for n in target.nouns))


def _part_full(out: GoodsChange, target: LexiconEntry, share: float, words: str) -> None:
    """'a half-empty sack of chicken feed': the entry's own fill at that share of its full amount, and its mass
    between its empty and full mass (its full mass scaled to the size built)."""
    full = float(target.params.get("fill", 1.0))
    out.params["fill"] = float(np.clip(full * share, 0.05, 1.0))
    full_kg = target.mass_kg * (out.size_m / target.size_m) ** 3
    empty_kg = float(target.empty_mass_kg or 0.0)
    kg = empty_kg + max(full_kg - empty_kg, 0.0) * share
    out.match = out.match.model_copy(update={"stated_mass_kg": kg, "stated_mass_source": (
        f"'{words}': {share:g} of the full {target.key.replace('_', ' ')}'s contents ({full_kg:.3g} kg full, "
        f"{empty_kg:.3g} kg empty)")})
    out.notes += (f"{words}: {share:g} of its fill",)


def _is_pair_itself(plan: str, params: dict) -> bool:
    """True when 'a pair of' names one object (trousers, jeans, shorts: the pair is its two legs)."""
    return plan == "garment" and params.get("kind") == "trousers"


def stated_folds(text: str) -> tuple[int, bool] | None:
    """(halvings, the first in thirds) a text states ('folded in quarters': 2, False), else None."""
    m = _FOLD_WORDS.search(text)
    return _FOLDS[m.group(1)] if m is not None else None


def _folds(out: GoodsChange, plan: str, params: dict, text: str) -> None:
    """'folded in half / in thirds / in quarters': the folded sheet's layers, its size scaled to the new footprint."""
    m = _FOLD_WORDS.search(text)
    if m is None or params.get("state") != "folded" or "thirds" not in grammar.PLANS[plan][0].model_fields:
        return
    folds, thirds = _FOLDS[m.group(1)]
    new = {**params, "folds": folds, "thirds": thirds}
    k = _unit_longest(plan, new) / _unit_longest(plan, params)
    out.params.update(folds=folds, thirds=thirds)
    out.size_m *= k
    out.match = out.match.model_copy(update={"typical_size_m": out.size_m})
    out.notes += (f"folded in {m.group(1)}",)


def _puffy(out: GoodsChange, plan: str, params: dict, text: str) -> None:
    """'puffy', 'puffer', 'quilted', 'down-filled': a garment's quilted baffles (a sheet's quilting), its built layer
    thicker and its mass a padded garment's."""
    if _PUFFY.search(text) is None or params.get("shape") in grammar.goods.FORMED_SHEETS:
        return  # (a padded envelope is padded already)
    fields = grammar.PLANS[plan][0].model_fields
    if "baffles" in fields and not params.get("baffles"):
        out.params["baffles"] = PUFFER_BAFFLES
        puff = grammar.goods.PUFF
    elif "quilt" in fields and not params.get("quilt"):
        out.params["quilt"] = 6
        puff = grammar.goods.PUFF if params.get("state", "flat") == "flat" else 1.0
    else:
        return
    density = out.match.density_kg_per_m3
    mass = out.match.typical_mass_kg
    out.match = out.match.model_copy(update={
        "density_kg_per_m3": density * PUFFER_MASS / puff if density else None,
        "typical_mass_kg": mass * PUFFER_MASS if mass else None})
    out.notes += ("quilted: puffy baffles",)


def group_count(text: str) -> int | None:
    """The number of pieces a text asks for ('two bananas', 'a pack of 6 sponges', '3-pack'), 2..GROUP_MAX; else None."""
    for m in _GROUP_COUNT.finditer(text):
        word = m.group(1) or m.group(2) or m.group(3)
        n = int(word) if word.isdigit() else _COUNT_WORDS.get(word)
        if n is not None and n >= 2:
            return min(n, GROUP_MAX)
    return None


def grouped(program: ShapeProgram, match: ConceptMatch, count: int) -> tuple[ShapeProgram, ConceptMatch]:
    """`count` copies lying side by side, just touching (GROUP_PER_ROW along the shorter horizontal axis, then further
    rows along the longer; as many as a program's 64 parts hold): the typical mass times the count, the typical size
    the group's longest extent."""
    parts = list(program.parts)  # (a copy's carved parts, a peach's crease, carve only its own)
    if any(p.operation not in ("union", "subtract") for p in parts):
        return program, match
    asked = count
    count = max(1, min(count, MAX_PARTS // max(len(parts), 1)))
    if count < 2:
        return program, match
    ext = grammar.program_extents(program, 48)
    short, long_ = (1, 0) if ext[1] <= ext[0] else (0, 1)
    per_row = min(GROUP_PER_ROW, int(np.ceil(np.sqrt(count)))) if count > GROUP_PER_ROW - 1 else count  # (five bean
    shifts = []  # bags as 3 + 2, not a row of four and one: a Tetris L)
    for k in range(count):
        shift = [0.0, 0.0, 0.0]
        shift[short] = GROUP_PITCH * float(ext[short]) * (k % per_row)
        shift[long_] = GROUP_PITCH * float(ext[long_]) * (k // per_row)
        shifts.append(shift)
    many, match = copies(program, match, shifts)
    if asked > count:  # more asked than a program's parts draw: the ones drawn weigh all of them
        share = asked / count
        match = match.model_copy(update={
            "typical_mass_kg": match.typical_mass_kg * share if match.typical_mass_kg else None,
            "density_kg_per_m3": match.density_kg_per_m3 * share if match.density_kg_per_m3 else None})
    return many, match


def hand_of(program: ShapeProgram, match: ConceptMatch, count: int) -> tuple[ShapeProgram, ConceptMatch]:
    """A hand of curved fruit (bananas) lying on a table: `count` side by side HAND_PITCH of one's width apart, the
    inner ones resting a little higher on their neighbours, every stem end joined in one crown; the typical mass
    times the count."""
    count = max(1, min(count, (MAX_PARTS - 1) // max(len(program.parts), 1)))
    if count < 2:
        return program, match
    ext = grammar.program_extents(program, 48)
    mid = 0.5 * (count - 1)
    shifts = [(0.0, HAND_PITCH * float(ext[1]) * (k - mid), HAND_RISE * float(ext[2]) * (1.0 - abs(k - mid) / mid))
              for k in range(count)]
    many, match = copies(program, match, shifts)
    stems = [q for q in many.parts if part_group(q.name) == "stem"]
    if stems and len(many.parts) + len(stems) + 1 <= MAX_PARTS:  # the stems drawn in to one crown
        ends = np.array([q.transform.translation_m for q in stems])
        r = 0.16 * float(ext[1])
        crown = (float(ends[:, 0].max()) + 1.5 * r, 0.0, float(ends[:, 2].mean()))
        rgb = stems[0].color_rgb
        joins = [limb(f"stem join {k + 1}", tuple(float(v) for v in end), crown, r, blend=0.3 * r) for k, end in
                 enumerate(ends)]
        joins.append(ellipsoid("crown", (1.6 * r, 1.8 * r, 1.4 * r), crown, blend=0.3 * r))
        many = many.model_copy(update={"parts": [*many.parts, *(q.model_copy(update={"color_rgb": rgb})
                                                                  for q in joins)]})
    return many, match


def moved(part: Part, shift: Sequence[float], name: str) -> Part:
    """A copy of a part translated by shift [m], under another name (the copies of a pair, a group, a stack)."""
    x, y, z = part.transform.translation_m
    return part.model_copy(update={"name": name, "transform": part.transform.model_copy(update={
        "translation_m": (x + shift[0], y + shift[1], z + shift[2])})})


def duplicated(program: ShapeProgram) -> ShapeProgram | None:
    """The program twice: a flat one (a glove) lying over the first, shifted half its width along its shorter
    horizontal axis (one body, as the mesher keeps one); a standing one (a toy) beside it, just touching; None past
    the part limit."""
    parts = list(program.parts)
    if 2 * len(parts) > MAX_PARTS:
        return None
    ext = grammar.program_extents(program, 48)
    axis = 1 if ext[1] <= ext[0] else 0
    flat = float(ext[2]) < 0.3 * float(max(ext[0], ext[1]))
    if any(p.operation != "union" for p in parts) and flat:  # (a cut in the copy lying over the first cuts both;
        return None  # beside it, a roll's core or a cup's hollow cuts only its own copy: parts combine in order)
    if not flat and any(part_group(p.name) in ("left ring", "right ring", "ring") for p in parts):
        axis = 1 - axis  # two rolls side by side, both ends' layers seen (not end to end, read as one long roll)
    shift = [0.0, 0.0, 0.85 * float(ext[2]) if flat else 0.0]
    shift[axis] = (0.45 if flat else 0.97) * float(ext[axis])
    return program.model_copy(update={"parts": parts + [moved(p, shift, f"other {p.name}") for p in parts]})


def pair_up(program: ShapeProgram, match: ConceptMatch) -> tuple[ShapeProgram, ConceptMatch]:
    """The program built twice (duplicated) and the concept's typical size set to the pair's longest extent."""
    two = duplicated(program)
    if two is None:
        return program, match
    longest = float(grammar.program_extents(two, 48).max())
    return two, match.model_copy(update={"typical_size_m": longest})


def nested_stack(program: ShapeProgram, match: ConceptMatch, count: int) -> tuple[ShapeProgram, ConceptMatch]:
    """`count` open cups nested one in another, each NEST_STEP of a cup's height above the one below (as many as a
    program's 64 parts hold); the concept's typical mass times the count and its typical size the stack's longest
    extent."""
    count = max(1, min(count, MAX_PARTS // max(len(program.parts), 1)))
    rise = NEST_STEP * float(grammar.program_extents(program, 32)[2])
    return copies(program, match, [(0.0, 0.0, k * rise) for k in range(count)])


def _height(program: ShapeProgram) -> float:
    """A program's height [m], sampled finer when a thin good (a flat leg warmer) falls between a coarse grid's cells."""
    for resolution in (32, 64, 128):
        try:
            return float(grammar.program_extents(program, resolution)[2])
        except InputError:
            continue
    raise InputError(f"program '{program.name}' has no volume")


def piled(program: ShapeProgram, match: ConceptMatch, count: int) -> tuple[ProgramMatch, int]:
    """`count` copies one on another, each STACK_RISE of one's height above the one below, as many as a program's 64
    parts hold (a garment of 33 parts or more is drawn once); the drawn ones weigh all `count` (the typical mass and
    density times the share not drawn). Returns ((program, match), the number drawn)."""
    drawn = max(1, min(count, MAX_PARTS // max(len(program.parts), 1)))
    rise = STACK_RISE * _height(program)
    many, match = copies(program, match, [(0.0, 0.0, k * rise) for k in range(drawn)])
    if count > drawn:
        share = count / drawn
        match = match.model_copy(update={
            "typical_mass_kg": match.typical_mass_kg * share if match.typical_mass_kg else None,
            "density_kg_per_m3": match.density_kg_per_m3 * share if match.density_kg_per_m3 else None})
    return (many, match), drawn


ProgramMatch = tuple[ShapeProgram, ConceptMatch]


def copies(program: ShapeProgram, match: ConceptMatch, shifts: Sequence[Sequence[float]]
           ) -> tuple[ShapeProgram, ConceptMatch]:
    """The program once per shift [m] (the first copy keeps its parts' names, the k-th adds ' k'); the concept's
    typical mass times the number of copies and its typical size the copies' longest extent."""
    parts = [moved(p, shift, p.name if k == 0 else f"{p.name} {k + 1}")
             for k, shift in enumerate(shifts) for p in program.parts]
    many = program.model_copy(update={"parts": parts})
    mass = match.typical_mass_kg * len(shifts) if match.typical_mass_kg else None
    span = np.ptp(np.asarray(shifts, dtype=np.float64).reshape(-1, 3), axis=0)  # (the copies' extents from one's: a
    longest = float((grammar.program_extents(program, 48) + span).max())  # thin disc spread wide falls between voxels)
    return many, match.model_copy(update={"typical_mass_kg": mass, "typical_size_m": longest})


def painted_fill(program: ShapeProgram, color: str) -> ShapeProgram:
    """The program with its 'fill' parts in the fill's colour (rice shows ivory through a clear bag)."""
    rgb = load_lexicon().colors[color]
    return program.model_copy(update={"parts": [p.model_copy(update={"color_rgb": rgb}) if part_group(p.name) == "fill"
                                                else p for p in program.parts]})


def bunched(program: ShapeProgram, match: ConceptMatch) -> tuple[ShapeProgram, ConceptMatch]:
    """A bunch of small round pieces lying on a table: a tapered cluster BUNCH_LENGTH pieces long (wide at the stem's
    shoulder, narrow at the tip), the pieces over its upper surface, a core where the inner ones are, and the stem.
    Its typical mass is the pieces' mass at the cluster's volume (BUNCH_PACKING of it) and its typical size its
    length."""
    ext = grammar.program_extents(program, 32)
    r = 0.5 * float(ext.max())
    length = BUNCH_LENGTH * 2.0 * r
    spots: list[tuple[float, float, float]] = []
    jitter = np.random.default_rng(BUNCH_SEED)  # the same bunch for the same words
    rows = max(int(length / (1.7 * r)), 3)
    for i in range(rows):
        x = 0.5 * length - r - i * (length - 2.0 * r) / (rows - 1)
        u = i / (rows - 1)  # 0 at the shoulder, 1 at the tip
        half_w = max(r, (0.3 - 0.2 * u) * length)
        half_h = max(r, 0.7 * half_w)
        arc = np.pi * (half_w + half_h) / 2.0  # half the ellipse's perimeter (its upper half)
        n = max(int(arc / (1.6 * r)) + 1, 1)
        shift = 0.5 * np.pi / max(n - 1, 1) * (i % 2)  # odd rows sit in the even rows' gaps
        for a in np.linspace(shift, np.pi - shift, n) if n > 1 else [0.5 * np.pi]:
            dx, dy, dz = 0.2 * r * jitter.standard_normal(3)
            dz = abs(dz)  # (the pieces along the bottom stay on the ground)
            spots.append((x + dx, (half_w - r) * float(np.cos(a)) + dy, r + (half_h - r) * float(np.sin(a)) + dz))
    most = min(BUNCH_MAX_PIECES, (BUNCH_MAX_PIECES + 4) // max(len(program.parts), 1))
    if len(spots) > most:
        spots = [spots[int(k)] for k in np.linspace(0, len(spots) - 1, most)]
    parts: list = []
    c0 = program.parts[0].transform.translation_m  # the piece's body centre goes to each spot
    for k, (x, y, z) in enumerate(spots):
        for p in program.parts:
            t = p.transform.translation_m
            parts.append(p.model_copy(update={"name": f"{p.name} {k + 1}", "transform": p.transform.model_copy(
                update={"translation_m": (t[0] - c0[0] + x, t[1] - c0[1] + y, t[2] - c0[2] + z)})}))
    body_rgb = program.parts[0].color_rgb
    cores = []
    for i in range(BUNCH_CORES):
        u = (i + 0.5) / BUNCH_CORES
        outer_w = max(r, (0.3 - 0.2 * u) * length)
        top = max(r, 0.7 * outer_w)  # the top pieces' centres; the core spans from just above the ground to them
        at = (0.5 * length - r - u * (length - 2.0 * r), 0.0, 0.5 * top)
        cores.append(ellipsoid(f"body core {i + 1}", (0.6 * length / BUNCH_CORES, outer_w - r, 0.5 * top - 0.15 * r), at,
                               blend=0.5 * r).model_copy(update={"color_rgb": body_rgb}))
    stem = limb("stem", (0.5 * length - r, 0.0, 2.0 * r), (0.5 * length + 2.5 * r, 0.0, 3.0 * r), 0.18 * r)
    parts = [*cores, *parts,
             stem.model_copy(update={"color_rgb": (0.42, 0.33, 0.2)})]
    bunch = program.model_copy(update={"parts": parts})
    piece_v = max(program_volume(program, 24), 1e-12)
    count = BUNCH_PACKING * program_volume(bunch, 48) / piece_v
    longest = float(grammar.program_extents(bunch, 48).max())
    mass = match.typical_mass_kg * count if match.typical_mass_kg else None
    return bunch, match.model_copy(update={"typical_mass_kg": mass, "typical_size_m": longest,
                                           "mass_source": f"{match.mass_source}; a bunch: ~{count:.0f} of them "
                                           f"({BUNCH_PACKING:g} of the cluster's volume)"})

