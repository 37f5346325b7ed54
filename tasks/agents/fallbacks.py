"""When the rule backend stands in for an LLM: the models found unusable this run, the warning said on the console,
and the error raised under `--llm-fallback fail`; `fallback_notes` reads where it happened back from the evidence.
L0's shape Designer is asked only with credentials for its model (`l0_designer_stand_in`)."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from contracts.agents import AgentConfig
from contracts.errors import InputError

UNAVAILABLE: dict[str, str] = {}  # model string -> why it is unusable this run (no key, no server, no such model)
_SAID: set[str] = set()


class LLMUnavailable(InputError):
    """The configured LLM cannot be used (credential, connection, unknown model) and the policy is to fail."""


def brief(reason: str, limit: int = 160) -> str:
    """A provider error for the console: litellm's repeated 'XError: litellm.XError: XError:' prefix said once, cut."""
    text = re.sub(r"^(?:(?:litellm\.)?(\w+Error): )+", lambda m: m.group(1) + ": ", reason.strip())
    return text if len(text) <= limit else text[:limit - 3] + "..."


def announce(message: str) -> None:
    """Say on stderr, once per message, that the rule backend stood in for an LLM."""
    if message not in _SAID:
        _SAID.add(message)
        sys.stderr.write(f"warning: {message}\n")
        sys.stderr.flush()


def reset() -> None:
    """Forget the models found unusable and the warnings said (a new run, or a test)."""
    UNAVAILABLE.clear()
    _SAID.clear()


def missing_credentials(model: str) -> list[str]:
    """The credential variables (``*_KEY``, ``*_TOKEN``) litellm needs for a model and cannot find in the environment;
    an address with a default (``OLLAMA_API_BASE``) is not a credential."""
    from tasks.agents.litellm_client import litellm  # lazy: litellm takes ~10 s to import, only when a model is asked

    try:
        found = litellm.validate_environment(model)
    except Exception:  # an unknown provider: let the first call say what is wrong
        return []
    return [k for k in found.get("missing_keys", []) if k.endswith(("_KEY", "_TOKEN"))]


def fallback_notes(asset_dir: Path) -> list[str]:
    """'<stage> attempt <n> <role>: the rule backend stood in for <model> (<reason>)', one per fallback recorded in
    evidence/attempts.jsonl."""
    path = Path(asset_dir) / "evidence" / "attempts.jsonl"
    notes: list[str] = []
    if not path.is_file():
        return notes
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.strip():
            continue
        attempt = json.loads(line)
        for key, role in (("planner_source", "planner"), ("source", "designer"), ("critic_source", "critic")):
            src = attempt.get(key) or {}
            if src.get("backend") == "fallback_rule":
                reason = brief(src.get("fallback_reason") or "no reason recorded", 240)
                note = (f"{attempt.get('stage')} attempt {attempt.get('iteration')} {role}: the rule backend stood in "
                        f"for litellm/{src.get('model')} ({reason})")
                if note not in notes:
                    notes.append(note)
    return notes


def l0_designer_stand_in(agents: AgentConfig) -> str | None:
    """When L0's shape Designer's model has no credentials in the environment: the fallback note (the offline grammar
    stands in; L0 is keyed as offline), or LLMUnavailable under --llm-fallback fail. None when it can be asked."""
    model = str(agents.designer.model)
    missing = missing_credentials(model)
    if not missing:
        return None
    reason = f"no credentials for {model}: {', '.join(missing)} not set"
    if agents.designer.on_failure == "fail":
        raise LLMUnavailable(f"L0 designer: {reason} (--llm-fallback fail)")
    UNAVAILABLE[model] = reason
    announce(f"the offline rule backend stands in for litellm/{model} at L0 shape_designer: {reason}")
    return f"L0 designer: the offline grammar stood in for litellm/{model} ({reason})"
