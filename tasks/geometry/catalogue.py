"""Offline text Designer: description -> catalogue shape program, stated sizes and modifiers."""

from __future__ import annotations

import difflib
import functools
import re
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from pydantic import Field

from contracts.base import Model
from contracts.errors import InputError
from contracts.shape import ShapeProgram

CATALOGUE_FILE = Path(__file__).with_name("catalogue.yaml")
MIN_SIZE_M, MAX_SIZE_M = 0.01, 2.0

_UNITS = {"mm": 0.001, "millimeter": 0.001, "millimetre": 0.001, "cm": 0.01, "centimeter": 0.01,
          "centimetre": 0.01, "m": 1.0, "meter": 1.0, "metre": 1.0, "in": 0.0254, "inch": 0.0254, "inches": 0.0254,
          '"': 0.0254, "ft": 0.3048, "foot": 0.3048, "feet": 0.3048}
_UNIT_RE = r"(mm|millimet(?:er|re)s?|cm|centimet(?:er|re)s?|m|met(?:er|re)s?|inch(?:es)?|in|\"|ft|foot|feet)\b"
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
}


class SizeSpec(Model):
    """Requested size: explicit extents on canonical axes and/or a longest extent, plus relative modifiers."""

    extents_m: tuple[float | None, float | None, float | None] = Field(default=(None, None, None), description="x, y, z [m]")
    longest_m: float | None = Field(default=None, gt=0, description="longest extent [m]")
    axis_scale: tuple[float, float, float] = Field(default=(1.0, 1.0, 1.0), description="modifier scale per axis [-]")
    stated: str | None = Field(default=None, description="the text the size was read from")

    def resolve(self, current: np.ndarray) -> np.ndarray:
        """Target extents [m] for a mesh whose extents are `current` (x, y, z)."""
        ext = np.asarray(current, dtype=np.float64) * np.asarray(self.axis_scale)
        given = [(i, v) for i, v in enumerate(self.extents_m) if v is not None]
        if given:
            factors = [v / ext[i] for i, v in given]
            ext = ext * float(np.exp(np.mean(np.log(factors))))
            for i, v in given:
                ext[i] = v
        elif self.longest_m is not None:
            ext = ext * (self.longest_m / float(ext.max()))
        return ext

    @property
    def explicit(self) -> bool:
        """True when the text or the user stated a size."""
        return self.longest_m is not None or any(v is not None for v in self.extents_m)


class Design(Model):
    """What the offline Designer made of a description."""

    entry: str
    program: ShapeProgram
    size: SizeSpec
    modifiers: list[str] = Field(default_factory=list)
    warnings: list[str] = Field(default_factory=list)
    match_score: float = Field(description="keyword match strength; 0 means nearest-category fallback")


@functools.lru_cache(maxsize=1)
def _raw() -> dict[str, Any]:
    return yaml.safe_load(CATALOGUE_FILE.read_text(encoding="utf-8"))


def entry_names() -> list[str]:
    """All catalogue entry names."""
    return list(_raw()["entries"])


def entry_keywords(name: str) -> list[str]:
    """Keywords that select an entry."""
    return list(_raw()["entries"][name]["keywords"])


def entry_category(name: str) -> str:
    """Category of an entry (used for priors downstream)."""
    return str(_raw()["entries"][name]["category"])


def program_for(name: str) -> ShapeProgram:
    """The shape program (metres) of a catalogue entry."""
    raw = _raw()
    unit = float(raw["length_unit_m"])
    palette = raw["palette"]
    entry = raw["entries"][name]
    parts = []
    for p in entry["parts"]:
        prim = {k: (_scale(v, unit) if k.endswith("_m") else v) for k, v in p["p"].items()}
        col = p.get("c", "grey")
        parts.append({
            "name": p["n"], "primitive": prim,
            "transform": {"translation_m": _scale(p.get("t", [0, 0, 0]), unit), "rotation_deg": p.get("r", [0, 0, 0]),
                          "scale": p.get("s", [1, 1, 1])},
            "color_rgb": palette[col] if isinstance(col, str) else col,
            "operation": p.get("op", "union"), "blend_m": float(p.get("b", 0.0)) * unit,
        })
    return ShapeProgram(name=name.replace("_", " "), category=entry["category"], parts=parts)


def _scale(v: Any, unit: float) -> Any:
    return [float(x) * unit for x in v] if isinstance(v, list) else float(v) * unit


def _words(text: str) -> list[str]:
    return re.findall(r"[a-z]+", text.lower())


def match_entry(text: str) -> tuple[str, float]:
    """Best entry for a description: longest keyword phrase found (score > 0), else fuzzy nearest (score 0)."""
    words = _words(text)
    joined = " " + " ".join(words) + " "
    best, best_score = None, 0.0
    for name in entry_names():
        for kw in entry_keywords(name):
            kw_words = _words(kw)
            forms = {" " + " ".join(kw_words) + " ", " " + " ".join(kw_words) + "s "}
            if any(f in joined for f in forms):
                score = len(kw_words) + 0.01 * len(kw)
                if score > best_score:
                    best, best_score = name, score
    if best is not None:
        return best, best_score
    vocab = {kw_word: name for name in entry_names() for kw in entry_keywords(name) for kw_word in _words(kw)}
    vocab.update({w: name for name in entry_names() for w in [entry_category(name)] + name.split("_")})
    scored = []
    for w in words:
        if w in MODIFIERS or len(w) < 3:
            continue
        for cand in difflib.get_close_matches(w, list(vocab), n=1, cutoff=0.6):
            scored.append((difflib.SequenceMatcher(None, w, cand).ratio(), cand))
    if scored:
        scored.sort(key=lambda t: (-t[0], t[1]))
        return vocab[scored[0][1]], 0.0
    return _soft_default(words), 0.0


def _soft_default(words: list[str]) -> str:
    """Fallback entry from material words when no object word is recognised."""
    hints = {"plush": "teddy_bear", "stuffed": "teddy_bear", "toy": "teddy_bear", "foam": "foam_block",
             "rubber": "rubber_ball", "silicone": "silicone_ball", "soft": "foam_ball", "jelly": "jelly"}
    for w in words:
        if w in hints:
            return hints[w]
    return "foam_block"


def parse_size(text: str) -> SizeSpec:
    """Sizes stated in a description ('25 cm long', '10 x 7 x 3 cm', '8 cm in diameter', '5 in tall')."""
    t = text.replace("×", "x")
    m = _DIMS_RE.search(t)
    if m:
        unit = _UNITS[_unit_key(m.group(6))]
        dims = [float(m.group(i)) * unit for i in (1, 3, 5) if m.group(i) is not None]
        ext = tuple(dims) + (None,) * (3 - len(dims))
        return SizeSpec(extents_m=ext, stated=m.group(0))  # type: ignore[arg-type]
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
        else:
            longest = val
        stated.append(mm.group(0).strip())
    if not stated:
        return SizeSpec()
    if any(v is not None for v in ext):
        return SizeSpec(extents_m=tuple(ext), stated="; ".join(stated))  # type: ignore[arg-type]
    return SizeSpec(longest_m=longest, stated="; ".join(stated))


def _unit_key(u: str) -> str:
    u = u.lower()
    if u in _UNITS:
        return u
    for stem, key in (("milli", "mm"), ("centi", "cm"), ("met", "m"), ("inch", "in"), ("f", "ft")):
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


def strip_sizes(text: str) -> str:
    """The text without its size phrases (so '25 cm long' is not read as the modifier 'long')."""
    t = text.replace("×", "x")
    for rx in (_DIMS_RE, _PREFIX_RE, _ONE_RE):
        t = rx.sub(" ", t)
    return t


def parse_modifiers(text: str) -> tuple[list[str], tuple[float, float, float]]:
    """Modifier words found in the text and their combined per-axis scale."""
    words = _words(text)
    found = [w for w in words if w in MODIFIERS]
    scale = np.ones(3)
    for w in found:
        scale *= np.asarray(MODIFIERS[w])
    return found, (float(scale[0]), float(scale[1]), float(scale[2]))


def check_size(size: SizeSpec) -> None:
    """Reject sizes outside what L0 can build: [1 cm, 2 m] for every stated extent."""
    vals = [v for v in (*size.extents_m, size.longest_m) if v is not None]
    for v in vals:
        if not (MIN_SIZE_M <= v <= MAX_SIZE_M):
            raise InputError(
                f"requested size {v:g} m ({size.stated or 'size hint'}) is outside the supported range "
                f"[{MIN_SIZE_M:g}, {MAX_SIZE_M:g}] m"
            )


def design_from_text(text: str, size_hint_m: float | None = None) -> Design:
    """Map a description to a catalogue program, the stated size and the modifiers; record any fallback."""
    if not text or not text.strip():
        raise InputError("the description is empty")
    name, score = match_entry(text)
    warnings = []
    if score == 0.0:
        warnings.append(f"no catalogue object named in '{text.strip()}': using the nearest category "
                        f"'{entry_category(name)}' (entry '{name}')")
    size = parse_size(text)
    if size_hint_m is not None:
        size = SizeSpec(longest_m=size_hint_m, stated=f"size hint {size_hint_m:g} m")
    mods, axis_scale = parse_modifiers(strip_sizes(text))
    size = size.model_copy(update={"axis_scale": axis_scale})
    check_size(size)
    return Design(entry=name, program=program_for(name), size=size, modifiers=mods, warnings=warnings, match_score=score)
