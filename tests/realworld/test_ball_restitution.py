"""A ball's own restitution (issue #39, session 28): the lexicon carries the coefficient of restitution its rebound
rule implies, L0 records it in the concept, and L2's material loss is calibrated to it instead of the class's prior,
at the speed of a fall from the rule's own drop height (session 33)."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
from pydantic import ValidationError

import cache
from contracts.concept import ConceptMatch
from contracts.lexicon import LexiconEntry, load_lexicon
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.realworld import RealWorldObject, load_realworld
from contracts.sim import SimConfig
from flows.realworld import rule_rebound
from tasks.geometry import concepts
from tasks.geometry.outputs import L0Asset
from tasks.realworld import loss as loss_mod
from tasks.realworld.loss import (REFERENCE_DROP_M, RESTITUTION_TOLERANCE, calibration_drop, material_loss,
                                  reference_speed_m_per_s, restitution_target)
from tasks.realworld.physics import G_M_PER_S2
from tests.spheres import resting_sphere

SET = load_realworld()
RULE_BALLS = [o for o in SET.objects if o.rebound is not None]
ENTRY = {"key": "test_ball", "nouns": ["test ball"], "plan": "ball", "material": "rubber", "category": "ball",
         "size_m": 0.07, "mass_kg": 0.05, "mass_source": "a test entry, no source"}


RULE = {"restitution_source": "derived from a test rule", "restitution_drop_m": 2.54}


def test_an_entry_with_a_sourced_restitution_is_accepted() -> None:
    e = LexiconEntry(**ENTRY, restitution=1.0, **RULE)
    assert e.restitution == 1.0 and e.restitution_drop_m == 2.54


@pytest.mark.parametrize("extra, needle", [
    ({"restitution": 0.8}, "together"),
    ({"restitution_source": "derived from a test rule"}, "together"),
    ({"restitution": 0.8, "restitution_source": "derived from a test rule"}, "drop height"),
    ({"restitution_drop_m": 2.54}, "drop height"),
    ({"restitution": 0.8, **RULE, "restitution_drop_m": 0.0}, "greater than 0"),
    ({"restitution": 0.0, **RULE}, "greater than 0"),
    ({"restitution": 1.2, **RULE}, "less than or equal to 1"),
])
def test_the_schema_refuses_a_bad_restitution(extra: dict, needle: str) -> None:
    with pytest.raises(ValidationError, match=needle):
        LexiconEntry(**ENTRY, **extra)


@pytest.mark.parametrize("obj", RULE_BALLS, ids=lambda o: o.name)
def test_a_rule_ball_carries_the_restitution_of_its_rule(obj: RealWorldObject) -> None:
    """Every ball of the real-world set with a rebound rule: its lexicon entry's e^2 lies in the rule's band of
    rebound height / drop height, and its source says it is derived from the rule."""
    entry = load_lexicon().entries[obj.concept]
    assert obj.rebound is not None and entry.restitution is not None and entry.restitution_source
    band = obj.rebound.rebound_ratio
    assert band.low <= entry.restitution ** 2 <= band.high, (entry.restitution ** 2, band)
    assert entry.restitution_source.startswith("derived from")
    assert entry.restitution_drop_m == pytest.approx(obj.rebound.drop_height_m, abs=1e-9)  # the rule's own drop


@pytest.mark.parametrize("name, key", [("pickleball", "pickleball"), ("racquetball", "handball")])
def test_l0_records_the_concepts_restitution(name: str, key: str) -> None:
    _, match, _ = concepts.build(concepts.read_text(name), name)
    entry = load_lexicon().entries[key]
    assert match.concept == key and match.restitution == entry.restitution
    assert match.restitution_source == entry.restitution_source


def _concept(restitution: float | None, material: str = "rubber", drop_m: float | None = 1.981) -> ConceptMatch:
    return ConceptMatch(concept="pickleball", body_plan="ball", category="ball", fallback_level="exact",
                        default_material=material, restitution=restitution,
                        restitution_source="derived from a test rule" if restitution else None,
                        restitution_drop_m=drop_m if restitution else None)


def test_the_loss_takes_the_concepts_restitution_over_the_class_prior() -> None:
    priors = {"restitution": 0.75}
    assert restitution_target(priors, _concept(0.641), "rubber") == (0.641, "lexicon: pickleball")
    assert restitution_target(priors, _concept(None), "rubber") == (0.75, "class prior: rubber")
    assert restitution_target(priors, None, "rubber") == (0.75, "class prior: rubber")
    # the words named another material ('a foam pickleball'): the rule's restitution is not that object's
    assert restitution_target({"restitution": 0.3}, _concept(0.641), "pu_foam") == (0.3, "class prior: pu_foam")
    assert restitution_target({}, _concept(0.641), "pu_foam") is None
    assert restitution_target({}, _concept(0.641), "rubber") == (0.641, "lexicon: pickleball")


def _calibration_speed(monkeypatch: pytest.MonkeyPatch, concept: ConceptMatch | None, material_class: str,
                       priors: dict[str, float] | None = None) -> tuple[float, dict]:
    """(impact speed material_loss asks the calibration for [m/s], its record), the MPM replaced by a stub."""
    seen: dict[str, float] = {}

    def stub(*, speed_m_per_s: float, **_: object) -> dict[str, float]:
        seen["speed"] = speed_m_per_s
        return {"speed_m_per_s": seen["speed"], "viscosity_pa_s": 10.0, "restitution": 0.7}

    monkeypatch.setattr(loss_mod, "restitution_loss_task", stub)
    pos, vol, phys = resting_sphere(0.03, 0.01, 950.0)
    _, rec = material_loss(pos, vol, phys, Material(youngs_modulus_pa=1.5e6, poisson_ratio=0.48),
                           priors or {"restitution": 0.75}, SimConfig(), concept, material_class)
    return seen["speed"], rec


@pytest.mark.parametrize("obj", RULE_BALLS, ids=lambda o: o.name)
def test_a_rule_ball_is_calibrated_at_its_rules_impact_speed(obj: RealWorldObject,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    """The concept L0 builds from the plain name: its loss is calibrated at the speed of a free fall from the rule's
    drop height (v^2 / 2g is the rule's height: 7.06 m/s for the 2.54 m rules, 2.45 m/s for table tennis's 305 mm),
    and the record says so."""
    assert obj.rebound is not None
    _, match, _ = concepts.build(concepts.read_text(obj.name), obj.name)
    speed, rec = _calibration_speed(monkeypatch, match, str(match.default_material))
    assert speed ** 2 / (2.0 * G_M_PER_S2) == pytest.approx(obj.rebound.drop_height_m, rel=1e-12)
    assert rec["speed_m_per_s"] == speed and rec["calibration_drop_m"] == obj.rebound.drop_height_m
    assert rec["calibration_drop_source"] == f"the rule's drop: {obj.concept}"
    assert rec["source"] == f"lexicon: {obj.concept}"


@pytest.mark.parametrize("name", ["rubber duck", "bouncy ball"])
def test_an_object_without_a_rule_is_calibrated_at_2_m_as_before(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """No rule restitution: the class prior at a 2 m fall (6.26 m/s), the very float of before (same cache key), and
    the concept's dump carries no drop height."""
    _, match, _ = concepts.build(concepts.read_text(name), name)
    assert match.restitution is None and "restitution_drop_m" not in match.model_dump(mode="json")
    speed, rec = _calibration_speed(monkeypatch, match, "rubber")
    assert speed == reference_speed_m_per_s() == math.sqrt(2.0 * G_M_PER_S2 * 2.0)
    assert speed == pytest.approx(6.264, abs=1e-3) and rec["calibration_drop_m"] == REFERENCE_DROP_M
    assert rec["source"] == "class prior: rubber" and rec["calibration_drop_source"] == "reference drop"


def test_a_rule_ball_of_another_material_or_without_a_height_is_calibrated_at_2_m() -> None:
    """'a foam pickleball': the class prior's restitution, so the class prior's 2 m; a concept recorded before the
    drop height (an old geometry.json) keeps the 2 m it was calibrated at."""
    assert calibration_drop(_concept(0.641), "rubber") == (1.981, "the rule's drop: pickleball")
    assert calibration_drop(_concept(0.641), "pu_foam") == (REFERENCE_DROP_M, "reference drop")
    assert calibration_drop(_concept(0.641, drop_m=None), "rubber") == (REFERENCE_DROP_M, "reference drop")
    assert calibration_drop(None, "rubber") == (REFERENCE_DROP_M, "reference drop")


R, SPACING, RHO = 0.0371, 0.006, 950.0  # a pickleball-sized (74.2 mm) solid rubber sphere, 912 particles
RUBBER = Material(youngs_modulus_pa=1.5e6, poisson_ratio=0.48, damping_rate_per_s=0.0)


def _sphere() -> tuple[np.ndarray, np.ndarray, PhysicalModel]:
    return resting_sphere(R, SPACING, RHO)


def test_the_pickleballs_rule_rebound_lands_nearer_its_band_with_its_own_restitution(prefect_api: str) -> None:
    """The USA Pickleball drop (78 in onto granite) of a pickleball-sized sphere with the viscosity calibrated to the
    lexicon's restitution lands nearer the rule's band (0.385-0.436) than with the rubber class's 0.75."""
    pos, vol, phys = _sphere()
    sim = SimConfig()
    rule = next(o for o in RULE_BALLS if o.concept == "pickleball").rebound
    assert rule is not None
    asset = cast(L0Asset, SimpleNamespace(particles_m=pos, volumes_m3=vol))
    lexicon = load_lexicon().entries["pickleball"]
    band = rule.rebound_ratio
    miss: dict[str, float] = {}
    for label, concept in (("class", None), ("lexicon", _concept(lexicon.restitution))):
        with cache.local_runtime():  # the calibration is a cached task
            fixed, rec = material_loss(pos, vol, phys, RUBBER, {"restitution": 0.75}, sim, concept, "rubber")
        assert str(rec["source"]).startswith("lexicon" if concept else "class prior")
        if concept is not None:
            assert abs(float(rec["restitution"]) - (lexicon.restitution or 0.0)) <= RESTITUTION_TOLERANCE, rec
        ratio = rule_rebound(rule, asset, phys, RUBBER.model_copy(update=fixed), sim)["rebound_ratio"]
        assert ratio is not None and math.isfinite(ratio)
        miss[label] = max(band.low - ratio, ratio - band.high, 0.0)
    assert miss["lexicon"] < miss["class"], miss
