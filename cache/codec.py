"""Value trees <-> JSON attributes with type tags (arrays and files are stored beside them)."""

from __future__ import annotations

import hashlib
import importlib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np
from pydantic import BaseModel

from cache.hashing import qualified_name
from contracts.errors import CacheError

TAG = "__t"
_ARRAY_KINDS = "biufc"


@dataclass
class Encoded:
    """Result of encoding: the JSON tree plus the arrays and files it refers to."""

    tree: Any = None
    arrays: dict[str, np.ndarray] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)  # stored name -> source path


def tree_digest(tree: Any) -> str:
    """Hex sha256 of a JSON tree in canonical form (detects edits of the attributes)."""
    text = json.dumps(tree, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def _tag_floats(x: Any) -> Any:
    """JSON data with non-finite floats replaced by tagged strings (strict JSON has no NaN / inf)."""
    if isinstance(x, float) and not math.isfinite(x):
        return {TAG: "float", "v": repr(x)}
    if isinstance(x, list):
        return [_tag_floats(i) for i in x]
    if isinstance(x, dict):
        return {k: _tag_floats(i) for k, i in x.items()}
    return x


def _untag_floats(x: Any) -> Any:
    """Inverse of _tag_floats."""
    if isinstance(x, list):
        return [_untag_floats(i) for i in x]
    if isinstance(x, dict):
        if x.get(TAG) == "float":
            return float(x["v"])
        return {k: _untag_floats(i) for k, i in x.items()}
    return x


def encode(value: Any) -> Encoded:
    """Encode a value tree for storage; raises TypeError on unsupported types."""
    out = Encoded()
    out.tree = _enc(value, out)
    return out


def _enc(v: Any, out: Encoded) -> Any:
    if v is None or isinstance(v, (bool, str)):
        return v
    if isinstance(v, int):
        return int(v)
    if isinstance(v, float):
        return v if math.isfinite(v) else {TAG: "float", "v": repr(v)}
    if isinstance(v, BaseModel):
        return {TAG: "model", "cls": qualified_name(type(v)), "data": _tag_floats(v.model_dump(mode="json"))}
    if isinstance(v, np.ndarray):
        if v.dtype.kind not in _ARRAY_KINDS:
            raise TypeError(f"cannot store arrays of dtype {v.dtype} (numeric and bool only)")
        name = f"a{len(out.arrays)}"
        out.arrays[name] = v
        return {TAG: "array", "name": name}
    if isinstance(v, np.generic):
        if v.dtype.kind not in _ARRAY_KINDS:
            raise TypeError(f"cannot store numpy scalars of dtype {v.dtype}")
        return {TAG: "npscalar", "dtype": v.dtype.str, "v": _enc(v.item(), out)}
    if isinstance(v, Path):
        if not v.exists():
            raise CacheError(f"cannot store output path {v}: it does not exist")
        name = f"f{len(out.files)}/{v.name}"
        out.files[name] = v
        return {TAG: "path", "name": name}
    if isinstance(v, list):
        return [_enc(x, out) for x in v]
    if isinstance(v, tuple):
        return {TAG: "tuple", "items": [_enc(x, out) for x in v]}
    if isinstance(v, dict):
        for k in v:
            if not isinstance(k, str):
                raise TypeError(f"dict keys must be str to be stored, got {type(k).__name__}")
        return {TAG: "dict", "items": {k: _enc(x, out) for k, x in v.items()}}
    raise TypeError(f"cannot store a value of type {qualified_name(type(v))}")


def _import_qualified(name: str) -> type:
    """Import `module:qualname`."""
    module, _, qual = name.partition(":")
    obj: Any = importlib.import_module(module)
    for part in qual.split("."):
        obj = getattr(obj, part)
    return obj


def decode(tree: Any, load_array: Callable[[str], np.ndarray], files_dir: Path) -> Any:
    """Rebuild the value from its JSON tree; arrays come from `load_array`, paths point into `files_dir`."""
    if isinstance(tree, list):
        return [decode(x, load_array, files_dir) for x in tree]
    if not isinstance(tree, dict):
        return tree
    tag = tree.get(TAG)
    if tag == "float":
        return float(tree["v"])
    if tag == "model":
        cls = cast(type[BaseModel], _import_qualified(tree["cls"]))  # encode tags only BaseModel instances "model"
        return cls.model_validate_json(json.dumps(_untag_floats(tree["data"]), allow_nan=True))
    if tag == "array":
        return load_array(tree["name"])
    if tag == "npscalar":
        return np.dtype(tree["dtype"]).type(decode(tree["v"], load_array, files_dir))
    if tag == "path":
        return files_dir / tree["name"]
    if tag == "tuple":
        return tuple(decode(x, load_array, files_dir) for x in tree["items"])
    if tag == "dict":
        return {k: decode(x, load_array, files_dir) for k, x in tree["items"].items()}
    raise CacheError(f"unknown type tag {tag!r} in stored entry")
