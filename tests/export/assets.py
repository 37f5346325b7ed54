"""The export tests' assets: a committed sponge (its L0-L2 files, no recordings) and, for the slow mesh-quality
sweep, a folder of generated assets named by DEFORMSMITH_TEST_ASSETS (sponge, turtle, jelly, duck)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

SPONGE = Path(__file__).parent / "fixtures" / "sponge"  # "a yellow kitchen sponge, 10 cm long", --no-l3, draft
GENERATED = Path(os.environ["DEFORMSMITH_TEST_ASSETS"]) if os.environ.get("DEFORMSMITH_TEST_ASSETS") else None


def copy_sponge(dest: Path) -> Path:
    """A writable copy of the committed sponge at dest."""
    shutil.copytree(SPONGE, dest)
    return dest
