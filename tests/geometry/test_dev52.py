"""Session 52, post-hoc from sealed set 39 (after its one run): a page is a sheet of paper, plastic film a thin film
sheet, and a rolled poster said by its flat size is rolled from that sheet, all at their real mass."""

from __future__ import annotations

import pytest

from tests.geometry.test_mass_classes import assert_builds_at_its_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("crumpled misprinted page", "paper_sheet", 0.005),
    ("torn piece of black plastic mulch film, about 1.5 x 1 m", "plastic_sheeting", 0.045),
    ("a 3 x 4 m plastic drop cloth folded", "plastic_sheeting", 0.36),
    ("Rolled up 24x36 inch glossy poster", "rolled_poster", 0.1),
    ("rolled up poster", "rolled_poster", 0.1),
])
def test_dev52_request_builds_its_entry_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert_builds_at_its_mass(text, entry, kg)


def test_a_rolled_good_said_by_its_flat_size_is_rolled_along_the_shorter_side() -> None:
    """'Rolled up 24x36 inch poster' built a 0.9 x 0.6 m solid tube of 5.5 kg; it is a 61 cm tube of ~6 cm."""
    from contracts.request import AssetRequest
    from tasks.geometry import pipeline

    mesh_arrays, _info = pipeline.mesh_from_text(AssetRequest(text="Rolled up 24x36 inch glossy poster"),
                                                 pipeline.settings_from_contract("draft"))
    ext = sorted(pipeline.arrays_to_mesh(mesh_arrays).extents)
    assert abs(ext[2] - 0.6096) < 0.01 and ext[1] < 0.1
    assert sorted(pipeline.arrays_to_mesh(pipeline.mesh_from_text(AssetRequest(text="a pool noodle 150 x 6 cm"),
                  pipeline.settings_from_contract("draft"))[0]).extents)[2] > 1.4  # a long good's own length
