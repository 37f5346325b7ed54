"""A rubber's published Shore A hardness as its modulus band (#39, session 36): Gent's relation, the lexicon's
hardness carried by the concept, and L2's targets for the racquetball (USA Racquetball Rule 2.2: 55-60 durometer)."""

from __future__ import annotations

import pytest

from contracts.lexicon import LexiconEntry, load_lexicon
from contracts.material import shore_a_youngs_modulus_pa
from tasks.agents.intent import targets_from_intent
from tasks.geometry.concepts import read_text


def _band(text: str) -> tuple[float, float, str]:
    match = read_text(text).match
    band = next(b for b in targets_from_intent(text, {}, None, match).bands if b.metric == "effective_modulus_pa")
    return band.low, band.high, band.source


def test_gents_relation_against_hand_values() -> None:
    """E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa: Shore A 50 -> 2.46 MPa, 60 -> 3.61 MPa (by hand),
    rising with the hardness; outside Shore A 10-90 it is refused (the relation diverges towards 100)."""
    assert shore_a_youngs_modulus_pa(50.0) == pytest.approx(2.456e6, rel=2e-3)
    assert shore_a_youngs_modulus_pa(60.0) == pytest.approx(3.605e6, rel=2e-3)
    values = [shore_a_youngs_modulus_pa(s) for s in (20.0, 40.0, 60.0, 80.0)]
    assert values == sorted(values)
    with pytest.raises(ValueError):
        shore_a_youngs_modulus_pa(95.0)


def test_the_racquetball_takes_its_rule_hardness_as_its_modulus_band() -> None:
    """The racquetball's rubber was the rubber class's 1.0-2.5 MPa; its rule's 55-60 Shore A is 2.97-3.61 MPa."""
    match = read_text("a racquetball").match
    assert match.youngs_modulus_range_pa == pytest.approx((2.967e6, 3.605e6), rel=2e-3)
    assert "Rule 2.2" in (match.youngs_modulus_source or "")
    lo, hi, source = _band("a racquetball")
    assert (lo, hi) == pytest.approx((2.967e6, 3.605e6), rel=2e-3) and source.endswith(":hardness")


def test_words_and_other_objects_keep_their_bands() -> None:
    """A word that narrows the band ('soft') keeps the words' band; a ball with no published hardness keeps its
    class's, and its concept's record has no hardness keys (the cache keys of before are unchanged)."""
    lo, hi, source = _band("a soft racquetball")
    assert hi < 2.0e6 and "soft" in source
    assert _band("a tennis ball")[:2] == pytest.approx((1.0e6, 2.5e6))
    assert "youngs_modulus_range_pa" not in read_text("a tennis ball").match.model_dump()


def test_a_hardness_needs_its_source_and_a_sane_range() -> None:
    base = load_lexicon().entries["handball"].model_dump()
    with pytest.raises(ValueError):
        LexiconEntry(**{**base, "hardness_source": None})
    with pytest.raises(ValueError):
        LexiconEntry(**{**base, "hardness_shore_a": (60.0, 55.0)})
