"""litellm roles: validation, errors fed back, timeouts, failure policies (litellm mock responses, no network)."""

from __future__ import annotations

import json
import os
from typing import Any

import pytest
from harness_fakes import FakeL2Probes, l2_targets

os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
import litellm  # noqa: E402

from contracts.agents import AgentConfig, DesignerRequest, RoleConfig  # noqa: E402
from tasks.agents.backend import AgentError  # noqa: E402
from tasks.agents.llm import LLMDesigner, extract_json  # noqa: E402
from tasks.agents.orchestrator import run_stage  # noqa: E402
from tasks.agents.roles import build_roles  # noqa: E402

STRUCTURED = "openai/gpt-4o-mini"  # litellm says it supports JSON-schema output
PLAIN = "ollama/llama3"            # no response schema: JSON is extracted from the text


class MockCompletion:
    """Calls the real litellm.completion with scripted mock responses; records the kwargs of every call."""

    def __init__(self, responses: list[Any]) -> None:
        self.responses = list(responses)
        self.calls: list[dict[str, Any]] = []

    def __call__(self, **kwargs: Any) -> Any:
        self.calls.append(kwargs)
        return litellm.completion(**kwargs, mock_response=self.responses.pop(0))


def _designer_request(l2, budget_left: int = 9) -> DesignerRequest:  # noqa: ANN001
    fields = [f for f in l2.editable_fields if f.name == "youngs_modulus_pa"]
    return DesignerRequest(stage="L2", action="revise_stiffness", fields=fields,
                           current_values={"youngs_modulus_pa": 3e4, "poisson_ratio": 0.3, "damping_rate_per_s": 5.0},
                           targets=l2_targets(5e4), budget_left=budget_left)


def _timeout() -> Exception:
    return litellm.Timeout(message="mock timeout", model=STRUCTURED, llm_provider="openai")


def test_valid_structured_answer_records_tokens_and_cost(l2) -> None:
    mock = MockCompletion(['{"values": {"youngs_modulus_pa": 48000}, "rationale": "log-space step"}'])
    reply = LLMDesigner(RoleConfig(backend="litellm", model=STRUCTURED, timeout_s=7), mock).design(_designer_request(l2))
    assert reply.value.values == {"youngs_modulus_pa": 48000}
    assert reply.source.backend == "litellm" and reply.source.model == STRUCTURED
    assert reply.source.prompt_tokens > 0 and reply.source.completion_tokens > 0 and reply.source.cost_usd > 0
    assert mock.calls[0]["response_format"].__name__ == "Candidate" and mock.calls[0]["timeout"] == 7
    assert "youngs_modulus_pa" in mock.calls[0]["messages"][1]["content"]  # the request and schema are in the prompt


def test_plain_model_answer_is_extracted_from_prose(l2) -> None:
    text = 'Sure! Here is my proposal:\n```json\n{"values": {"youngs_modulus_pa": 52000}}\n```\nHope it helps.'
    mock = MockCompletion([text])
    reply = LLMDesigner(RoleConfig(backend="litellm", model=PLAIN), mock).design(_designer_request(l2))
    assert reply.value.values == {"youngs_modulus_pa": 52000} and "response_format" not in mock.calls[0]
    assert extract_json('noise {"a": {"b": 1}} tail') == '{"a": {"b": 1}}'


@pytest.mark.parametrize("bad, expected", [
    ('{"values": {"youngs_modulus_pa": "fifty kPa"}}', "schema validation failed"),       # malformed value
    ("I think the modulus should be a bit higher.", "no JSON object found"),               # prose only
    ('{"values": {"youngs_modulus_pa": 5e9}}', "outside [1000, 1e+07]"),                   # out of bounds
    ('{"values": {"poisson_ratio": 0.3}}', "not editable under action 'revise_stiffness'"),  # wrong field
])
def test_invalid_answer_is_fed_back_then_corrected(l2, bad: str, expected: str) -> None:
    mock = MockCompletion([bad, '{"values": {"youngs_modulus_pa": 45000}}'])
    reply = LLMDesigner(RoleConfig(backend="litellm", model=STRUCTURED), mock).design(_designer_request(l2))
    assert reply.value.values == {"youngs_modulus_pa": 45000}
    assert reply.source.retries == 1 and expected in reply.source.errors[0]
    assert len(reply.invalid) == 1 and expected in reply.invalid[0].error
    second = mock.calls[1]["messages"]
    assert second[-2] == {"role": "assistant", "content": bad}
    assert expected in second[-1]["content"]  # the validation error was fed back


def test_timeout_is_retried(l2) -> None:
    mock = MockCompletion([_timeout(), '{"values": {"youngs_modulus_pa": 45000}}'])
    reply = LLMDesigner(RoleConfig(backend="litellm", model=STRUCTURED, timeout_s=3), mock).design(_designer_request(l2))
    assert reply.value is not None and reply.source.errors == ["timed out after 3 s"]
    assert "timed out" in mock.calls[1]["messages"][-1]["content"]


def test_repeated_failure_with_fail_policy_raises(l2) -> None:
    mock = MockCompletion(["prose", _timeout(), '{"values": {"youngs_modulus_pa": -1}}'])
    cfg = RoleConfig(backend="litellm", model=STRUCTURED, max_answers=3, on_failure="fail")
    with pytest.raises(AgentError, match=r"designer \(openai/gpt-4o-mini\) gave no valid answer"):
        LLMDesigner(cfg, mock).design(_designer_request(l2))
    assert len(mock.calls) == 3


def test_repeated_failure_with_fallback_policy_uses_rule_and_says_so(l2) -> None:
    mock = MockCompletion(["prose", "more prose"])
    cfg = RoleConfig(backend="litellm", model=PLAIN, max_answers=2, on_failure="fallback_rule")
    req = _designer_request(l2)
    reply = LLMDesigner(cfg, mock).design(req)
    assert reply.source.backend == "fallback_rule" and reply.source.model == PLAIN
    assert reply.source.retries == 2 and "no JSON object" in reply.source.fallback_reason
    assert set(reply.value.values) <= {"youngs_modulus_pa"}


def test_exception_mock_counts_as_failure(l2) -> None:
    mock = MockCompletion([Exception("provider down"), Exception("provider down")])
    cfg = RoleConfig(backend="litellm", model=STRUCTURED, max_answers=2, on_failure="fallback_rule")
    reply = LLMDesigner(cfg, mock).design(_designer_request(l2))
    assert reply.source.backend == "fallback_rule" and "provider down" in reply.source.errors[0]


def test_full_loop_with_llm_roles_charges_invalid_answers_and_records_sources(l2) -> None:
    """Planner, Designer and Critic all by one (mock) model; one invalid designer answer costs one attempt."""
    crit_accept = json.dumps({"verdict": "accept", "diagnosis": "none", "rationale": "in band"})
    crit_revise = json.dumps({"verdict": "revise", "diagnosis": "material",
                              "directions": {"youngs_modulus_pa": "increase"}, "rationale": "too soft"})
    e_good = 5.0e4 / 1.0  # fake modulus at 5e4 Pa is within +-10% of 5e4
    mock = MockCompletion([
        '{"action": "propose_material", "rationale": "start"}',
        '{"values": {"youngs_modulus_pa": 20000, "poisson_ratio": 0.3, "damping_rate_per_s": 16.6}}',
        crit_revise,
        '{"action": "revise_stiffness", "rationale": "stiffer"}',
        '{"values": {"youngs_modulus_pa": 5e12}}',                 # out of bounds: rejected, charged
        f'{{"values": {{"youngs_modulus_pa": {e_good}}}}}',
        crit_accept,
    ])
    probes = FakeL2Probes()
    out = run_stage(l2, probes, l2_targets(5e4), roles=build_roles(AgentConfig.llm(STRUCTURED, on_failure="fail"), mock))
    assert [a.verdict for a in out.attempts] == ["best_so_far", "rejected", "accepted"]
    assert out.attempts[1].source.backend == "litellm" and "outside" in out.attempts[1].rejected_before_probe
    assert out.attempts[2].source.retries == 1 and out.attempts[2].critic_source.backend == "litellm"
    assert out.attempts[2].planner_source.model == STRUCTURED
    assert len(probes.calls) == 2 and not mock.responses
