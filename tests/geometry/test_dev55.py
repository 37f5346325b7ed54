"""Session 55 (post-hoc from sealed set 42's misses): a bird said thawed, frozen or cooked is the whole bird, not
ground meat; a hard hat and a motorcycle helmet are refused as rigid, not built as a felt hat and a foam bike helmet;
a lifebuoy is the foam ring, not the 40 kg mooring buoy."""

from __future__ import annotations

import pytest

from contracts.errors import InputError
from tasks.agents.intent import check_rigid_object
from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a thawed pheasant for the falcons", "whole_pheasant", 0.9),
    ("a thawed quail", "whole_quail", 0.14),
    ("an orange life ring on the dock", "lifebuoy", 2.5),
])
def test_the_new_goods_build_at_their_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


@pytest.mark.parametrize(("text", "entry"), [
    ("a frozen chicken", "whole_chicken"),  # said eaten, not cut up: the whole bird
    ("a thawed turkey", "whole_turkey"),
    ("a life buoy", "lifebuoy"),
    ("ground chicken", "ground_meat"),  # cut up: still meat
    ("raw chicken breasts", "chicken_breast"),
    ("a thawed rabbit", "ground_meat"),  # no whole rabbit in the lexicon: meat as before
    ("a quail", "plush_quail"),  # nothing says it is eaten: the bird
    ("a buoy", "mooring_buoy"),  # the lifebuoy takes no plain buoy, nor the swim ring
    ("a swim ring", "swim_ring"),
])
def test_cut_or_live_birds_keep_their_reading(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize("text", ["a hard hat", "a yellow construction hard hat", "a motorcycle helmet",
                                  "a full face helmet", "a football helmet", "a pith helmet"])
def test_hard_shells_are_refused_as_rigid(text: str) -> None:
    with pytest.raises(InputError, match="rigid object"):
        check_rigid_object(text)


@pytest.mark.parametrize("text", ["a bike helmet", "a helmet", "a star helmet cover", "a plush motorcycle helmet",
                                  "a soft hard hat for kids"])
def test_soft_helmets_and_covers_are_not_refused(text: str) -> None:
    check_rigid_object(text)
