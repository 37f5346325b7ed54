"""Every data file the packages load at run time is shipped: each YAML / JSON file under a package matches a
[tool.setuptools.package-data] pattern of pyproject.toml (an editable install hides a missing one)."""

from __future__ import annotations

import fnmatch
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("contracts", "cache", "tasks", "flows", "benchmarks")
DATA_SUFFIXES = {".yaml", ".yml", ".json", ".jsonl"}


def test_every_data_file_is_package_data() -> None:
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]
    patterns = setuptools["package-data"]
    assert set(setuptools["packages"]["find"]["include"]) == {f"{p}*" for p in PACKAGES}
    missing = []
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*")):
            if path.suffix in DATA_SUFFIXES and "__pycache__" not in path.parts:
                rel = path.relative_to(ROOT / pkg).as_posix()
                if not any(fnmatch.fnmatchcase(rel, pat) and rel.count("/") == pat.count("/")
                           for pat in patterns.get(pkg, [])):
                    missing.append(f"{pkg}/{rel}")
    assert not missing, "not in [tool.setuptools.package-data]: " + ", ".join(missing)
