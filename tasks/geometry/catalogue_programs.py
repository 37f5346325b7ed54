"""The catalogue's hand-written shape programs (tasks/geometry/catalogue.yaml and shapes/*.yaml), read once: the
entries the offline Designer (tasks/geometry/catalogue.py) and the lexicon's concepts (tasks/geometry/concepts.py)
both build from."""

from __future__ import annotations

import functools
import hashlib
import os
import pickle
import tempfile
from pathlib import Path
from typing import Any

from contracts.yaml_io import load_yaml

from contracts.shape import ShapeProgram

CATALOGUE_FILE = Path(__file__).with_name("catalogue.yaml")
SHAPES_DIR = Path(__file__).with_name("shapes")  # more hand-written entries, one file per batch, same units


@functools.lru_cache(maxsize=1)
def catalogue_yaml() -> dict[str, Any]:
    """catalogue.yaml as read (entries, palette, length unit), with the entries of every shapes/*.yaml merged in;
    an entry named twice is an error. The parse (1.4 MB of YAML, ~3 s) is kept beside the files, as Python keeps
    bytecode, under a hash of their bytes: a process that starts L0 reads it back in ~0.1 s."""
    files = [CATALOGUE_FILE, *sorted(SHAPES_DIR.glob("*.yaml"))]
    texts = [path.read_bytes() for path in files]
    digest = hashlib.sha256(b"\0".join(p.name.encode() + b"\0" + t for p, t in zip(files, texts))).hexdigest()[:20]
    kept = SHAPES_DIR / "__pycache__" / f"catalogue-{digest}.pickle"
    try:
        return pickle.loads(kept.read_bytes())  # noqa: S301 - written by this function, as a .pyc is by Python
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ValueError):
        pass
    raw = _parsed(files, texts)
    _keep(kept, pickle.dumps(raw, protocol=pickle.HIGHEST_PROTOCOL))
    for stale in kept.parent.glob("catalogue-*.pickle"):  # an older catalogue's parse
        if stale != kept:
            stale.unlink(missing_ok=True)
    return raw


def _parsed(files: list[Path], texts: list[bytes]) -> dict[str, Any]:
    """The catalogue file with the shapes files' entries merged in."""
    raw = load_yaml(texts[0].decode("utf-8"))
    for path, text in zip(files[1:], texts[1:]):
        more = load_yaml(text.decode("utf-8"))["entries"]
        twice = sorted(set(more) & set(raw["entries"]))
        if twice:
            raise ValueError(f"{path.name}: catalogue entries {twice} are defined twice")
        raw["entries"].update(more)
    return raw


def _keep(path: Path, data: bytes) -> None:
    """Write `data` to `path` whole or not at all (a temporary file renamed); a folder that cannot be written (an
    installed, read-only package) keeps nothing."""
    try:
        path.parent.mkdir(exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".catalogue-", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    except OSError:
        pass


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
