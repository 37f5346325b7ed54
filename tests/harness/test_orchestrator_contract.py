"""The orchestrator enforces the contract: bad proposals never reach a probe; budget, rollback and failure outcomes."""

from __future__ import annotations

from harness_fakes import HEALTHY, FakeL2Probes, fake_modulus_pa, fake_rebound, l2_targets

from contracts import ProbeResult, ProbeSpec
from contracts.agents import Candidate, DesignerRequest, TargetBand, TargetBehaviour
from contracts.evidence import AgentSource
from tasks.agents.backend import RoleReply
from tasks.agents.orchestrator import Roles, run_stage
from tasks.agents.rule import RuleCritic, RuleDesigner, RulePlanner


class ScriptedDesigner:
    """Returns scripted candidates in order, then defers to the rule designer; remembers every request."""

    def __init__(self, script: list[dict[str, float]]) -> None:
        self.script = list(script)
        self.requests: list[DesignerRequest] = []
        self.rule = RuleDesigner()

    def design(self, req: DesignerRequest) -> RoleReply[Candidate]:
        self.requests.append(req)
        if self.script:
            return RoleReply(Candidate(values=self.script.pop(0), rationale="scripted"), AgentSource(backend="user"))
        return self.rule.design(req)


def _roles(designer) -> Roles:  # noqa: ANN001
    return Roles(RulePlanner(), designer, RuleCritic())


def test_out_of_bounds_and_non_editable_proposals_never_run_a_probe(l2) -> None:
    probes = FakeL2Probes()
    designer = ScriptedDesigner([
        {"youngs_modulus_pa": 1e9},                       # above the contract's 1e7 Pa bound
        {"density_kg_per_m3": 500.0},                     # not an L2 field (L1 owns density)
        {"youngs_modulus_pa": float("nan")},              # not finite
    ])
    out = run_stage(l2, probes, l2_targets(5e4), roles=_roles(designer))
    rejected = [a for a in out.attempts if a.verdict == "rejected"]
    assert [a.iteration for a in rejected] == [0, 1, 2]
    assert "outside [1000, 1e+07]" in rejected[0].rejected_before_probe
    assert "not editable" in rejected[1].rejected_before_probe
    assert "not a finite number" in rejected[2].rejected_before_probe
    assert all(a.evidence.probe_keys == [] and a.gates == [] for a in rejected)
    assert len(probes.calls) == out.attempts_used - 3  # the three rejections ran nothing
    assert all(c["youngs_modulus_pa"] <= 1e7 for c in probes.calls)
    assert designer.requests[1].feedback == rejected[0].rejected_before_probe  # the error is fed back
    assert out.status == "accepted"  # the rejections cost budget, the rest still converges


def test_a_field_of_another_action_is_rejected(l2) -> None:
    """revise_damping may edit only the damping; a modulus change under it is out of contract."""
    probes = FakeL2Probes()
    designer = ScriptedDesigner([])
    out = run_stage(l2, probes, l2_targets(5e4), roles=_roles(designer))
    n = len(probes.calls)

    class Sneaky(ScriptedDesigner):
        def design(self, req: DesignerRequest) -> RoleReply[Candidate]:
            if req.action == "revise_damping":
                return RoleReply(Candidate(values={"youngs_modulus_pa": 2e4}), AgentSource(backend="user"))
            return super().design(req)

    probes2 = FakeL2Probes()
    out2 = run_stage(l2, probes2, l2_targets(5e4), roles=_roles(Sneaky([])))
    bad = [a for a in out2.attempts if a.verdict == "rejected"]
    assert bad and all("not editable under action 'revise_damping'" in a.rejected_before_probe for a in bad)
    assert len(probes2.calls) == out2.attempts_used - len(bad)
    assert out.status == "accepted" and n == out.attempts_used


def test_repeated_candidate_is_rejected_without_probing(l2) -> None:
    probes = FakeL2Probes()
    designer = ScriptedDesigner([{}, {}])  # the second one repeats the first proposal
    out = run_stage(l2, probes, l2_targets(5e4), roles=_roles(designer))
    assert out.attempts[1].verdict == "rejected" and "already probed" in out.attempts[1].rejected_before_probe
    assert len(probes.calls) == out.attempts_used - 1


def test_budget_exhaustion_returns_best_valid_candidate(l2) -> None:
    """A modulus target above the contract's bound cannot be met: the best valid candidate comes back, clearly."""
    out = run_stage(l2.model_copy(update={"revision_budget": 4}), FakeL2Probes(), l2_targets(5e7))
    assert out.status == "best_valid" and out.passed
    assert out.attempts_used <= 5
    assert out.values["youngs_modulus_pa"] == 1e7  # pushed to the bound, the closest allowed
    assert out.score == max(a.score for a in out.attempts if a.score is not None)
    assert "targets not all met" in out.message or "planner stopped" in out.message


def test_no_valid_candidate_is_a_clear_outcome(l2) -> None:
    def always_explodes(values: dict[str, float], action: str) -> list[ProbeResult]:
        return [ProbeResult(spec=ProbeSpec(kind="stability"), metrics={**HEALTHY, "finite": 0.0, "j_max": 40.0})]

    out = run_stage(l2.model_copy(update={"revision_budget": 3}), always_explodes, l2_targets(5e4))
    assert out.status == "no_valid_candidate" and not out.passed and out.values is None
    assert "no valid candidate" in out.message and "finite" in out.message
    assert all(a.verdict in ("revise", "rejected") for a in out.attempts)
    assert out.attempts[0].diagnosis == "numerical"


def test_regression_is_rolled_back(l2) -> None:
    """A valid but worse candidate does not replace the current version; the next revision starts from the best."""
    probes = FakeL2Probes()
    designer = ScriptedDesigner([{}, {"youngs_modulus_pa": 1e7}])  # initial priors, then a far worse modulus
    t = TargetBehaviour(bands=[TargetBand(metric="effective_modulus_pa", low=4e4, high=5e4, scale="log")],
                        priors={"youngs_modulus_pa": 3e4})
    out = run_stage(l2, probes, t, roles=Roles(RulePlanner(), designer, RuleCritic()))
    assert out.attempts[1].verdict == "rolled_back"
    assert designer.requests[2].current_values["youngs_modulus_pa"] == 3e4  # back at the best
    assert out.attempts[2].parent_iteration == 0
    assert out.status == "accepted"


def test_required_observation_missing_fails_the_gate(l2) -> None:
    def partial(values: dict[str, float], action: str) -> list[ProbeResult]:
        m = {k: v for k, v in HEALTHY.items() if k != "stable_long_rollout"}
        return [ProbeResult(spec=ProbeSpec(kind="compress"), metrics={**m, "effective_modulus_pa": 4e4})]

    out = run_stage(l2.model_copy(update={"revision_budget": 0}), partial, TargetBehaviour())
    a = out.attempts[0]
    assert not next(g for g in a.gates if g.metric == "stable_long_rollout").passed
    assert "missing observations" in a.critique and out.status == "no_valid_candidate"


def test_metric_reported_twice_keeps_its_worst_value(l2) -> None:
    def two(values: dict[str, float], action: str) -> list[ProbeResult]:
        return [ProbeResult(spec=ProbeSpec(kind="drop"), metrics={**HEALTHY, "j_min": 0.8}),
                ProbeResult(spec=ProbeSpec(kind="compress"), metrics={**HEALTHY, "j_min": 0.25})]

    out = run_stage(l2.model_copy(update={"revision_budget": 0}), two, TargetBehaviour())
    assert out.attempts[0].evidence.metrics["j_min"] == 0.25 and out.status == "no_valid_candidate"


def test_a_target_not_measured_does_not_demote_a_passing_material(l2) -> None:
    """#36: the lift probe's pinch slips, so sag_ratio is missing; every measured target holds. The material is
    accepted on its first attempt (not 'best_valid'), its score counts the measured bands, and the attempt records
    sag_ratio as not measured with the lift probe's reason."""
    probes = FakeL2Probes()

    def slipping_lift(values: dict[str, float], action: str) -> list[ProbeResult]:
        results = probes(values, action)
        lift = ProbeResult(spec=ProbeSpec(kind="lift"), sim_calls=1,
                           metrics={**HEALTHY, "lift_held": 0.0, "pinch_rise_m": 0.016, "sag_m": 0.0013})
        return [*results[:2], lift]

    bands = l2_targets(fake_modulus_pa(3e4), fake_rebound(5.0)).bands
    t = TargetBehaviour(bands=[*bands, TargetBand(metric="sag_ratio", low=0.0, high=0.3, weight=0.25)],
                        priors={"youngs_modulus_pa": 3e4, "poisson_ratio": 0.3, "damping_rate_per_s": 5.0})
    out = run_stage(l2, slipping_lift, t)
    assert out.status == "accepted" and out.passed and out.best_iteration == 0 and out.score == 1.0
    a = out.attempts[0]
    assert a.verdict == "accepted" and "sag_ratio" not in a.evidence.metrics
    assert list(a.evidence.not_measured) == ["sag_ratio"]
    assert a.evidence.not_measured["sag_ratio"].startswith("the lift probe's pinch did not hold the object")
    assert t.unmet(a.evidence.metrics) == [] and t.not_measured(a.evidence.metrics) == ["sag_ratio"]
    # a target measured outside its band still demotes: the same material with a sag far outside
    sagging = run_stage(l2.model_copy(update={"revision_budget": 0}),
                        lambda v, act: [*probes(v, act)[:2], ProbeResult(spec=ProbeSpec(kind="lift"), sim_calls=1,
                                                                         metrics={**HEALTHY, "sag_ratio": 0.9})], t)
    assert sagging.status == "best_valid" and t.unmet(sagging.metrics) == ["sag_ratio"]
