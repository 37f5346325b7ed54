"""Session 58, development set 58 (200 everyday prompts by a writer who never opened the repository): a deflated air
mattress (a body thinner than the volume grid's cell) had no volume and crashed L0 with a division by zero; a count
inside a pack ('a pack of 80 baby wipes') built twelve packs (4.4 kg); a plush named for its role ('a dinosaur plush
prize', 'a cat plush keyring') was a generic animal."""

from __future__ import annotations

import pytest

from contracts.shape import Part, RoundedBox, ShapeProgram
from tasks.geometry import catalogue
from tasks.geometry.meshing import mesh_program, program_volume
from tests.geometry.test_mass_classes import planned_mass


def test_a_body_thinner_than_a_cell_has_its_volume_and_its_mesh() -> None:
    # a 2 m x 1 m x 1.5 cm slab: at 40 cells along 2 m a cell is 5 cm, and no grid point fell inside it
    slab = ShapeProgram(name="slab", category="textile",
                        parts=[Part(name="body", primitive=RoundedBox(size_m=(2.0, 1.0, 0.015)))])
    assert program_volume(slab) == pytest.approx(2.0 * 1.0 * 0.015, rel=0.25)
    mesh = mesh_program(slab, 40)
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx(0.03, rel=0.35)


def test_a_deflated_air_mattress_is_built_and_weighs_its_skin() -> None:
    match = catalogue.design_from_text("single air mattress deflated and folded up").concept
    assert "deflated" in match.states
    mass = planned_mass("single air mattress deflated")
    assert 0.3 <= mass <= 3.0  # a PVC air bed's skin (0.9-2.5 kg), not its inflated volume's


@pytest.mark.parametrize(("text", "packs"), [
    ("a pack of 80 baby wipes", 1),
    ("pack of baby wipes, 80", 1),
    ("an 80-pack of baby wipes", 1),
    ("3 packs of baby wipes", 3),
])
def test_a_count_inside_a_pack_is_what_it_holds(text: str, packs: int) -> None:
    one = planned_mass("a pack of baby wipes")
    assert 0.2 <= one <= 0.8  # an 80-count soft pack: 380-450 g
    assert planned_mass(text) == pytest.approx(packs * one, rel=0.2)


@pytest.mark.parametrize(("text", "entry"), [
    ("can u do a green dinosaur plush prize, 40cm long", "plush_dinosaur"),
    ("little cat plush keyring", "plush_cat"),
    ("giant banana plush prize, like 1 meter long", "plush_banana"),
])
def test_a_plush_named_for_its_role_is_that_plush(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_known_noun_tagged_a_determiner_is_still_the_object() -> None:
    # spaCy tagged 'tablecloth' PRON/DT here, and the blue flowers it is printed with became the object (a 15 g daisy)
    assert catalogue.design_from_text("tablecloth folded up, white with blue flowers").entry == "tablecloth"


def test_a_crumpled_paper_cup_is_its_cup_alone() -> None:
    assert planned_mass("a paper coffee cup") > 0.3  # a 16 oz cup of coffee
    assert planned_mass("crumpled paper coffee cup") < 0.03  # the paper cup and lid (15-20 g); it weighed 480 g


def test_a_bag_holding_one_named_object_weighs_the_bag_and_the_object() -> None:
    # 'a paper bag' is a 1 kg bag of seed; with a croissant in it: ~30 g of kraft paper and a ~60 g croissant
    held = planned_mass("paper bag with a croissant in it")
    assert 0.06 <= held <= 0.15
    assert planned_mass("a paper bag with its handles") > 0.5  # 'its handles' is no content
