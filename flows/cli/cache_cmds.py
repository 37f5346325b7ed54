"""`deformsmith cache stats|verify|gc` (the cache benchmark is `python -m benchmarks.cache_bench`)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated, Any

import typer

from cache.config import ENV_VAR, use_cache_root
from cache.tempfiles import remove_dead_temporaries
from contracts.errors import DeformSmithError, InputError
from flows.cli.apps import cache_app, emit_json, fail, results
from tasks.report.tables import cache_stats_table, empty_cache_stats, gc_line
from tasks.report.units import parse_duration, parse_size

CacheOption = Annotated[
    Path | None,
    typer.Option("--cache", help=f"Cache root (default: ${ENV_VAR}, else the user cache directory).",
                 show_default=False),
]
JsonOption = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON on stdout.")]

def resolve_cache_option(value: Path | None) -> Path:
    """Resolve `--cache` (> env > user dir) and export it so cached tasks in this process use that root."""
    return use_cache_root(value)


def _store(cache: Path | None) -> Any:
    from cache.store import CacheStore  # lazy: pulls zarr (--help imports every command module)

    return CacheStore(resolve_cache_option(cache))


@cache_app.command("stats")
def stats_cmd(cache: CacheOption = None, json_out: JsonOption = False) -> None:
    """Entries, total size, last use and hit/miss counts of the cache."""
    try:
        explicit = cache is not None or bool(os.environ.get(ENV_VAR))
        store = _store(cache)
        if not store.root.exists() and not explicit:  # a fresh default cache is simply empty
            data: dict[str, Any] = empty_cache_stats(store.root)
        else:
            data = store.stats()
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    if json_out:
        emit_json(data)
        return
    results.print(cache_stats_table(data))


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
    results.print(gc_line(result, dead))
