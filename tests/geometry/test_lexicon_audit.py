"""Fixes from the audit of the lexicon's own objects (session 37): each entry named by its first noun, rendered, and
named back by a judge who had not seen the lexicon (docs/blind/audit37/)."""

from __future__ import annotations

import pytest

from contracts.lexicon import load_lexicon
from tasks.agents.intent import rigid_object


def test_no_lexicon_noun_is_refused_as_a_rigid_object() -> None:
    """'a baby spoon' is the silicone weaning spoon of the lexicon, not a metal spoon: every noun of every entry reads
    as deformable."""
    refused = [(key, noun) for key, entry in load_lexicon().entries.items() for noun in entry.nouns
               if noun != "(generic)" and rigid_object(f"a {noun}") is not None]
    assert refused == []


@pytest.mark.parametrize("text", ["a spoon", "a metal spoon", "a chair", "a brick", "a pot"])
def test_the_rigid_words_alone_are_still_refused(text: str) -> None:
    assert rigid_object(text) is not None
