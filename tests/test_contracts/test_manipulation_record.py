"""L3's record (manipulation.json) is typed end to end (contracts/manipulation.py): the committed records read as
models, write back as the same JSON, and no part of it is a loose dict."""

from __future__ import annotations

import json
import typing
from pathlib import Path

from pydantic import BaseModel

from contracts import manipulation
from contracts.manipulation import (ConditionRow, ConditionSummary, L2Check, ManipulationRecord, MaterialRevision,
                                    TrialRow)
from contracts.material import Material
from tasks.asset_dir import AssetDir, document_json

HERE = Path(__file__).parent
RECORDS = (HERE / "asset_fixture" / "manipulation.json", HERE.parent / "render" / "card_fixtures" / "turtle" /
           "manipulation.json")


def _loose(model: type[BaseModel]) -> list[str]:
    """Fields of a model (and the models it holds) typed as a dict of Any or as Any."""
    out = []
    for name, f in model.model_fields.items():
        text = str(f.annotation)
        if "Any" in text:
            out.append(f"{model.__name__}.{name}: {text}")
        for arg in typing.get_args(f.annotation) or (f.annotation,):
            for inner in typing.get_args(arg) or (arg,):
                if isinstance(inner, type) and issubclass(inner, BaseModel) and inner.__module__ == manipulation.__name__:
                    out += _loose(inner)
    return out


def test_no_part_of_l3s_record_is_a_loose_dict() -> None:
    assert _loose(ManipulationRecord) == []


def test_the_committed_records_read_typed(tmp_path: Path) -> None:
    for path in RECORDS:
        raw = json.loads(path.read_text())
        rec = ManipulationRecord.model_validate(raw)
        assert isinstance(rec.attempts[0], TrialRow) and rec.attempts[0].condition is not None
        assert rec.robustness is not None and isinstance(rec.robustness.conditions[0], ConditionRow)
        assert rec.best_attempt is not None and rec.best_attempt.plan.gripper == rec.gripper.name
        assert rec.trial_of_attempt(rec.attempt) == 1 and rec.simulated_trials() == len(rec.attempts)


def test_an_older_record_gains_only_its_plans_default_on_rewrite(tmp_path: Path) -> None:
    """The migration: a record written before the best attempt's plan carried grasp_reason (its plan was a loose
    dict) reads as it is; written back, only that default key is added (to its plan and to the adopted plan, which
    was typed before)."""
    raw = json.loads(RECORDS[1].read_text())
    assert "grasp_reason" not in raw["best_attempt"]["plan"] and "grasp_reason" not in raw["plan"]
    out = AssetDir(tmp_path)
    out.write_manipulation(ManipulationRecord.model_validate(raw))
    back = json.loads(out.file("manipulation").read_text())
    assert back["best_attempt"]["plan"].pop("grasp_reason") == back["plan"].pop("grasp_reason") == ""
    assert back == raw


def _revision(accepted: bool) -> MaterialRevision:
    l2 = Material(youngs_modulus_pa=2e4, poisson_ratio=0.3, damping_rate_per_s=2.0)
    revised = l2.model_copy(update={"youngs_modulus_pa": 4e4})
    check = L2Check(material=revised, passed=True, gates={"finite": True}, bands={}, metrics={"rebound_ratio": 0.2},
                    probe_keys=["k"])
    rev = MaterialRevision.model_validate({"trigger": "robustness", "from": l2, "to": revised, "reason": "slip",
                                           "failed_gates": ["lifted"], "l2_revalidation": check, "l2_checks": [check],
                                           "plan_values": {"squeeze_depth_m": 0.004}, "accepted": False})
    if accepted:
        rev = rev.model_copy(update={"accepted": True, "confirmation": {"lifted": 1.0},
                                     "robustness": ConditionSummary(conditions=[], passed=0)})
    return rev


def test_a_material_revision_writes_the_keys_l3_always_wrote() -> None:
    """'from' (a Python keyword) is its JSON key; the confirmation and its robustness only once L2 passed it."""
    rejected = json.loads(json.dumps(document_json(_revision(False))))
    assert set(rejected) == {"trigger", "from", "to", "reason", "failed_gates", "l2_revalidation", "l2_checks",
                             "plan_values", "accepted"}
    assert rejected["from"]["youngs_modulus_pa"] == 2e4 and rejected["l2_revalidation"]["material"]["youngs_modulus_pa"]
    adopted = json.loads(json.dumps(document_json(_revision(True))))
    assert set(adopted) - set(rejected) == {"confirmation", "robustness"}
    assert MaterialRevision.model_validate(adopted) == _revision(True)
