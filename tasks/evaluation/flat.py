"""Ablation A's *Flat* stage: one joint harness stage over the L1 + L2 editable fields (no layer gating).

Same probes (rigid place / drop / slide + MPM compress / drop / lift / stability), the same hard gates and targets,
the same feedback (the rule or LLM roles read the union of the two route tables) and the same total attempt budget
as the hierarchy's L1 + L2 stages. Only the layer-by-layer gating and freezing is removed.
"""

from __future__ import annotations

from contracts.stage import StageContract, load_contract
from tasks.agents.vocab import load_routes, stage_routes

FLAT_TITLE = "flat: physical model and material revised jointly (ablation A)"
PROPOSE_ALL = "propose_all"


def _union(a: list, b: list) -> list:
    return list(a) + [x for x in b if x not in a]


def flat_routes(l1: StageContract, l2: StageContract) -> dict:
    """The union of the L1 and L2 route tables (L2's contract overrides applied) as a harness_routes mapping."""
    r1 = load_routes().get("L1")
    r2 = stage_routes("L2", l2.parameters)
    assert r1 is not None
    fields = [f.name for f in (*l1.editable_fields, *l2.editable_fields)]
    actions = {PROPOSE_ALL: fields}
    actions.update({a: fs for a, fs in r1.actions.items() if a.startswith("revise")})
    actions.update({a: fs for a, fs in r2.actions.items() if a.startswith("revise")})
    return {
        "actions": actions, "escalations": [],
        "route_order": _union(r1.route_order, r2.route_order),
        "couplings": {**{m: [c.model_dump() for c in cs] for m, cs in r1.couplings.items()},
                      **{m: [c.model_dump() for c in cs] for m, cs in r2.couplings.items()}},
        "methods": {**r1.methods, **r2.methods}, "integers": _union(r1.integers, r2.integers),
        "gates": {**{g: v.model_dump() for g, v in r1.gates.items()}, **{g: v.model_dump() for g, v in r2.gates.items()}},
    }


def flat_contract(l1: StageContract | None = None, l2: StageContract | None = None) -> StageContract:
    """The joint contract: union of fields, observations and gates; budget = the two stages' attempts together."""
    l1 = l1 or load_contract("L1")
    l2 = l2 or load_contract("L2")
    attempts = (1 + l1.revision_budget) + (1 + l2.revision_budget)
    params = {**l1.parameters, **{k: v for k, v in l2.parameters.items() if k != "harness_routes"}}
    params["harness_routes"] = flat_routes(l1, l2)
    actions = [PROPOSE_ALL] + [a for a in params["harness_routes"]["actions"] if a != PROPOSE_ALL]
    return StageContract(
        stage="L2", title=FLAT_TITLE, permitted_actions=actions,
        required_observations=_union(l1.required_observations, l2.required_observations),
        hard_gates=[*l1.hard_gates, *l2.hard_gates],
        editable_fields=[*l1.editable_fields, *l2.editable_fields],
        revision_budget=attempts - 1, parameters=params)


def split_values(values: dict[str, float], l1: StageContract, l2: StageContract) -> tuple[dict, dict]:
    """A joint candidate -> (L1 values, L2 values)."""
    return ({f.name: values[f.name] for f in l1.editable_fields},
            {f.name: values[f.name] for f in l2.editable_fields})
