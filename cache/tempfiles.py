"""Temporaries of dead processes: find and remove what a SIGKILL, Ctrl-C or full disk left behind.

Three kinds, each named after its owner's process id, and removed only when that process is gone:
- ``<cache>/recordings/**/<name>.rrd.<pid>.tmp``: a Rerun recording being written (tasks.record.ProbeRecording);
- ``<cache>/tmp/<key>.<pid>.<random>``: a cache entry being written (cache.store.CacheStore.put);
- ``<dir>/.<name>.{partial,tmp,old}-<host>~<pid>~<random>``: a working directory beside an output (an asset being
  built by flows.generate, an L0 output by tasks.geometry.outputs, an old directory set aside by tasks.publish).
A name that carries no host (the first two) is removed only once untouched for `GRACE_S` seconds, so that a live
writer of another host sharing the cache is never mistaken for a dead local one.
"""

from __future__ import annotations

import os
import re
import shutil
import socket
import time
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

GRACE_S = 60.0  # a pid-only temporary must be untouched this long before it counts as dead [s]
_RRD_TMP = re.compile(r"^.+\.rrd\.(\d+)\.tmp$")
_ENTRY_TMP = re.compile(r"^[0-9a-f]{16,}\.(\d+)\.[0-9a-f]{8}$")
_PARTIAL = re.compile(r"^\.(?P<name>.+)\.(?P<kind>partial|tmp|old)-(?P<host>[^~]+)~(?P<pid>\d+)~")


def owner_tag() -> str:
    """`<host>~<pid>~`: put in a working directory's name so that a dead owner can be recognised (dead_partials)."""
    return f"{socket.gethostname()}~{os.getpid()}~"


def pid_alive(pid: int) -> bool:
    """True while a process with this id exists on this host (one we may not signal counts as alive)."""
    if pid <= 0:
        return True  # not a real owner: never treat it as dead
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _untouched_for(path: Path, seconds: float, now: float) -> bool:
    try:
        return now - path.lstat().st_mtime >= seconds
    except OSError:
        return False


def dead_cache_temporaries(root: Path, grace_s: float = GRACE_S, now: float | None = None) -> list[Path]:
    """Recording temporaries and entry temp dirs under the cache root whose writer process is dead."""
    root, now = Path(root), time.time() if now is None else now
    found: list[Path] = []
    candidates = [(p, _RRD_TMP) for p in (root / "recordings").rglob("*.tmp")] if (root / "recordings").is_dir() else []
    if (root / "tmp").is_dir():
        candidates += [(p, _ENTRY_TMP) for p in (root / "tmp").iterdir()]
    for path, pattern in candidates:
        m = pattern.match(path.name)
        if m and not pid_alive(int(m.group(1))) and _untouched_for(path, grace_s, now):
            found.append(path)
    return sorted(found)


def dead_partials(parent: Path, name: str | None = None) -> list[Path]:
    """`.<name>.{partial,tmp,old}-<host>~<pid>~*` working directories in `parent` left by a dead process of this
    host (only those of output `name` when given)."""
    parent, host = Path(parent), socket.gethostname()
    found: list[Path] = []
    if not parent.is_dir():
        return found
    for path in parent.glob(".*-*~*~*"):
        m = _PARTIAL.match(path.name)
        if m and m.group("host") == host and not pid_alive(int(m.group("pid"))) and name in (None, m.group("name")):
            found.append(path)
    return sorted(found)


def remove_own_working_dirs(places: Iterable[Path]) -> None:
    """Remove this process's `.<name>.partial-` / `.tmp-` working directories found in `places` (a process stopped
    by a signal, whose unwinding did not get to them). A set-aside previous asset (`.old-`) is left for the next run
    to restore or clear, as after a kill."""
    host, pid = socket.gethostname(), str(os.getpid())
    for place in places:
        try:
            entries = list(place.iterdir()) if place.is_dir() else []
        except OSError:
            continue
        for entry in entries:
            m = _PARTIAL.match(entry.name)
            if m and m.group("kind") != "old" and (m.group("host"), m.group("pid")) == (host, pid):
                shutil.rmtree(entry, ignore_errors=True)


def remove_paths(paths: list[Path]) -> tuple[list[Path], int]:
    """Remove files and directory trees; (the paths removed, bytes freed). A path that vanished meanwhile is skipped."""
    removed, freed = [], 0
    for path in paths:
        try:
            if path.is_dir() and not path.is_symlink():
                freed += sum(f.lstat().st_size for f in path.rglob("*") if f.is_file())
                shutil.rmtree(path)
            else:
                freed += path.lstat().st_size
                path.unlink()
        except FileNotFoundError:
            continue
        except OSError:
            continue  # not ours to remove (permissions): left as it is
        removed.append(path)
    return removed, freed


def remove_dead_temporaries(root: Path, outputs: Sequence[Path] = (), grace_s: float = GRACE_S) -> dict[str, Any]:
    """Remove the cache's temporaries of dead processes and the dead working directories in each `outputs` folder."""
    paths = dead_cache_temporaries(root, grace_s)
    for folder in outputs:
        paths += dead_partials(folder)
    removed, freed = remove_paths(paths)
    return {"removed": [str(p) for p in removed], "freed_bytes": int(freed)}
