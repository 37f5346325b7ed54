"""An LLM that is not there (no key, no server): asked once, the rule backend stands in loudly and for free, or
`--llm-fallback fail` stops with one error line. Real litellm calls to places that cannot answer; no network."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from harness_fakes import FakeL2Probes, l2_targets

os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
import litellm  # noqa: E402

from contracts.agents import AgentConfig, DesignerRequest, RoleConfig  # noqa: E402
from tasks.agents import fallbacks  # noqa: E402
from tasks.agents.llm import LLMDesigner, is_unusable  # noqa: E402
from tasks.agents.orchestrator import Roles, run_stage  # noqa: E402
from tasks.agents.roles import build_roles  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
REFUSED = "http://127.0.0.1:9"  # the discard port: connection refused


@pytest.fixture(autouse=True)
def _fresh_fallbacks() -> Iterator[None]:
    fallbacks.reset()
    yield
    fallbacks.reset()


def _designer_request(l2) -> DesignerRequest:  # noqa: ANN001
    fields = [f for f in l2.editable_fields if f.name == "youngs_modulus_pa"]
    return DesignerRequest(stage="L2", action="revise_stiffness", fields=fields,
                           current_values={"youngs_modulus_pa": 3e4, "poisson_ratio": 0.3, "damping_rate_per_s": 5.0},
                           targets=l2_targets(5e4), budget_left=9)


class Unreachable:
    """A completion that always fails like a provider with no key or no server; counts the calls."""

    def __init__(self, error: Exception) -> None:
        self.error, self.calls = error, 0

    def __call__(self, **kwargs: Any) -> Any:
        self.calls += 1
        raise self.error


@pytest.mark.parametrize("model, env", [
    ("openai/gpt-4o", {"OPENAI_API_KEY": None}),                        # no key: litellm says InternalServerError
    ("openai/gpt-4o", {"OPENAI_API_KEY": "sk-test", "OPENAI_BASE_URL": REFUSED, "OPENAI_API_BASE": REFUSED}),
    ("ollama/llama3", {"OLLAMA_API_BASE": REFUSED}),                     # a local server that is not running
])
def test_missing_key_or_server_is_asked_once_then_never_again(l2, model: str, env: dict, monkeypatch,  # noqa: ANN001
                                                              capsys) -> None:  # noqa: ANN001
    for k, v in env.items():
        monkeypatch.delenv(k, raising=False) if v is None else monkeypatch.setenv(k, v)
    designer = LLMDesigner(RoleConfig(backend="litellm", model=model, max_answers=3, on_failure="fallback_rule"))
    t0 = time.perf_counter()
    reply = designer.design(_designer_request(l2))
    first_s = time.perf_counter() - t0
    assert reply.invalid == []  # no answer came: nothing to charge to the stage's budget
    assert reply.source.backend == "fallback_rule" and reply.value is not None
    assert "(at L2 designer)" in reply.source.fallback_reason and len(reply.source.errors) == 1  # asked once
    err = capsys.readouterr().err
    assert err.startswith(f"warning: the offline rule backend stands in for litellm/{model} at L2 designer: ")
    t0 = time.perf_counter()
    again = designer.design(_designer_request(l2))  # the model is known unusable: not asked again
    assert "first met at L2 designer" in again.source.fallback_reason and again.source.errors == []
    assert time.perf_counter() - t0 < 0.5 and first_s < 20


def test_fallback_costs_no_budget_and_is_recorded_in_the_evidence(l2, tmp_path: Path) -> None:  # noqa: ANN001
    """An LLM loop whose model is unreachable runs exactly the rule loop, every attempt saying who stood in."""
    error = litellm.InternalServerError(message="OpenAIException - Missing credentials. Please pass an `api_key`",
                                        llm_provider="openai", model="openai/gpt-4o")
    dead = Unreachable(error)
    llm_out = run_stage(l2, FakeL2Probes(), l2_targets(5e4), roles=build_roles(AgentConfig.llm("openai/gpt-4o"), dead))
    rule_out = run_stage(l2, FakeL2Probes(), l2_targets(5e4), roles=Roles.rule())
    assert rule_out.status == "accepted"
    assert [(a.verdict, a.proposal) for a in llm_out.attempts] == [(a.verdict, a.proposal) for a in rule_out.attempts]
    assert llm_out.status == rule_out.status and llm_out.attempts_used == rule_out.attempts_used
    # each role call asked once (no retries of a dead model), three roles per probed attempt
    assert dead.calls == 3 * len(llm_out.attempts)
    for a in llm_out.attempts:
        for src in (a.source, a.planner_source, a.critic_source):
            assert src.backend == "fallback_rule" and "Missing credentials" in src.fallback_reason
    evidence = tmp_path / "evidence" / "attempts.jsonl"
    evidence.parent.mkdir()
    evidence.write_text("".join(a.model_dump_json() + "\n" for a in llm_out.attempts), encoding="utf-8")
    notes = fallbacks.fallback_notes(tmp_path)
    assert notes[0].startswith("L2 attempt 0 planner: the rule backend stood in for litellm/openai/gpt-4o (")
    assert len(notes) == 3 * len(llm_out.attempts)


def test_fail_policy_stops_with_one_line_exit_2(l2) -> None:  # noqa: ANN001
    dead = Unreachable(litellm.AuthenticationError(message="no API key", llm_provider="openai", model="openai/gpt-4o"))
    designer = LLMDesigner(RoleConfig(backend="litellm", model="openai/gpt-4o", on_failure="fail"), dead)
    with pytest.raises(fallbacks.LLMUnavailable) as info:
        designer.design(_designer_request(l2))
    assert dead.calls == 1 and info.value.exit_code == 2 and "\n" not in str(info.value)
    assert "litellm/openai/gpt-4o is not usable (AuthenticationError" in str(info.value)


def test_retryable_errors_are_not_taken_for_a_missing_model() -> None:
    said = fallbacks.brief("InternalServerError: litellm.InternalServerError: InternalServerError: OpenAIException - "
                           "Missing credentials. Please pass an `api_key`" + " x" * 200)
    assert said.startswith("InternalServerError: OpenAIException - Missing credentials.") and len(said) == 160
    assert not is_unusable(Exception("provider down"))
    assert not is_unusable(litellm.Timeout(message="slow", model="m", llm_provider="openai"))
    assert not is_unusable(litellm.RateLimitError(message="slow down", llm_provider="openai", model="m"))
    assert is_unusable(litellm.APIConnectionError(message="refused", llm_provider="ollama", model="m"))


@pytest.mark.slow  # ~35 s on 2 busy cores (the CLI imports every layer); the policy itself is tested above
def test_cli_fail_policy_publishes_nothing(tmp_path: Path) -> None:
    env = {**os.environ, "OLLAMA_API_BASE": REFUSED}
    out = tmp_path / "tofu"
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "geometry", "a tofu block 10 x 7 x 4 cm", "--out",
                           str(out), "--no-cache", "--llm", "ollama/llama3", "--llm-fallback", "fail"], cwd=REPO,
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 2, proc.stderr[-3000:]
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: the LLM litellm/ollama/llama3 is not usable"), proc.stderr
    assert "--llm-fallback rule" in lines[0]
    assert not out.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_generate_without_a_key_says_the_rule_backend_stood_in(tmp_path: Path) -> None:
    """generate --llm openai/gpt-4o with no key: exit 0, a warning, asset.json and the evidence say where."""
    env = {k: v for k, v in os.environ.items() if k != "OPENAI_API_KEY"}
    out = tmp_path / "duck"
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "generate", "a rubber duck", "--no-l3", "--out",
                           str(out), "--llm", "openai/gpt-4o"], cwd=REPO, capture_output=True, text=True, env=env,
                          timeout=1200)
    assert proc.returncode == 0, proc.stderr[-3000:]
    said = " ".join(proc.stderr.split())
    assert "warning: the offline rule backend stands in for litellm/openai/gpt-4o at L0 shape_designer" in said
    assert "at L1 planner" in said and "at L2 planner" in said
    manifest = json.loads((out / "asset.json").read_text())
    notes = manifest["provenance"]["fallbacks"]
    assert any(n.startswith("L1 attempt 0 planner") for n in notes) and any(n.startswith("L2 ") for n in notes)
    geometry = json.loads((out / "geometry.json").read_text())  # no key: L0's Designer is not asked at all
    assert any("OPENAI_API_KEY not set" in w for w in geometry["info"]["warnings"])
    l1 = [json.loads(ln) for ln in (out / "evidence" / "attempts.jsonl").read_text().splitlines() if '"L1"' in ln]
    assert l1 and all(a["verdict"] != "rejected" for a in l1)  # no attempt charged for the missing model
    assert next(s for s in manifest["validation"] if s["stage"] == "L1")["attempts"] == len(
        [a for a in l1 if a["stage"] == "L1"])
