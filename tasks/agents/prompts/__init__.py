"""Role prompts as data: one YAML file per role (system text + answer instructions)."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import yaml

PROMPTS_DIR = Path(__file__).parent


@lru_cache(maxsize=8)
def load_prompt(role: str) -> dict[str, str]:
    """The prompt of one role: keys 'system' and 'instructions'."""
    data = yaml.safe_load((PROMPTS_DIR / f"{role}.yaml").read_text(encoding="utf-8"))
    return {"system": str(data["system"]).strip(), "instructions": str(data["instructions"]).strip()}
