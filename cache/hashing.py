"""Content keys: a type-tagged, length-prefixed sha256 over values (never identity, time or run ids)."""

from __future__ import annotations

import hashlib
import json
import os
import struct
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel

from contracts.errors import InputError

_PARALLEL_BYTES = 4 << 20  # arrays at least this large are digested on a thread pool (hashlib drops the GIL)
_FILE_BLOCK = 1 << 20


def qualified_name(obj: Any) -> str:
    """`module:qualname` of a class or function (how types are named in keys and stored entries)."""
    return f"{obj.__module__}:{obj.__qualname__}"


def canonical_model_json(model: BaseModel) -> str:
    """Canonical JSON of a pydantic model: `model_dump(mode="json")` with sorted keys, no whitespace."""
    return json.dumps(model.model_dump(mode="json"), sort_keys=True, separators=(",", ":"), allow_nan=True)


def array_digest(array: np.ndarray) -> str:
    """Hex sha256 of an array's dtype, shape and C-order bytes (the digest stored and verified in entries)."""
    if array.dtype.hasobject:
        raise TypeError("object arrays cannot be content-hashed")
    h = hashlib.sha256()
    h.update(f"{array.dtype.str}|{array.shape}|".encode())
    if array.size:
        h.update(np.ascontiguousarray(array).reshape(-1).data.cast("B"))
    return h.hexdigest()


def file_digest(path: Path) -> str:
    """Hex sha256 of a file's bytes."""
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def path_digest(path: Path) -> str:
    """Hex sha256 of a file's or directory's content (directory: sorted relative paths + file digests)."""
    p = Path(path)
    if p.is_file():
        return "f" + file_digest(p)
    if p.is_dir():
        h = hashlib.sha256()
        for dirpath, dirnames, filenames in os.walk(p):
            dirnames.sort()
            rel_dir = Path(dirpath).relative_to(p)
            for name in sorted(filenames):
                rel = (rel_dir / name).as_posix()
                h.update(f"{len(rel)}:{rel}:".encode())
                h.update(file_digest(Path(dirpath) / name).encode())
            for name in dirnames:  # empty directories count too
                rel = (rel_dir / name).as_posix()
                h.update(f"d{len(rel)}:{rel}:".encode())
        return "d" + h.hexdigest()
    raise InputError(f"cannot hash {p}: no such file or directory")


class _Encoder:
    """Streams a canonical encoding of a value tree into one sha256."""

    def __init__(self) -> None:
        self.h = hashlib.sha256()
        self.arrays: list[np.ndarray] = []

    def _str(self, tag: bytes, text: str) -> None:
        data = text.encode("utf-8")
        self.h.update(tag + struct.pack("<Q", len(data)) + data)

    def collect(self, value: Any) -> None:
        """First pass: gather large arrays so their digests can be computed in parallel."""
        if isinstance(value, np.ndarray):
            if value.nbytes >= _PARALLEL_BYTES:
                self.arrays.append(value)
        elif isinstance(value, (list, tuple)):
            for item in value:
                self.collect(item)
        elif isinstance(value, dict):
            for item in value.values():
                self.collect(item)

    def encode(self, value: Any, digests: dict[int, str]) -> None:
        """Second pass: feed the tagged encoding of `value` into the hash."""
        h = self.h
        if value is None:
            h.update(b"N")
        elif isinstance(value, bool):
            h.update(b"B1" if value else b"B0")
        elif isinstance(value, BaseModel):
            self._str(b"M", qualified_name(type(value)))
            self._str(b"J", canonical_model_json(value))
        elif isinstance(value, str):
            self._str(b"S", value)
        elif isinstance(value, int):
            self._str(b"I", str(int(value)))
        elif isinstance(value, float):
            h.update(b"F" + struct.pack("<d", value))
        elif isinstance(value, np.ndarray):
            self._str(b"A", digests.get(id(value)) or array_digest(value))
        elif isinstance(value, np.generic):
            self._str(b"G", array_digest(np.asarray(value)))
        elif isinstance(value, Path):
            self._str(b"P", path_digest(value))
        elif isinstance(value, (list, tuple)):
            h.update((b"L" if isinstance(value, list) else b"T") + struct.pack("<Q", len(value)))
            for item in value:
                self.encode(item, digests)
        elif isinstance(value, dict):
            h.update(b"D" + struct.pack("<Q", len(value)))
            for key in sorted(value, key=_dict_key):
                self._str(b"K", _dict_key(key))
                self.encode(value[key], digests)
        else:
            raise TypeError(f"cannot content-hash a value of type {qualified_name(type(value))}")


def _dict_key(key: Any) -> str:
    """Dict keys must be strings (they are stored as JSON object keys)."""
    if not isinstance(key, str):
        raise TypeError(f"dict keys must be str for content hashing, got {type(key).__name__}")
    return key


def content_key(*parts: Any) -> str:
    """Hex sha256 content key of `parts` (models, arrays, file/dir paths by content, scalars, containers)."""
    enc = _Encoder()
    enc.collect(parts)
    digests: dict[int, str] = {}
    if len(enc.arrays) > 1:
        with ThreadPoolExecutor(max_workers=min(len(enc.arrays), os.cpu_count() or 1)) as pool:
            for arr, dig in zip(enc.arrays, pool.map(array_digest, enc.arrays)):
                digests[id(arr)] = dig
    enc.encode(tuple(parts), digests)
    return enc.h.hexdigest()
