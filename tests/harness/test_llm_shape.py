"""L0's LLM shape Designer and vision Critic (litellm mock responses, no network): validation against the L0
contract's bounds, errors fed back at the cost of budget, a revision round, the recorded, loud offline fallback."""

from __future__ import annotations

import base64
import copy
import io
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
import imageio.v3 as iio  # noqa: E402
import litellm  # noqa: E402

from contracts.agents import AgentConfig  # noqa: E402
from contracts.request import AssetRequest  # noqa: E402
from contracts.stage import load_contract  # noqa: E402
from tasks.geometry import pipeline, sources  # noqa: E402

VISION = "openai/gpt-4o-mini"  # litellm: supports vision
PLAIN = "ollama/llama3"        # litellm: no vision (no Critic), JSON extracted from text
REPO = Path(__file__).resolve().parents[2]
BLUE, GREY = [0.05, 0.15, 0.8], [0.5, 0.5, 0.5]
WHALE: dict[str, Any] = {"name": "blue plush whale", "category": "plush_animal", "parts": [
    {"name": "body", "primitive": {"kind": "ellipsoid", "radii_m": [0.15, 0.08, 0.07]}, "color_rgb": BLUE},
    {"name": "tail fluke", "primitive": {"kind": "ellipsoid", "radii_m": [0.03, 0.07, 0.012]},
     "transform": {"translation_m": [-0.16, 0.0, 0.03]}, "blend_m": 0.01, "color_rgb": BLUE},
]}


def _whale(**changes: Any) -> str:
    prog = copy.deepcopy(WHALE)
    for path, value in changes.items():
        node = prog
        *keys, last = path.split(".")
        for k in keys:
            node = node[int(k)] if k.isdigit() else node[k]
        node[last] = value
    return json.dumps(prog)


class MockCompletion:
    """Stands in for litellm.completion: the real function with scripted mock responses; records every call."""

    def __init__(self, responses: list[Any]) -> None:
        self.responses = list(responses)
        self.calls: list[dict[str, Any]] = []
        self.real = litellm.completion

    def __call__(self, **kwargs: Any) -> Any:
        self.calls.append(kwargs)
        return self.real(**kwargs, mock_response=self.responses.pop(0))


@pytest.fixture
def script(monkeypatch: pytest.MonkeyPatch):  # noqa: ANN201
    """script(responses) -> the MockCompletion that litellm.completion now is."""
    def install(responses: list[Any]) -> MockCompletion:
        mock = MockCompletion(responses)
        monkeypatch.setattr(litellm, "completion", mock)
        return mock
    return install


def _settings(model: str) -> pipeline.L0Settings:
    cfg = AgentConfig.llm(model)
    return pipeline.settings_from_contract("draft", coacd_overrides={"method": "hull"}).model_copy(
        update={"designer": cfg.designer, "critic": cfg.critic})


def _build(text: str, model: str = PLAIN) -> tuple[dict, pipeline.BuildInfo]:
    return sources.build_mesh(AssetRequest(text=text), _settings(model))


def test_valid_program_is_accepted_meshed_sized_and_gated(script) -> None:  # noqa: ANN001
    mock = script([_whale()])
    mesh, info = _build("a blue plush whale, 40 cm long")
    m = pipeline.arrays_to_mesh(mesh)
    assert m.is_watertight and m.extents[0] == pytest.approx(0.40, rel=0.01)  # the stated length binds x
    assert m.extents[1] / m.extents[0] == pytest.approx(0.16 / 0.34, rel=0.1)  # the model's proportions kept
    rgb = np.asarray(m.visual.vertex_colors)[:, :3].astype(float).mean(axis=0)
    assert rgb[2] > 150 and rgb[0] < 100  # the program's blue
    assert info.generator == f"litellm/{PLAIN}" and info.program is not None and len(info.program.parts) == 2
    assert [a.verdict for a in info.design_attempts] == ["accepted"]
    assert info.design_attempts[0].proposal["program"]["name"] == "blue plush whale"
    prompt = mock.calls[0]["messages"][1]["content"]
    assert "superellipsoid" in prompt and "a blue plush whale, 40 cm long" in prompt  # schema and request
    assert '"max_parts":24' in prompt and "40 cm long" in prompt  # the contract's bounds, the stated size
    proxy = pipeline.build_proxy(mesh, _settings(PLAIN).coacd)
    particles = pipeline.build_particles(mesh, _settings(PLAIN).particles)
    gaussians = pipeline.build_gaussians(mesh, particles, _settings(PLAIN))
    assert pipeline.check_geometry(mesh, proxy, particles, gaussians).passed


@pytest.mark.parametrize("bad, expected", [
    ('{"name": "whale", "category": "plush_animal", "parts": [{"name": "body", ', "no JSON object found"),
    (_whale(**{"parts.0.primitive.kind": "sphere"}), "schema validation failed"),
    (_whale(**{"parts.1.primitive.radii_m": [5.0, 0.07, 0.012]}), "radii_m[0] = 5 m is outside [0.002, 2] m"),
    (_whale(**{"parts.1.transform.translation_m": [-0.6, 0.0, 0.03]}), "detached parts: 1 'tail fluke'"),
    (_whale(**{"parts.0.operation": "subtract"}), "the first part must be a union"),
])
def test_invalid_answer_is_fed_back_costs_an_attempt_then_fixed(script, bad: str,  # noqa: ANN001
                                                                 expected: str) -> None:
    mock = script([bad, _whale()])
    _, info = _build("a blue plush whale")
    assert [a.verdict for a in info.design_attempts] == ["rejected", "accepted"]
    assert expected in info.design_attempts[0].rejected_before_probe
    assert info.design_attempts[0].proposal["answer"] == bad
    assert info.design_attempts[1].source.retries == 1 and info.generator == f"litellm/{PLAIN}"
    second = mock.calls[1]["messages"]
    assert second[-2] == {"role": "assistant", "content": bad} and expected in second[-1]["content"]


def _views(call: dict[str, Any]) -> list[np.ndarray]:
    parts = call["messages"][1]["content"]
    urls = [p["image_url"]["url"] for p in parts if p["type"] == "image_url"]
    return [iio.imread(io.BytesIO(base64.b64decode(u.split(",", 1)[1]))) for u in urls]


def test_vision_critic_asks_for_one_revision_then_accepts(script) -> None:  # noqa: ANN001
    no_tail = json.dumps({**WHALE, "parts": WHALE["parts"][:1]})
    revise = json.dumps({"verdict": "revise", "problems": ["the tail fluke is missing"],
                         "rationale": "a whale has one"})
    accept = json.dumps({"verdict": "accept", "rationale": "a blue whale with its fluke"})
    mock = script([no_tail, revise, _whale(), accept])
    mesh, info = _build("a blue plush whale", model=VISION)
    assert [a.verdict for a in info.design_attempts] == ["revise", "accepted"]
    first, second = info.design_attempts
    assert "the tail fluke is missing" in first.critique and first.critic_source.model == VISION
    assert second.parent_iteration == 0 and second.critic_source.backend == "litellm"
    assert len(info.program.parts) == 2  # the revision was kept
    views = _views(mock.calls[1])  # the Critic saw front, side, top and iso renders of the meshed draft
    assert len(views) == 4 and all(v.shape == (256, 256, 3) for v in views)
    assert all((v < 250).any(axis=2).mean() > 0.1 for v in views)  # the object is in each picture
    assert "a blue plush whale" in mock.calls[1]["messages"][1]["content"][0]["text"]
    redo = json.loads(mock.calls[2]["messages"][1]["content"].split("Request:\n", 1)[1])
    assert redo["critique"].startswith("the tail fluke is missing") and redo["previous"]["name"] == "blue plush whale"
    assert redo["budget_left"] == load_contract("L0").revision_budget  # the draft cost one attempt
    assert not mock.responses


def test_a_failed_revision_keeps_the_draft_the_critic_judged(script) -> None:  # noqa: ANN001
    no_tail = json.dumps({**WHALE, "parts": WHALE["parts"][:1]})
    revise = json.dumps({"verdict": "revise", "problems": ["the tail fluke is missing"]})
    left = load_contract("L0").revision_budget  # the draft cost one attempt
    mock = script([no_tail, revise] + ["a whale with a tail"] * left)
    _, info = _build("a blue plush whale", model=VISION)
    assert [a.verdict for a in info.design_attempts] == ["best_so_far"] + ["rejected"] * left
    assert len(info.program.parts) == 1 and info.generator == f"litellm/{VISION}" and not mock.responses
    assert any("revision gave no valid program" in w for w in info.warnings)


def test_budget_exhausted_falls_back_to_the_offline_grammar_loudly(script) -> None:  # noqa: ANN001
    budget = 1 + load_contract("L0").revision_budget
    mock = script(["I would make a whale."] * budget)
    mesh, info = _build("a blue plush whale")
    offline_mesh, offline = pipeline.mesh_from_text(AssetRequest(text="a blue plush whale"), _settings(PLAIN))
    assert len(mock.calls) == budget
    np.testing.assert_array_equal(mesh["vertices"], offline_mesh["vertices"])  # the offline build, unchanged
    assert info.generator == "offline" and info.entry == offline.entry
    assert any(f"LLM Designer (litellm/{PLAIN}) gave no valid shape program" in w for w in info.warnings)
    verdicts = [a.verdict for a in info.design_attempts]
    assert verdicts == ["rejected"] * budget + ["accepted"]
    last = info.design_attempts[-1]
    assert last.source.backend == "fallback_rule" and "no JSON object" in last.source.fallback_reason
    concept = getattr(info, "concept", None)
    if concept is not None:  # the lexicon's concept record says so too
        assert "offline grammar" in concept.fallback_note


@pytest.mark.parametrize("error", [
    litellm.APIConnectionError(message="Connection refused", llm_provider="ollama", model=PLAIN),
    litellm.AuthenticationError(message="no API key", llm_provider="ollama", model=PLAIN),
])
def test_unreachable_or_refused_model_stops_at_once(script, error: Exception) -> None:  # noqa: ANN001
    mock = script([error, _whale()])
    _, info = _build("a blue plush whale")
    assert len(mock.calls) == 1 and info.generator == "offline"
    assert type(error).__name__ in info.design_attempts[-1].source.fallback_reason


def test_attempts_are_written_as_l0_evidence(script, tmp_path: Path) -> None:  # noqa: ANN001
    from flows.l0_geometry import run_l0, write_l0
    from tasks.agents.records import read_attempts

    script(['{"name": "whale"}', _whale()])
    result = run_l0(AssetRequest(text="a blue plush whale"), "draft", use_cache=False,
                    coacd_overrides={"method": "hull"}, agents=AgentConfig.llm(PLAIN))
    assert result.checks.passed
    write_l0(result, tmp_path / "whale")
    attempts = read_attempts(tmp_path / "whale" / "evidence" / "attempts.jsonl")
    assert [(a.stage, a.verdict) for a in attempts] == [("L0", "rejected"), ("L0", "accepted")]
    assert attempts[1].source.model == PLAIN and attempts[1].proposal["program"]["name"] == "blue plush whale"
    record = json.loads((tmp_path / "whale" / "geometry.json").read_text())
    assert record["info"]["generator"] == f"litellm/{PLAIN}" and "design_attempts" not in record["info"]
    assert (tmp_path / "whale" / "recordings" / "harness_L0.rrd").is_file()


def test_designer_model_keys_the_cache_and_only_text_requests_use_it(monkeypatch: pytest.MonkeyPatch) -> None:
    import flows.l0_geometry as l0
    from cache import content_key

    seen = []
    monkeypatch.setenv("OPENAI_API_KEY", "sk-test")  # VISION is an OpenAI model: with its key it is asked
    monkeypatch.setattr(l0, "l0_geometry", lambda request, settings, contract: seen.append(settings))
    monkeypatch.setattr(l0.cache, "local_runtime", lambda: __import__("contextlib").nullcontext())
    l0.run_l0(AssetRequest(text="a whale"), "draft")
    l0.run_l0(AssetRequest(text="a whale"), "draft", agents=AgentConfig.llm(PLAIN))
    l0.run_l0(AssetRequest(text="a whale"), "draft", agents=AgentConfig.llm(VISION))
    l0.run_l0(AssetRequest(text="a whale", geometry_backend="tests.geometry.fake_backend:icosphere"), "draft",
              agents=AgentConfig.llm(VISION))
    assert [s.designer.model if s.designer else None for s in seen] == [None, PLAIN, VISION, None]
    assert len({content_key(s) for s in seen}) == 3  # no model and a backend request share the offline settings


def test_a_model_without_credentials_is_not_asked_and_l0_is_keyed_offline(monkeypatch: pytest.MonkeyPatch,
                                                                          capsys: pytest.CaptureFixture) -> None:
    """No OPENAI_API_KEY: the offline build is made under the offline key (a later run with the key is not served
    the fallback from the cache), the console and the record say so; --llm-fallback fail refuses instead."""
    import flows.l0_geometry as l0
    from tasks.agents import fallbacks
    from tasks.geometry.pipeline import BuildInfo

    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    fallbacks.reset()
    seen = []

    def fake(request, settings, contract):  # noqa: ANN001, ANN202
        seen.append(settings)
        return l0.L0Result({}, {}, {}, {}, BuildInfo(source="text", name="whale", category="plush_animal"), None)

    monkeypatch.setattr(l0, "l0_geometry", fake)
    monkeypatch.setattr(l0.cache, "local_runtime", lambda: __import__("contextlib").nullcontext())
    result = l0.run_l0(AssetRequest(text="a whale"), "draft", agents=AgentConfig.llm(VISION))
    assert seen[0].designer is None  # the offline settings, hence the offline cache key
    assert any("OPENAI_API_KEY not set" in w and VISION in w for w in result.info.warnings)
    assert f"stands in for litellm/{VISION} at L0 shape_designer" in capsys.readouterr().err
    assert VISION in fallbacks.UNAVAILABLE  # later stages do not ask it either
    fallbacks.reset()
    strict = AgentConfig.llm(VISION, on_failure="fail")
    with pytest.raises(fallbacks.LLMUnavailable, match="OPENAI_API_KEY"):
        l0.run_l0(AssetRequest(text="a whale"), "draft", agents=strict)
    fallbacks.reset()


def test_cli_with_an_unreachable_model_says_it_fell_back(tmp_path: Path, cli_env: dict[str, str]) -> None:
    """A real litellm call to a local Ollama that is not running: one connection error, the offline build, a warning.
    (The command in this process, which has litellm imported already: a subprocess spent ~10 s importing it.)"""
    from typer.testing import CliRunner

    from flows.cli.main import app

    env = {**cli_env, "OLLAMA_API_BASE": "http://127.0.0.1:9"}
    res = CliRunner().invoke(app, ["geometry", "a tofu block 10 x 7 x 4 cm", "--out", str(tmp_path / "t"),
                                   "--no-cache", "--llm", PLAIN], env=env)
    assert res.exit_code == 0, res.output
    assert f"LLM Designer (litellm/{PLAIN}) gave no valid shape program (APIConnectionError" in \
        " ".join(res.stderr.split())
    record = json.loads((tmp_path / "t" / "geometry.json").read_text())
    assert record["info"]["generator"] == "offline" and record["passed"]
    assert (tmp_path / "t" / "evidence" / "attempts.jsonl").is_file()
