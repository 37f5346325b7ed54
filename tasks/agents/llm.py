"""litellm backend: any model string plays any role; answers are validated, errors fed back, failures handled by policy."""

from __future__ import annotations

import base64
import json
import re
import socket
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from cache.dont_store import dont_store
from contracts.agents import (
    Candidate, Critique, CriticRequest, DesignerRequest, PlannerContext, PlannerDecision, RoleConfig,
)
from contracts.evidence import AgentSource
from contracts.errors import validation_message
from tasks.agents.litellm_client import litellm  # (configured there: no network at import)
from tasks.agents.backend import (
    AgentError, InvalidAnswer, RoleReply, check_candidate, check_critique, check_decision,
)
from tasks.agents import fallbacks
from tasks.agents.prompts import load_prompt
from tasks.agents.rule import RuleCritic, RuleDesigner, RulePlanner
from tasks.agents.vocab import StageRoutes

_LITELLM_COMPLETION = litellm.completion  # models found unusable are remembered only for real calls, not test mocks
M = TypeVar("M", bound=BaseModel)
Completion = Callable[..., Any]
# errors after which asking again cannot help: go straight to the failure policy (an unreachable server will not
# answer the next time either)
FATAL_ERRORS: tuple[type[Exception], ...] = (
    litellm.AuthenticationError, litellm.NotFoundError, litellm.BadRequestError, litellm.PermissionDeniedError,
    litellm.APIConnectionError,
)
# errors that make the model unusable for the rest of the run (no key, no such model, no server): every later call
# goes straight to the failure policy, without asking
UNAVAILABLE_ERRORS: tuple[type[Exception], ...] = (
    litellm.AuthenticationError, litellm.NotFoundError, litellm.PermissionDeniedError, litellm.APIConnectionError,
)


_NO_CREDENTIALS = re.compile(r"missing credentials|api[_ ]key (must|is not|was not|not) (be )?(set|provided|found)|"
                             r"no api[_ ]key|(invalid|incorrect) api[_ ]key", re.IGNORECASE)


def is_unusable(exc: BaseException) -> bool:
    """True for an error after which the model cannot answer this run: no credentials, no server (refused, unknown
    host), no such model. litellm reports some of these as InternalServerError: its causes are searched too."""
    seen: BaseException | None = exc
    for _ in range(12):
        if seen is None:
            return False
        if isinstance(seen, litellm.Timeout) or "Timeout" in type(seen).__name__:
            return False  # a slow server may answer the next time
        if isinstance(seen, (*UNAVAILABLE_ERRORS, ConnectionRefusedError, socket.gaierror)) \
                or type(seen).__name__ in ("APIConnectionError", "ConnectError") or _NO_CREDENTIALS.search(str(seen)):
            return True
        seen = seen.__cause__ or seen.__context__
    return False


def extract_json(text: str) -> str:
    """The first JSON object in an answer: a ```json fence, else the first parseable {...}."""
    if m := re.search(r"```(?:json)?\s*(\{.*?\})\s*```", text, re.DOTALL):
        return m.group(1)
    decoder = json.JSONDecoder()
    for i, ch in enumerate(text):
        if ch == "{":
            try:
                _, end = decoder.raw_decode(text[i:])
            except json.JSONDecodeError:
                continue
            return text[i:i + end]
    raise ValueError("no JSON object found in the answer")


def _validation_message(exc: ValidationError) -> str:
    return "schema validation failed: " + validation_message(exc, limit=8)


def _parse(text: str | None, out_type: type[M]) -> M:
    """Validate an answer against the schema (JSON extraction from prose-wrapped answers)."""
    if not text or not text.strip():
        raise ValueError("empty answer")
    try:
        return out_type.model_validate_json(extract_json(text))
    except ValidationError as exc:
        raise ValueError(_validation_message(exc)) from None


def _cost(response: Any) -> float:
    try:
        return float(litellm.completion_cost(completion_response=response) or 0.0)
    except Exception:  # unknown models (local ollama) have no price
        return 0.0


def ask(
    role: str,
    cfg: RoleConfig,
    request: BaseModel,
    out_type: type[M],
    check: Callable[[M], str | None],
    fallback: Callable[[], RoleReply[M]],
    completion: Completion | None = None,
    max_answers: int | None = None,
    images: Sequence[bytes] = (),
    fatal_errors: tuple[type[Exception], ...] = FATAL_ERRORS,
    structured: bool | None = None,
) -> RoleReply[M]:
    """Ask a model for a schema-valid, contract-valid answer; feed each error back; then apply cfg.on_failure.

    images: PNG bytes attached to the request (vision models); fatal_errors: errors that end the asking at once;
    structured: ask for schema-constrained output (default: when litellm says the model supports it)."""
    model = str(cfg.model)
    where = f"{getattr(request, 'stage', None) or 'L0'} {role}"
    if completion is None and litellm.completion is _LITELLM_COMPLETION and model in fallbacks.UNAVAILABLE:
        # found unusable earlier in this run: do not ask again
        return _give_up(role, cfg, where, fallbacks.UNAVAILABLE[model], [], [], fallback, 0, 0, 0.0, unusable=True)
    completion = completion or litellm.completion
    prompt = load_prompt(role)
    schema = json.dumps(out_type.model_json_schema(), separators=(",", ":"))
    text = f"{prompt['instructions']}\n{schema}\n\nRequest:\n{request.model_dump_json()}"
    content: Any = text if not images else [{"type": "text", "text": text}, *(
        {"type": "image_url", "image_url": {"url": "data:image/png;base64," + base64.b64encode(png).decode()}}
        for png in images)]
    messages: list[dict[str, Any]] = [
        {"role": "system", "content": prompt["system"]},
        {"role": "user", "content": content},
    ]
    structured = _supports_schema(model) if structured is None else structured
    tokens_in = tokens_out = 0
    cost = 0.0
    invalid: list[InvalidAnswer] = []  # answers the model gave that failed validation: each costs the stage budget
    transport: list[str] = []  # calls that got no answer (no key, no server, timeouts): cost nothing
    fatal: str | None = None
    error: str | None = None
    unusable = False
    for _ in range(max(1, max_answers or cfg.max_answers)):
        kwargs: dict[str, Any] = {"model": model, "messages": list(messages), "timeout": cfg.timeout_s,
                                  "temperature": cfg.temperature}
        if structured:
            kwargs["response_format"] = out_type
        try:
            response = completion(**kwargs)
        except litellm.Timeout:
            error = f"timed out after {cfg.timeout_s:g} s"
            transport.append(error)
            messages.append({"role": "user", "content": f"The previous request {error}. Answer again, briefly, JSON only."})
            continue
        except Exception as exc:
            error = f"{type(exc).__name__}: {str(exc)[:300]}"
            transport.append(error)
            unusable = is_unusable(exc)
            if not unusable and not isinstance(exc, fatal_errors):
                continue  # rate limits, outages, provider 5xx: worth asking again
            fatal = error
            if unusable and completion is _LITELLM_COMPLETION:
                fallbacks.UNAVAILABLE[model] = f"{fatal} (first met at {where})"
            break
        usage = getattr(response, "usage", None)
        tokens_in += int(getattr(usage, "prompt_tokens", 0) or 0)
        tokens_out += int(getattr(usage, "completion_tokens", 0) or 0)
        cost += _cost(response)
        text = response.choices[0].message.content or ""
        value: M | None = None
        try:
            value = _parse(text, out_type)
            error = check(value)
        except ValueError as exc:
            error = str(exc)
        if error is None and value is not None:
            source = AgentSource(backend="litellm", model=model, prompt_tokens=tokens_in, completion_tokens=tokens_out,
                                 cost_usd=cost, retries=len(invalid), errors=[*transport, *(i.error for i in invalid)])
            return RoleReply(value, source, invalid)
        values = dict(value.values) if isinstance(value, Candidate) else None
        invalid.append(InvalidAnswer(text=text, error=error or "invalid answer", values=values))
        messages.append({"role": "assistant", "content": text})
        messages.append({"role": "user", "content": f"Your answer was rejected: {error}. "
                                                    "Reply again with ONE corrected JSON object only."})
    errors = [*transport, *(i.error for i in invalid)]
    reason = fatal or f"{len(invalid)} invalid answer(s); last: {errors[-1] if errors else 'none'}"
    if not invalid and transport:
        reason, unusable = fatal or f"no answer ({transport[-1]})", True
    return _give_up(role, cfg, where, reason, errors, invalid, fallback, tokens_in, tokens_out, cost, unusable)


def _give_up(role: str, cfg: RoleConfig, where: str, reason: str, errors: list[str], invalid: list[InvalidAnswer],
             fallback: Callable[[], RoleReply[M]], tokens_in: int, tokens_out: int, cost: float,
             unusable: bool) -> RoleReply[M]:
    """cfg.on_failure: raise (LLMUnavailable when no answer came at all), or let the rule backend answer, saying so."""
    model = str(cfg.model)
    if cfg.on_failure == "fail":
        if unusable:
            raise fallbacks.LLMUnavailable(f"the LLM litellm/{model} is not usable ({reason}) at {where}; "
                                           "nothing published (--llm-fallback rule lets the offline rule backend "
                                           "stand in)")
        raise AgentError(f"{role} ({model}) gave no valid answer: {reason}")
    fallbacks.announce(f"the offline rule backend stands in for litellm/{model} at {where}: {fallbacks.brief(reason)}")
    dont_store()  # inside a cached task: the stand-in is not kept under the LLM's key
    reply = fallback()
    source = AgentSource(backend="fallback_rule", model=model, prompt_tokens=tokens_in, completion_tokens=tokens_out,
                         cost_usd=cost, retries=len(invalid), errors=errors, fallback_reason=f"{reason} (at {where})")
    return RoleReply(reply.value, source, invalid)


def _supports_schema(model: str) -> bool:
    try:
        return bool(litellm.supports_response_schema(model=model))
    except Exception:
        return False


class LLMPlanner:
    """Planner played by a litellm model."""

    def __init__(self, cfg: RoleConfig, completion: Completion | None = None, routes: StageRoutes | None = None) -> None:
        self.cfg, self.completion, self.rule = cfg, completion, RulePlanner(routes)

    def plan(self, ctx: PlannerContext) -> RoleReply[PlannerDecision]:
        """Ask for a permitted action."""
        return ask("planner", self.cfg, ctx, PlannerDecision, lambda d: check_decision(ctx, d),
                   lambda: self.rule.plan(ctx), self.completion)


class LLMDesigner:
    """Designer played by a litellm model; every invalid answer is returned so the orchestrator can charge it."""

    def __init__(self, cfg: RoleConfig, completion: Completion | None = None, routes: StageRoutes | None = None) -> None:
        self.cfg, self.completion, self.rule = cfg, completion, RuleDesigner(routes)

    def design(self, req: DesignerRequest) -> RoleReply[Candidate]:
        """Ask for a candidate inside the action's fields and bounds (at most budget_left - 1 answers)."""
        answers = min(self.cfg.max_answers, max(1, req.budget_left - 1))
        return ask("designer", self.cfg, req, Candidate, lambda c: check_candidate(req, c),
                   lambda: self.rule.design(req), self.completion, max_answers=answers)


class LLMCritic:
    """Critic played by a litellm model."""

    def __init__(self, cfg: RoleConfig, completion: Completion | None = None, routes: StageRoutes | None = None) -> None:
        self.cfg, self.completion, self.rule = cfg, completion, RuleCritic(routes)

    def critique(self, req: CriticRequest) -> RoleReply[Critique]:
        """Ask for a verdict with a diagnosis and directions on editable fields."""
        return ask("critic", self.cfg, req, Critique, lambda c: check_critique(req, c),
                   lambda: self.rule.critique(req), self.completion)
