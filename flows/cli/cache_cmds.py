"""`deformsmith cache stats|verify|gc` (the cache benchmark is `python -m benchmarks.cache_bench`)."""

from __future__ import annotations

import os
import re
import time
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.table import Table

from cache.config import ENV_VAR, use_cache_root
from cache.tempfiles import remove_dead_temporaries
from contracts.errors import DeformSmithError, InputError
from flows.cli.apps import cache_app, emit_json, fail, results

CacheOption = Annotated[
    Path | None,
    typer.Option("--cache", help=f"Cache root (default: ${ENV_VAR}, else the user cache directory).",
                 show_default=False),
]
JsonOption = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON on stdout.")]

_DURATION = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([smhdw]?)\s*$", re.IGNORECASE)
_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kmgt]?i?b?)\s*$", re.IGNORECASE)
_SECONDS = {"": 1, "s": 1, "m": 60, "h": 3600, "d": 86400, "w": 604800}


def resolve_cache_option(value: Path | None) -> Path:
    """Resolve `--cache` (> env > user dir) and export it so cached tasks in this process use that root."""
    return use_cache_root(value)


def parse_duration(text: str) -> float:
    """'90', '90s', '30m', '12h', '7d', '2w' -> seconds."""
    m = _DURATION.match(text)
    if not m:
        raise InputError(f"invalid duration {text!r} (examples: 3600, 30m, 12h, 7d)")
    return float(m.group(1)) * _SECONDS[m.group(2).lower()]


def parse_size(text: str) -> int:
    """'1000', '500MB', '2G', '1.5GiB' -> bytes (K/M/G/T are powers of 1024)."""
    m = _SIZE.match(text)
    if not m:
        raise InputError(f"invalid size {text!r} (examples: 1000000, 500MB, 2GB)")
    unit = m.group(2).lower()[:1]
    return int(float(m.group(1)) * 1024 ** "bkmgt".index(unit or "b"))


def _store(cache: Path | None) -> Any:
    from cache.store import CacheStore  # lazy: pulls zarr (--help imports every command module)

    return CacheStore(resolve_cache_option(cache))


def _human(n: float) -> str:
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if abs(n) < 1024 or unit == "TB":
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n} B"


def _when(ts: float | None) -> str:
    return "-" if ts is None else time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(ts))


@cache_app.command("stats")
def stats_cmd(cache: CacheOption = None, json_out: JsonOption = False) -> None:
    """Entries, total size, last use and hit/miss counts of the cache."""
    try:
        explicit = cache is not None or bool(os.environ.get(ENV_VAR))
        store = _store(cache)
        if not store.root.exists() and not explicit:  # a fresh default cache is simply empty
            data: dict[str, Any] = {"root": str(store.root), "entries": 0, "bytes": 0, "oldest_use": None,
                                    "newest_use": None, "tmp_dirs": 0, "events": 0, "hits": 0, "misses": 0}
        else:
            data = store.stats()
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    if json_out:
        emit_json(data)
        return
    table = Table(title=f"cache {data['root']}", show_header=False)
    table.add_row("entries", str(data["entries"]))
    table.add_row("size", _human(data["bytes"]))
    table.add_row("oldest use", _when(data["oldest_use"]))
    table.add_row("newest use", _when(data["newest_use"]))
    table.add_row("runs logged", f"{data['events']} ({data['hits']} hits, {data['misses']} executed)")
    table.add_row("temp dirs", str(data["tmp_dirs"]))
    results.print(table)


@cache_app.command("verify")
def verify_cmd(
    cache: CacheOption = None,
    remove: Annotated[bool, typer.Option("--remove", help="Delete the corrupt entries found.")] = False,
    json_out: JsonOption = False,
) -> None:
    """Recompute every entry's digests; exits 1 and names each corrupt entry if any."""
    try:
        store = _store(cache)
        keys = store.keys() if store.root.is_dir() else []
        problems = store.verify(remove=remove)
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    if json_out:
        emit_json({"root": str(store.root), "checked": len(keys), "removed": remove,
                   "corrupt": [{"key": p.key, "reason": p.reason} for p in problems]})
    else:
        for p in problems:
            results.print(f"[red]corrupt[/red] {p.key}: {p.reason}" + (" (removed)" if remove else ""))
        results.print(f"checked {len(keys)} entries, {len(problems)} corrupt")
    if problems:
        raise typer.Exit(1)


@cache_app.command("gc")
def gc_cmd(
    cache: CacheOption = None,
    older_than: Annotated[str | None, typer.Option("--older-than", help="Remove entries unused for this long (30m, 12h, 7d).")] = None,
    max_size: Annotated[str | None, typer.Option("--max-size", help="Then remove least recently used entries until the total is at most this (500MB, 2GB).")] = None,
    outputs: Annotated[list[Path] | None, typer.Option("--outputs", help="A folder holding asset directories: also remove the .NAME.partial-* working directories that dead runs left in it (repeatable).")] = None,
    json_out: JsonOption = False,
) -> None:
    """Remove old entries and/or shrink the cache to a size; also removes what dead processes left (crash leftovers:
    recordings/*.rrd.<pid>.tmp, tmp/ entries, and with --outputs the .NAME.partial-* working directories)."""
    try:
        age = parse_duration(older_than) if older_than is not None else None
        size = parse_size(max_size) if max_size is not None else None
        for folder in outputs or []:
            if not folder.is_dir():
                raise InputError(f"--outputs {folder}: not a directory")
        store = _store(cache)
        store.require_root()  # never tidy a folder that is not a DeformSmith cache
        dead = remove_dead_temporaries(store.root, list(outputs or []))
        result = store.gc(older_than_s=age, max_bytes=size)
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    result = {**result, "dead_temporaries_removed": dead["removed"], "dead_temporaries_bytes": dead["freed_bytes"]}
    if json_out:
        emit_json(result)
        return
    results.print(f"removed {len(result['removed'])} entries ({_human(result['freed_bytes'])}); "
                  f"{result['remaining_entries']} remain ({_human(result['remaining_bytes'])}); "
                  f"{len(dead['removed'])} temporaries of dead processes removed ({_human(dead['freed_bytes'])})")
