"""Publish a finished directory in place of another with renames, so readers never see a half-written one."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cache.tempfiles import owner_tag


def replace_directory(finished: Path, dest: Path) -> None:
    """Rename `finished` to `dest` (same filesystem); an existing `dest` is moved aside first, then removed."""
    finished, dest = Path(finished), Path(dest)
    if dest.exists():
        aside = Path(tempfile.mkdtemp(prefix=f".{dest.name}.old-{owner_tag()}", dir=dest.parent))
        os.replace(dest, aside / "previous")
        os.replace(finished, dest)
        shutil.rmtree(aside, ignore_errors=True)
    else:
        os.replace(finished, dest)


def write_json_atomic(path: Path, record: Any, default: Callable[[Any], Any] | None = str) -> None:
    """Write a JSON record (sorted keys, indented) to a temporary name and rename it into place."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(record, indent=2, sort_keys=True, default=default) + "\n", encoding="utf-8")
    tmp.replace(path)
