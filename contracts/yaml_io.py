"""YAML reading through libyaml's C parser where PyYAML was built with it (the lexicon's 1,000 entries parse ~10x
faster); the same safe constructor and resolver as `yaml.safe_load`, so the data are identical."""

from __future__ import annotations

from typing import Any

import yaml

_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def load_yaml(text: str) -> Any:
    """`yaml.safe_load(text)`, parsed in C when available."""
    return yaml.load(text, Loader=_LOADER)  # noqa: S506 - a safe loader (CSafeLoader or SafeLoader)
