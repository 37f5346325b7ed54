"""A file made once per content: later runs with the same inputs copy it from the cache instead of making it again
(e.g. a video rendered from recorded data)."""

from __future__ import annotations

import hashlib
import os
import shutil
from collections.abc import Callable, Iterable
from importlib import metadata
from pathlib import Path

from cache.config import cache_root
from cache.store import CacheMiss, CacheStore


def source_digest(paths: Iterable[Path], distributions: Iterable[str] = ()) -> str:
    """Hex sha256 of the given files' bytes (directories: every file under them but __pycache__) and the installed
    versions of the given distributions: the code part of a key, so an edit makes a new key."""
    h = hashlib.sha256()
    files: list[Path] = []
    for p in map(Path, paths):
        files.extend([f for f in p.rglob("*") if f.is_file() and "__pycache__" not in f.parts] if p.is_dir() else [p])
    for f in sorted(set(files)):
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    for dist in sorted(distributions):
        try:
            version = metadata.version(dist)
        except metadata.PackageNotFoundError:
            version = "-"
        h.update(f"{dist}={version}\0".encode())
    return h.hexdigest()


def cached_file(key: str, dest: Path, make: Callable[[Path], object]) -> bool:
    """dest (a file, or a folder such as a Zarr group) copied from the cache entry `key` (True), else made by
    make(dest) and stored under `key` (False). The copy appears only complete (copied beside dest, then renamed)."""
    store = CacheStore(cache_root())
    dest = Path(dest)
    try:
        src = store.get(key)
    except CacheMiss:
        src = None
    dest.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(src, Path) and src.exists():
        tmp = dest.with_name(f".{dest.name}.from-cache-{os.getpid()}")
        try:
            if src.is_dir():
                shutil.copytree(src, tmp)
                if dest.is_dir():
                    shutil.rmtree(dest)
            else:
                shutil.copyfile(src, tmp)
            os.replace(tmp, dest)
        finally:
            if tmp.is_dir():
                shutil.rmtree(tmp, ignore_errors=True)
            else:
                tmp.unlink(missing_ok=True)
        return True
    make(dest)
    store.put(key, dest, meta={"made": dest.name})
    return False
