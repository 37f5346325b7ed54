"""Build the three roles from an AgentConfig (rule or litellm per role)."""

from __future__ import annotations

from contracts.agents import AgentConfig
from tasks.agents.orchestrator import Roles
from tasks.agents.rule import RuleCritic, RuleDesigner, RulePlanner
from tasks.agents.vocab import StageRoutes


def build_roles(config: AgentConfig | None = None, completion=None, routes: StageRoutes | None = None) -> Roles:  # noqa: ANN001
    """Roles per the config; litellm is imported only when a role uses it. completion: injectable litellm.completion."""
    config = config or AgentConfig()
    if all(c.backend == "rule" for c in (config.planner, config.designer, config.critic)):
        return Roles.rule(routes)
    # lazy: tasks.agents.llm pulls litellm (~10 s), only for an LLM backend
    from tasks.agents.llm import LLMCritic, LLMDesigner, LLMPlanner

    return Roles(
        planner=LLMPlanner(config.planner, completion, routes) if config.planner.backend == "litellm" else RulePlanner(routes),
        designer=LLMDesigner(config.designer, completion, routes) if config.designer.backend == "litellm" else RuleDesigner(routes),
        critic=LLMCritic(config.critic, completion, routes) if config.critic.backend == "litellm" else RuleCritic(routes),
    )
