"""litellm, imported and configured in one place (no network at import: the packaged cost map; no debug banner):
tasks.agents.llm talks to models through it, tasks.agents.fallbacks asks it for a model's credentials."""

from __future__ import annotations

import os

os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")  # before importing litellm: no network at import

import litellm  # noqa: E402

litellm.suppress_debug_info = True

__all__ = ["litellm"]
