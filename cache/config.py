"""Cache root resolution: `--cache` option > env `DEFORMSMITH_CACHE` > the user cache directory."""

from __future__ import annotations

import os
from pathlib import Path

import platformdirs

ENV_VAR = "DEFORMSMITH_CACHE"
APP_NAME = "deformsmith"


def default_cache_root() -> Path:
    """The per-user cache directory (platformdirs), e.g. ~/.cache/deformsmith/results on Linux."""
    return Path(platformdirs.user_cache_dir(APP_NAME)) / "results"


def cache_root(cli_value: str | os.PathLike[str] | None = None) -> Path:
    """Resolve the cache root: explicit value, else `$DEFORMSMITH_CACHE`, else the user cache dir (absolute)."""
    if cli_value is not None and str(cli_value) != "":
        return Path(cli_value).expanduser().absolute()
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env).expanduser().absolute()
    return default_cache_root()


def use_cache_root(cli_value: str | os.PathLike[str] | None) -> Path:
    """Resolve the root and export it in `$DEFORMSMITH_CACHE` so cached tasks and subprocesses use it."""
    root = cache_root(cli_value)
    os.environ[ENV_VAR] = str(root)
    return root


def cache_relative(path: str | os.PathLike[str]) -> str:
    """A path inside the cache root as a root-relative reference (records stay identical whatever the root)."""
    p = Path(path).absolute()
    try:
        return p.relative_to(cache_root()).as_posix()
    except ValueError:
        return str(p)


def cache_resolve(reference: str | os.PathLike[str]) -> Path:
    """The file a cache-relative (or absolute) reference points to."""
    p = Path(reference)
    return p if p.is_absolute() else cache_root() / p
