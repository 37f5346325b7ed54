"""The catalogue's hand-written shape programs (tasks/geometry/catalogue.yaml and shapes/*.yaml), read once: the
entries the offline Designer (tasks/geometry/catalogue.py) and the lexicon's concepts (tasks/geometry/concepts.py)
both build from."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from contracts.yaml_io import load_yaml

from contracts.shape import ShapeProgram

CATALOGUE_FILE = Path(__file__).with_name("catalogue.yaml")
SHAPES_DIR = Path(__file__).with_name("shapes")  # more hand-written entries, one file per batch, same units


@functools.lru_cache(maxsize=1)
def catalogue_yaml() -> dict[str, Any]:
    """catalogue.yaml as read (entries, palette, length unit), with the entries of every shapes/*.yaml merged in;
    an entry named twice is an error."""
    raw = load_yaml(CATALOGUE_FILE.read_text(encoding="utf-8"))
    for path in sorted(SHAPES_DIR.glob("*.yaml")):
        more = load_yaml(path.read_text(encoding="utf-8"))["entries"]
        twice = sorted(set(more) & set(raw["entries"]))
        if twice:
            raise ValueError(f"{path.name}: catalogue entries {twice} are defined twice")
        raw["entries"].update(more)
    return raw


def catalogue_program(name: str) -> ShapeProgram:
    """The hand-written shape program (metres) of a catalogue entry, at the catalogue's size."""
    raw = catalogue_yaml()
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
