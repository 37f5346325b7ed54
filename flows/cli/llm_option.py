"""`--llm-fallback rule|fail`: what happens when the `--llm` model gives no answer (no key, no server, bad answers)."""

from __future__ import annotations

from typing import Any

from contracts.agents import AgentConfig
from flows.cli.apps import fail

LLM_FALLBACK_HELP = ("when the --llm model cannot be used (no key, no server) or gives no valid answer: 'rule' "
                     "(default) lets the offline rule backend stand in, said on the console and recorded in asset.json and the "
                     "evidence; 'fail' stops with an error, nothing published")
POLICIES = {"rule": "fallback_rule", "fail": "fail"}


def llm_agents(llm: str | None, fallback: str = "rule") -> Any:
    """AgentConfig with every role played by `llm` under the fallback policy, or None for the offline rule backend."""
    if fallback not in POLICIES:
        fail(f"--llm-fallback must be rule or fail, got '{fallback}'")
    if not llm:
        return None

    return AgentConfig.llm(llm, on_failure=POLICIES[fallback])  # type: ignore[arg-type]
