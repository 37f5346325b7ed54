"""Publish a finished directory in place of another with renames, so readers never see a half-written one."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path


def replace_directory(finished: Path, dest: Path) -> None:
    """Rename `finished` to `dest` (same filesystem); an existing `dest` is moved aside first, then removed."""
    finished, dest = Path(finished), Path(dest)
    if dest.exists():
        aside = Path(tempfile.mkdtemp(prefix=f".{dest.name}.old-", dir=dest.parent))
        os.replace(dest, aside / "previous")
        os.replace(finished, dest)
        shutil.rmtree(aside, ignore_errors=True)
    else:
        os.replace(finished, dest)
