"""Sealed set 23's leftovers fixed after its one run (docs/blind/sealed23/), checked on other phrasings."""

from __future__ import annotations

import pytest

from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources


def _extents(text: str):  # noqa: ANN202
    arrays, _ = sources.build_mesh(AssetRequest(text=text), pipeline.settings_from_contract("draft"))
    return pipeline.arrays_to_mesh(arrays).extents


@pytest.mark.parametrize(("slight", "plain"), [("a slightly flattened cushion", "a flattened cushion"),
                                               ("a somewhat flat tennis ball", "a flat tennis ball")])
def test_slightly_takes_a_part_of_a_shape_words_change(slight: str, plain: str) -> None:
    """'a slightly flat yellow tenis ball' was squashed to half its height like a flat one (a judge saw a bar of
    soap): 'slightly' keeps a third of the change."""
    whole = _extents(plain.replace("flattened ", "").replace("flat ", ""))
    a, b = _extents(slight), _extents(plain)
    assert b[2] / whole[2] < a[2] / whole[2] < 1.0
    assert a[2] / whole[2] > 0.7


def test_a_ball_slightly_flat_is_half_deflated() -> None:
    """A hollow ball with a little air gone is dented as half deflated, not as flat."""
    from tasks.geometry.catalogue import design_from_text

    slight = design_from_text("a slightly flat basketball").concept
    flat = design_from_text("a flat basketball").concept
    assert slight is not None and "half deflated" in slight.states
    assert flat is not None and "deflated" in flat.states
