"""The cheap half of `bench realworld`: the material prior each plain name gets (the first proposal L2 starts from,
no MPM) is within 2x of the published Young's modulus, for every object of the set that has one."""

from __future__ import annotations

import pytest

from contracts.realworld import OurFigures, RealWorldObject, load_realworld
from tasks.agents.intent import targets_from_intent
from tasks.geometry import concepts
from tasks.realworld.compare import compare

MEASURED = [o for o in load_realworld().objects if o.modulus is not None or o.squeeze is not None]


@pytest.mark.parametrize("obj", MEASURED, ids=lambda o: o.name)
def test_the_prior_modulus_is_within_2x_of_the_measurement(obj: RealWorldObject) -> None:
    """E prior of the name's material class vs the published E (a cheddar block was the gel class's 30 kPa against
    113-230 kPa measured before #39 added the cheese class)."""
    _, match, _ = concepts.build(concepts.read_text(obj.name), obj.name)
    priors = targets_from_intent(obj.name, concept=match).priors
    ours = OurFigures(youngs_modulus_pa=priors["youngs_modulus_pa"], poisson_ratio=priors["poisson_ratio"])
    judged = [c for c in compare(obj, ours) if c.quantity in ("youngs_modulus_pa", "squeeze_modulus_pa")]
    assert judged and all(c.passed for c in judged), [(c.quantity, c.ours, c.measured) for c in judged]
