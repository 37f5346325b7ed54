"""Zarr result store: one group per key, published atomically, verified on read, with stats/verify/gc."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import time
import uuid
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cache import codec
from cache.hashing import array_digest, path_digest
from cache.locks import key_lock
from contracts.errors import CacheError

FORMAT = 1
MARKER = "DEFORMSMITH_CACHE"
ATTR = "deformsmith"
CHUNK_BYTES = 16 << 20  # chunk target along axis 0 (chosen with `python -m benchmarks.cache_bench`)
COMPRESSORS: Any = None  # uncompressed: simulation state is float noise, compression costs more than it saves
STALE_TMP_S = 6 * 3600.0  # temp dirs older than this are crash leftovers that gc removes


class CacheMiss(KeyError):
    """No intact entry under the key (missing or corrupt)."""


@dataclass(frozen=True)
class Problem:
    """A corrupt entry found by verify."""

    key: str
    reason: str


def _fsync_tree(path: Path) -> None:
    """fsync every file and directory under `path` (so a rename publishes durable bytes)."""
    for dirpath, _dirs, files in os.walk(path):
        for name in files:
            fd = os.open(os.path.join(dirpath, name), os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
        _fsync_dir(Path(dirpath))


def _fsync_dir(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _tree_bytes(path: Path) -> int:
    total = 0
    for dirpath, _dirs, files in os.walk(path):
        for name in files:
            with contextlib.suppress(OSError):
                total += os.lstat(os.path.join(dirpath, name)).st_size
    return total


def _chunks(array: np.ndarray) -> tuple[int, ...]:
    if array.ndim == 0:
        return ()
    row = max(1, int(np.prod(array.shape[1:], dtype=np.int64)) * array.itemsize)
    n = array.shape[0]
    pieces = max(1, -(-n * row // CHUNK_BYTES))  # balanced chunks: zarr pads the last one to full size
    rows = max(1, -(-n // pieces))
    return (rows, *array.shape[1:])


def _digests(arrays: dict[str, np.ndarray]) -> dict[str, str]:
    """Digest arrays, in parallel when there are several large ones (hashlib releases the GIL)."""
    if len(arrays) > 1 and sum(a.nbytes for a in arrays.values()) > (8 << 20):
        with ThreadPoolExecutor(max_workers=min(len(arrays), os.cpu_count() or 1)) as pool:
            return dict(zip(arrays, pool.map(array_digest, arrays.values())))
    return {name: array_digest(a) for name, a in arrays.items()}


class CacheStore:
    """Content-addressed store of task results under `root` (see cache/__init__.py for the layout)."""

    def __init__(self, root: str | os.PathLike[str]) -> None:
        self.root = Path(root).expanduser().absolute()
        self._memo: dict[str, tuple[tuple[int, int], Any, dict[str, Any]]] = {}

    # ---- layout -------------------------------------------------------------------------------
    def entry_dir(self, key: str) -> Path:
        """Directory (Zarr group) of `key`'s entry."""
        if len(key) < 8 or not all(c in "0123456789abcdef" for c in key):
            raise CacheError(f"invalid cache key {key!r} (expected lowercase hex)")
        return self.root / "entries" / key[:2] / key

    @property
    def events_path(self) -> Path:
        """JSONL execution log: one line per cached-task run (hit or miss)."""
        return self.root / "events.jsonl"

    def init_root(self) -> None:
        """Make `root` a DeformSmith cache (its folders and marker); an existing cache is left as it is."""
        for sub in ("entries", "tmp", "locks"):
            (self.root / sub).mkdir(parents=True, exist_ok=True)
        marker = self.root / MARKER
        if not marker.exists():
            marker.write_text(f"DeformSmith result cache, format {FORMAT}\n")

    def require_root(self) -> None:
        """Raise CacheError unless `root` is an existing DeformSmith cache directory."""
        if not self.root.exists():
            raise CacheError(f"cache root {self.root} does not exist")
        if not self.root.is_dir():
            raise CacheError(f"cache root {self.root} is not a directory")
        if not (self.root / MARKER).exists() and not (self.root / "entries").is_dir():
            raise CacheError(f"{self.root} is not a DeformSmith cache (no {MARKER} marker)")

    def keys(self) -> list[str]:
        """Keys of all published entries (intact or not)."""
        base = self.root / "entries"
        if not base.is_dir():
            return []
        return sorted(p.name for shard in base.iterdir() if shard.is_dir() for p in shard.iterdir() if p.is_dir())

    # ---- write --------------------------------------------------------------------------------
    def put(self, key: str, value: Any, meta: dict[str, Any] | None = None) -> bool:
        """Store `value` under `key` atomically; False if an intact entry was already there (kept)."""
        final = self.entry_dir(key)
        self.init_root()
        enc = codec.encode(value)
        tmp = self.root / "tmp" / f"{key}.{os.getpid()}.{uuid.uuid4().hex[:8]}"
        try:
            self._write(tmp, key, enc, meta or {})
            with key_lock(self.root, key):
                if final.exists():
                    if self.verify_entry(key) is None:
                        return False  # an intact entry won the race: keep it
                    trash = self.root / "tmp" / f"trash-{key}.{uuid.uuid4().hex[:8]}"
                    os.rename(final, trash)
                    shutil.rmtree(trash, ignore_errors=True)
                final.parent.mkdir(parents=True, exist_ok=True)
                os.rename(tmp, final)
                _fsync_dir(final.parent)
            return True
        finally:
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)

    def _write(self, tmp: Path, key: str, enc: codec.Encoded, meta: dict[str, Any]) -> None:
        """Write the complete entry into `tmp` and fsync it."""
        digests = _digests(enc.arrays)
        files = {}
        for name, src in enc.files.items():
            dst = tmp / "_files" / name
            dst.parent.mkdir(parents=True, exist_ok=True)
            if src.is_dir():
                shutil.copytree(src, dst)
            else:
                shutil.copyfile(src, dst)
            files[name] = path_digest(dst)
        attrs = {
            ATTR: {
                "format": FORMAT,
                "key": key,
                "created": time.time(),
                "meta": meta,
                "value": enc.tree,
                "value_digest": codec.tree_digest(enc.tree),
                "arrays": {n: {"digest": d, "dtype": enc.arrays[n].dtype.str, "shape": list(enc.arrays[n].shape)}
                           for n, d in digests.items()},
                "files": files,
                "nbytes": int(sum(a.nbytes for a in enc.arrays.values())),
            }
        }
        import zarr  # (lazy: ~0.5 s to import; reading an entry without arrays never needs it)

        group = zarr.create_group(store=str(tmp), attributes=attrs, zarr_format=3)
        for name, arr in enc.arrays.items():
            z = group.create_array(name, shape=arr.shape, dtype=arr.dtype, chunks=_chunks(arr),
                                   compressors=COMPRESSORS, fill_value=0)
            if arr.size:
                z[...] = arr
        _fsync_tree(tmp)

    # ---- read ---------------------------------------------------------------------------------
    def _stamp(self, key: str) -> tuple[int, int] | None:
        try:
            st = os.stat(self.entry_dir(key) / "zarr.json")
        except OSError:
            return None
        return (st.st_ino, st.st_mtime_ns)

    def _attrs(self, key: str) -> dict[str, Any]:
        with open(self.entry_dir(key) / "zarr.json", "rb") as fh:
            doc = json.load(fh)
        info = doc["attributes"][ATTR]
        if info.get("format") != FORMAT or info.get("key") != key:
            raise CacheError("entry header does not match its key")
        return info

    def load(self, key: str) -> tuple[Any, dict[str, Any]]:
        """(value, meta) of an intact entry; raises CacheMiss when missing or corrupt (never returns bad data)."""
        stamp = self._stamp(key)
        memo = self._memo.pop(key, None)
        if memo is not None and stamp is not None and memo[0] == stamp:
            return memo[1], memo[2]
        if stamp is None:
            raise CacheMiss(key)
        try:
            value, meta = self._load_verified(key)
        except CacheMiss:
            raise
        except Exception as exc:  # any unreadable part makes the entry corrupt: a miss
            raise CacheMiss(key) from exc
        with contextlib.suppress(OSError):
            os.utime(self.entry_dir(key))  # last use, for gc
        return value, meta

    def load_keep(self, key: str) -> tuple[Any, dict[str, Any]]:
        """Like load, and remember the result so the next load of the same unchanged entry is free."""
        value, meta = self.load(key)
        stamp = self._stamp(key)
        if stamp is not None:
            while len(self._memo) >= 2:
                self._memo.pop(next(iter(self._memo)))
            self._memo[key] = (stamp, value, meta)
        return value, meta

    def _load_verified(self, key: str) -> tuple[Any, dict[str, Any]]:
        d = self.entry_dir(key)
        info = self._attrs(key)
        if codec.tree_digest(info["value"]) != info["value_digest"]:
            raise CacheMiss(key)
        arrays = {}
        if info["arrays"]:
            import zarr  # (lazy: an entry of values and files alone is read without it)

            group = zarr.open_group(store=str(d), mode="r")
            arrays = {name: np.asarray(group[name][...]) for name in info["arrays"]}
        digests = _digests(arrays)
        for name, spec in info["arrays"].items():
            if digests[name] != spec["digest"]:
                raise CacheMiss(key)
        for name, digest in info["files"].items():
            if path_digest(d / "_files" / name) != digest:
                raise CacheMiss(key)
        value = codec.decode(info["value"], arrays.__getitem__, d / "_files")
        return value, info["meta"]

    def get(self, key: str) -> Any:
        """Value of an intact entry; raises CacheMiss (a KeyError) when missing or corrupt."""
        return self.load(key)[0]

    def contains(self, key: str) -> bool:
        """True when a published entry with a readable header exists (arrays are checked by get/verify)."""
        try:
            self._attrs(key)
            return True
        except Exception:
            return False

    # ---- maintenance --------------------------------------------------------------------------
    def verify_entry(self, key: str) -> str | None:
        """None if the entry is intact, else the reason it is corrupt."""
        try:
            info = self._attrs(key)
        except Exception as exc:
            return f"unreadable header: {type(exc).__name__}: {exc}"
        if codec.tree_digest(info["value"]) != info["value_digest"]:
            return "attribute digest mismatch"
        d = self.entry_dir(key)
        try:
            import zarr

            group = zarr.open_group(store=str(d), mode="r")
            for name, spec in info["arrays"].items():
                arr = np.asarray(group[name][...])
                if array_digest(arr) != spec["digest"]:
                    return f"array {name} digest mismatch"
            for name, digest in info["files"].items():
                if path_digest(d / "_files" / name) != digest:
                    return f"file {name} digest mismatch"
        except Exception as exc:
            return f"unreadable data: {type(exc).__name__}: {exc}"
        return None

    def verify(self, remove: bool = False) -> list[Problem]:
        """Recompute every entry's digests; returns the corrupt ones (removed when `remove`)."""
        self.require_root()
        problems = []
        for key in self.keys():
            reason = self.verify_entry(key)
            if reason is not None:
                problems.append(Problem(key, reason))
                if remove:
                    self.remove(key)
        return problems

    def remove(self, key: str) -> bool:
        """Remove an entry atomically (renamed away, then deleted); False if absent."""
        final = self.entry_dir(key)
        with key_lock(self.root, key):
            if not final.exists():
                return False
            (self.root / "tmp").mkdir(parents=True, exist_ok=True)
            trash = self.root / "tmp" / f"trash-{key}.{uuid.uuid4().hex[:8]}"
            os.rename(final, trash)
        shutil.rmtree(trash, ignore_errors=True)
        return True

    def _entries(self) -> list[tuple[str, float, int]]:
        """(key, last use time, bytes) for every entry."""
        out = []
        for key in self.keys():
            d = self.entry_dir(key)
            with contextlib.suppress(OSError):
                out.append((key, os.stat(d).st_mtime, _tree_bytes(d)))
        return out

    def _tmp_dirs(self) -> list[Path]:
        base = self.root / "tmp"
        return sorted(base.iterdir()) if base.is_dir() else []

    def stats(self) -> dict[str, Any]:
        """Entry count, total bytes, oldest/newest last use, leftover temp dirs, event count."""
        self.require_root()
        entries = self._entries()
        tmps = self._tmp_dirs()
        events = self.events()
        return {
            "root": str(self.root),
            "entries": len(entries),
            "bytes": int(sum(e[2] for e in entries)),
            "oldest_use": min((e[1] for e in entries), default=None),
            "newest_use": max((e[1] for e in entries), default=None),
            "tmp_dirs": len(tmps),
            "events": len(events),
            "hits": sum(1 for e in events if e.get("outcome") == "hit"),
            "misses": sum(1 for e in events if e.get("outcome") == "miss"),
        }

    def gc(self, older_than_s: float | None = None, max_bytes: int | None = None) -> dict[str, Any]:
        """Remove entries unused for `older_than_s`, then least recently used ones until <= `max_bytes`."""
        self.require_root()
        if older_than_s is not None and older_than_s < 0:
            raise CacheError("older-than must be >= 0")
        if max_bytes is not None and max_bytes < 0:
            raise CacheError("max-size must be >= 0")
        now = time.time()
        removed: list[str] = []
        freed = 0
        entries = sorted(self._entries(), key=lambda e: e[1])  # least recently used first
        keep = []
        for key, used, size in entries:
            if older_than_s is not None and now - used > older_than_s:
                if self.remove(key):
                    removed.append(key)
                    freed += size
            else:
                keep.append((key, used, size))
        if max_bytes is not None:
            total = sum(e[2] for e in keep)
            while keep and total > max_bytes:
                key, _used, size = keep.pop(0)
                if self.remove(key):
                    removed.append(key)
                    freed += size
                total -= size
        stale = 0
        for tmp in self._tmp_dirs():
            with contextlib.suppress(OSError):
                if tmp.name.startswith("trash-") or now - os.stat(tmp).st_mtime > STALE_TMP_S:
                    shutil.rmtree(tmp, ignore_errors=True)
                    stale += 1
        return {"removed": removed, "freed_bytes": int(freed), "stale_tmp_removed": stale,
                "remaining_entries": len(keep), "remaining_bytes": int(sum(e[2] for e in keep))}

    # ---- execution log ------------------------------------------------------------------------
    def record_event(self, **event: Any) -> None:
        """Append one JSON line to the execution log (single O_APPEND write: safe across processes)."""
        self.init_root()
        event.setdefault("time", time.time())
        event.setdefault("pid", os.getpid())
        line = (json.dumps(event, sort_keys=True, default=str) + "\n").encode()
        fd = os.open(self.events_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, line)
        finally:
            os.close(fd)

    def events(self) -> list[dict[str, Any]]:
        """All execution-log records in order (unparseable lines are skipped)."""
        try:
            lines = self.events_path.read_text().splitlines()
        except FileNotFoundError:
            return []
        out = []
        for line in lines:
            with contextlib.suppress(json.JSONDecodeError):
                out.append(json.loads(line))
        return out
