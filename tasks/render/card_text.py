"""The asset card's words: numbers in SI units and figure lines of at most 80 characters (shared by card_png and
card_html)."""

from __future__ import annotations

import math
from typing import Any

from tasks.render.card_data import Figure

WIDTH = 80
PREFIXED_UNITS = ("Pa", "N", "m", "s")  # units written with an SI prefix (kPa, mN, mm, ms); others as they are
_PREFIXES = ((1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "u"), (1e-9, "n"))


def si(value: float | None, unit: str) -> str:
    """A value with its unit, 3 significant digits: 10.4 kPa, 388 um, 0.152 kg, 26.6 deg, 0.0728 (unit '-')."""
    if value is None or not math.isfinite(value):
        return "not measured"  # never 'nan' on a card (#36)
    suffix = "" if unit == "-" else f" {unit}"
    if unit in PREFIXED_UNITS and value != 0.0:
        for scale, prefix in _PREFIXES:
            if abs(value) >= scale * 0.9995:
                return f"{value / scale:.3g} {prefix}{unit}"
        return f"{value:.3g}{suffix}"
    return f"{value:.3g}{suffix}"


def band_text(fig: Figure) -> str:
    """'in [5 kPa, 19.9 kPa]' / 'OUTSIDE [...]' (measured) / 'target [...]' (not measured) / '' without a band."""
    if fig.band is None:
        return ""
    word = {"measured inside": "in", "measured outside": "OUTSIDE"}.get(fig.state, "target")
    return f"{word} [{si(fig.band[0], fig.unit)}, {si(fig.band[1], fig.unit)}]"


def state_text(fig: Figure) -> str:
    """A figure's state in words: 'measured, inside its target' / 'measured, OUTSIDE its target' / 'measured' /
    'not measured: <why>'."""
    if fig.state == "not measured":
        return f"not measured: {fig.note}" if fig.note else "not measured"
    return {"measured inside": "measured, inside its target",
            "measured outside": "measured, OUTSIDE its target"}.get(fig.state, "measured")


def figure_lines(fig: Figure, label_width: int = 24) -> list[str]:
    """Two lines: 'label  value  band' and '  from <source> [cache key]', each cut to WIDTH characters."""
    first = f"{fig.label:<{label_width}} {si(fig.value, fig.unit):>11}  {band_text(fig)}".rstrip()
    second = f"  from {fig.source}" + (f" [key {fig.key[:12]}]" if fig.key else "")
    return [_cut(first), _cut(second)]


def _cut(line: str) -> str:
    return line if len(line) <= WIDTH else line[:WIDTH - 3] + "..."


def wrap(text: str, width: int = WIDTH, indent: str = "") -> list[str]:
    """Text wrapped at width characters."""
    import textwrap

    return textwrap.wrap(text, width=width, subsequent_indent=indent) or [""]


def request_line(request: dict[str, Any]) -> str:
    """What was asked for, in one line."""
    what = (f"text '{request['text']}'" if request.get("text") else
            f"image {request.get('image_path')}" if request.get("image_path") else f"mesh {request.get('mesh_path')}")
    return f"request: {what}; quality {request.get('quality')}, seed {request.get('seed')}"


def outcome_lines(outcome: dict[str, bool]) -> list[str]:
    """L3's outcome flags, a few per line: 'lifted yes, transported yes, ...'."""
    words = [f"{k.replace('_', ' ')} {'yes' if v else 'no'}" for k, v in outcome.items()]
    lines, line = [], ""
    for w in words:
        if line and len(line) + len(w) + 2 > WIDTH:
            lines.append(line)
            line = ""
        line = f"{line}, {w}" if line else w
    return [*lines, line] if line else lines
