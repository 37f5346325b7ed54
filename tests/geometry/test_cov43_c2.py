"""Coverage round 43 (helper c2): requests of development set 43 that read as no named entry (a generic block, blob,
bag or garment) now read as entries with hand-written shapes (tasks/geometry/shapes/cov43_c2.yaml, lexicon
contracts/lexicon/cov43_c2.yaml) drawn with the cues a person names them by, and their built mass is within 2x of the
real object's. 'pick up a ...' is a request's opening ('pick' was read as a guitar pick) and a product's 'N-in-1' is
no size ('a 5-in-1 reflector' was built 5 inches across). Checked on the programs: the readings in the default run,
a few built masses in the default run and the rest under -m slow."""

from __future__ import annotations

import functools

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass

# prompt as typed, entry, the real object's mass [kg]
CASES = [
    ("one pollen patty for the hive", "pollen_patty", 0.45),
    ("gulab jamun dripping syrup", "gulab_jamun", 0.04),
    ("pick up a besan laddu", "besan_laddu", 0.04),
    ("stack of perilla leaves", "perilla_leaves", 0.03),
    ("roll of mulberry pestil", "mulberry_pestil", 0.1),
    ("round nian gao in plastic wrap", "nian_gao", 0.45),
    ("latex zombie mask", "zombie_mask", 0.45),
    ("terry cloth blade soakers", "blade_soakers", 0.05),
    ("neoprene ankle brace", "ankle_brace", 0.08),
    ("sheet of griptape", "griptape_sheet", 0.1),
    ("empty pod pack harness", "pod_harness", 0.3),
    ("crushed paper water cup", "crushed_paper_cup", 0.007),
    ("foam boot shapers", "boot_shapers", 0.08),
    ("flannel shoe dust bag", "shoe_dust_bag", 0.05),
    ("rolled-up carpet remnant", "carpet_roll", 4.0),
    ("collapsible 5-in-1 reflector", "folded_reflector", 0.4),
    ("softbox front diffuser", "softbox_diffuser", 0.1),
    ("rolled xl desk mat", "rolled_desk_mat", 0.5),
    ("zip bag hygiene kit", "hygiene_kit_bag", 0.4),
    ("canvas picking bag", "canvas_picking_bag", 0.4),
    ("silicone corner tamping mat", "tamping_mat", 0.15),
]
QUICK = {"pick up a besan laddu", "collapsible 5-in-1 reflector", "gulab jamun dripping syrup"}  # (the reading fixes)


@functools.cache
def _design(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text)


@pytest.mark.parametrize(("text", "entry", "_kg"), CASES)
def test_the_prompt_reads_as_the_entry(text: str, entry: str, _kg: float) -> None:
    d = _design(text)
    assert d.entry == entry
    assert len(d.program.parts) <= 64


def test_pick_up_and_n_in_one_are_not_the_object_or_its_size() -> None:
    """'pick up a X' is X (not a guitar pick); 'a 5-in-1 reflector' states no size; a size in inches still does."""
    assert _design("pick up a besan laddu").size.longest_m is None
    assert _design("collapsible 5-in-1 reflector").size.longest_m is None
    assert _design("a 5 in foam ball").size.longest_m == pytest.approx(0.127)


@pytest.mark.parametrize(("text", "entry", "kg"), [c for c in CASES if c[0] in QUICK])
def test_the_built_mass_is_within_2x_quick(text: str, entry: str, kg: float) -> None:
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (entry, planned_mass(text), kg)


@pytest.mark.slow
@pytest.mark.parametrize(("text", "entry", "kg"), [c for c in CASES if c[0] not in QUICK])
def test_the_built_mass_is_within_2x_of_the_real_mass(text: str, entry: str, kg: float) -> None:
    """L1's mass as the blind bench weighs it (tests.geometry.test_mass_classes.planned_mass)."""
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg, (entry, planned_mass(text), kg)
