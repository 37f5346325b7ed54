"""Material intent -> quantitative target bands (vocabulary, explicit numbers, request overrides)."""

from __future__ import annotations

import pytest

from contracts import AssetRequest
from contracts.errors import InputError
from tasks.agents.intent import targets_from_intent, targets_from_request
from tasks.agents.vocab import load_material_vocab


def _band(t, metric):  # noqa: ANN001, ANN202
    b = t.band(metric)
    return (b.low, b.high)


def test_words_map_to_reference_priors_and_bands() -> None:
    plush = targets_from_intent("a plush teddy bear")
    rubber = targets_from_intent("a rubber ball")
    assert _band(plush, "effective_modulus_pa") == (5e3, 5e4) and _band(rubber, "effective_modulus_pa") == (1e6, 2.5e6)
    assert plush.band("effective_modulus_pa").scale == "log" and plush.band("effective_modulus_pa").unit == "Pa"
    assert plush.band("rebound_ratio").high < rubber.band("rebound_ratio").low  # plush is dead, rubber bounces
    assert rubber.priors["density_kg_per_m3"] == 950.0 and rubber.priors["poisson_ratio"] < 0.5
    assert 5e3 <= plush.priors["youngs_modulus_pa"] <= 5e4


def test_modifiers_narrow_the_band() -> None:
    soft = targets_from_intent("soft foam pillow").band("effective_modulus_pa")
    firm = targets_from_intent("firm foam pillow").band("effective_modulus_pa")
    plain = targets_from_intent("foam pillow").band("effective_modulus_pa")
    assert plain.low <= soft.low < soft.high < firm.high <= plain.high and soft.high <= firm.low * 10
    very = targets_from_intent("very soft foam")
    assert "soft" not in very.matched_words and "very soft" in very.matched_words
    assert targets_from_intent("bouncy gel").band("rebound_ratio").low >= 0.4


def test_objects_imply_materials_and_unknown_falls_back() -> None:
    assert "duck" in targets_from_intent("a yellow duck").matched_words
    default = targets_from_intent("a thing")
    assert default.matched_words == [] and default.band("effective_modulus_pa").source.startswith("vocab:default")


@pytest.mark.parametrize("text", ["a steel wrench", "a wooden toy", "a glass marble"])
def test_rigid_materials_are_refused(text: str) -> None:
    with pytest.raises(InputError, match="is a rigid material .*Name a deformable material"):
        targets_from_intent(text)


@pytest.mark.parametrize("text, word", [("a steel-grey plush seal", "plush"), ("a stone-washed denim plush", "plush"),
                                        ("a wooden-handled sponge", "sponge")])
def test_a_deformable_material_wins_over_rigid_words(text: str, word: str) -> None:
    assert targets_from_intent(text).matched_words[0] == word


def test_explicit_numbers_beat_words() -> None:
    t = targets_from_intent("a soft plush turtle with E = 50 kPa, rebound 0.3 and sag 10%, density 120 kg/m3")
    assert _band(t, "effective_modulus_pa") == pytest.approx((4e4, 6.25e4))
    assert _band(t, "rebound_ratio") == pytest.approx((0.25, 0.35))
    assert _band(t, "sag_ratio") == pytest.approx((0.05, 0.15))
    assert t.priors["youngs_modulus_pa"] == 5e4 and t.priors["density_kg_per_m3"] == 120.0
    assert t.band("effective_modulus_pa").source.startswith("request:")
    assert targets_from_intent("Young's modulus of 2 MPa").band("effective_modulus_pa").center == pytest.approx(2e6)


def test_request_overrides_win() -> None:
    req = AssetRequest(text="a rubber duck", target_overrides={"effective_modulus_pa": (2e4, 4e4), "sag_ratio": (0, 0.1)})
    t = targets_from_request(req)
    assert _band(t, "effective_modulus_pa") == (2e4, 4e4) and t.band("effective_modulus_pa").source == "override"
    assert _band(t, "sag_ratio") == (0, 0.1)
    assert targets_from_request(AssetRequest(text="a duck", material_intent="bread")).matched_words == ["bread"]
    with pytest.raises(InputError):
        targets_from_intent("foam", overrides={"rebound_ratio": (0.5, 0.1)})


def test_vocabulary_priors_follow_the_reference_table() -> None:
    v = load_material_vocab()
    for name, entry in v.materials.items():
        lo, hi = entry.prior_ranges["youngs_modulus_pa"]
        assert lo <= entry.priors["youngs_modulus_pa"] <= hi, name
        assert 0.0 <= entry.priors["poisson_ratio"] < 0.5, name
        rlo, rhi = entry.prior_ranges["density_kg_per_m3"]
        assert rlo <= entry.priors["density_kg_per_m3"] <= rhi, name


def test_score_and_met() -> None:
    t = targets_from_intent("rubber ball")
    inside = {"effective_modulus_pa": 1.5e6, "rebound_ratio": 0.6, "recovery_ratio": 0.99}
    assert t.met(inside) and t.score(inside) == 1.0
    off = {**inside, "effective_modulus_pa": 1.5e4}
    assert not t.met(off) and t.score(off) < t.score({**inside, "effective_modulus_pa": 5e5}) < 1.0
    assert not t.met({}) and t.score({}) == 0.0


def test_the_concept_l0_built_gives_the_material_the_words_do_not_name() -> None:
    """A ConceptMatch's default material comes after the material words and before object words ('duck' -> rubber)."""
    from contracts.concept import ConceptMatch

    plush_duck = ConceptMatch(concept="plush_duck", noun="duck", body_plan="bird", category="plush_animal",
                              fallback_level="exact", default_material="plush")
    t = targets_from_intent("a yellow duck", concept=plush_duck)
    assert _band(t, "effective_modulus_pa") == (5e3, 5e4) and t.priors["density_kg_per_m3"] == 100.0
    assert t.band("effective_modulus_pa").source == "concept:plush_duck(plush)" and t.matched_words == []
    assert _band(targets_from_intent("a rubber duck", concept=plush_duck), "effective_modulus_pa") == (1e6, 2.5e6)
    unknown = plush_duck.model_copy(update={"default_material": "vinyl"})  # not a vocabulary class: ignored
    assert "duck" in targets_from_intent("a yellow duck", concept=unknown).matched_words


def test_a_rigid_attachment_does_not_make_the_object_rigid() -> None:
    """'a rolled elastic bandage with a metal clip' is a bandage (a blind prompt was refused for its clip); 'a steel
    ball' is still refused."""
    import pytest

    from contracts.errors import InputError
    from tasks.agents.intent import targets_from_intent

    targets_from_intent("a rolled elastic bandage with a metal clip")
    with pytest.raises(InputError, match="'steel' is a rigid material"):
        targets_from_intent("a steel ball")
