"""Small foods sold loose in bags (contracts/lexicon/snacks39.yaml, shapes in tasks/geometry/shapes/snacks39.yaml):
'a bag of salted cashews', 'a bag of peanut m&ms' were a generic opaque pouch, judged 'a bag of rice'. Each piece
reads as itself by name, is built at its real size and mass, is a piece a pouch can copy into every slot (at most 5
parts, all unions: a subtract would cut the bag), and a bag of them is a pouch that draws those pieces."""

from __future__ import annotations

import re

import pytest

from contracts.lexicon import load_lexicon
from contracts.yaml_io import load_yaml
from tasks.geometry import catalogue, grammar
from tasks.geometry.catalogue_programs import SHAPES_DIR
from tasks.geometry.concepts import SEEN_PIECE_M, concept_program, program_volume

LEX = load_lexicon().entries
ENTRIES = sorted(load_yaml((SHAPES_DIR / "snacks39.yaml").read_text(encoding="utf-8"))["entries"])
BAGS = {  # entry -> a request for a retail bag of them, as people type it
    "popcorn": "a bag of microwave popcorn",
    "spinach_leaf": "a 5oz bag of baby spinach",
    "goldfish_cracker": "half eaten bag of goldfish crackers",
    "cashew": "a bag of salted cashews",
    "almond": "a bag of roasted almonds",
    "candy_coated_peanut": "a bag of peanut m&ms",
    "candy_coated_chocolate": "a bag of m&ms",
    "beef_jerky": "a bag of beef jerky",
    "mini_pretzel": "a bag of mini pretzels",
    "tortilla_chip": "a bag of tortilla chips",
    "potato_chip": "a bag of kettle chips",
    "cheese_puff": "a bag of cheetos",
    "animal_cracker": "a bag of animal crackers",
    "baby_carrot": "a bag of baby carrots",
    "french_fry": "a bag of frozen fries",
    "peanut_in_shell": "a bag of peanuts",
    "pistachio": "a bag of pistachios",
    "walnut": "a bag of walnuts",
    "cheese_cracker": "a bag of cheez its",
}
def _concept(text: str) -> str:
    """The lexicon concept a request reads as."""
    match = catalogue.design_from_text(text).concept
    assert match is not None, text
    return match.concept


_SLOT = re.compile(r"^fill \d+(?: (.+))?$")  # a pouch's piece slot ('fill 3') and the piece's parts in it ('fill 3 tail')


def test_every_entry_is_a_hand_written_piece_with_a_bag_request() -> None:
    assert sorted(BAGS) == ENTRIES
    for key in ENTRIES:
        assert LEX[key].catalogue == key and key in catalogue.entry_names(), key


@pytest.mark.parametrize("key", ENTRIES)
def test_a_piece_reads_as_itself_and_is_built_at_its_real_size_and_mass(key: str) -> None:
    entry = LEX[key]
    assert _concept(f"a {entry.nouns[0]}") == key
    program = concept_program(key)
    assert 1 <= len(program.parts) <= 5 and all(p.operation == "union" for p in program.parts), key
    assert max(grammar.program_extents(program)) == pytest.approx(entry.size_m, rel=0.06)
    built_kg = program_volume(program, 32) * entry.solid_density_kg_per_m3
    assert 0.75 <= built_kg / entry.mass_kg <= 1.33, (key, built_kg, entry.mass_kg)


@pytest.mark.parametrize("key", ENTRIES)
def test_a_bag_of_them_is_a_pouch_drawing_the_pieces(key: str) -> None:
    design = catalogue.design_from_text(BAGS[key])
    assert design.entry == "generic_pouch" and design.concept is not None, BAGS[key]
    assert f"pieces of {key}" in design.concept.analogy[0], BAGS[key]
    if LEX[key].size_m < SEEN_PIECE_M:
        return  # (plain m&ms, 1.3 cm: a fill too fine to tell apart through the film)
    piece = concept_program(key)
    slots = [(p, m.group(1)) for p in design.program.parts if (m := _SLOT.match(p.name))]
    assert len({p.name.split()[1] for p, _ in slots}) >= 2, BAGS[key]  # at least two pieces
    if len(piece.parts) > 1:  # the piece's own parts ('fill 3 tail'), not a plain lump
        assert {own for _, own in slots if own} <= {p.name for p in piece.parts[1:]}, BAGS[key]
        assert any(own for _, own in slots), BAGS[key]
    else:  # a one-part piece: its own primitive in the slot (the tortilla chip's flat cone)
        assert all(p.primitive.kind == piece.parts[0].primitive.kind for p, _ in slots), BAGS[key]


@pytest.mark.parametrize(("text", "key"), [
    ("a single salted cashew", "cashew"),
    ("a peanut m&m", "candy_coated_peanut"),
    ("a blue m&m", "candy_coated_chocolate"),
    ("a dorito", "tortilla_chip"),
    ("a cheeto", "cheese_puff"),
    ("a pretzel twist", "mini_pretzel"),
    ("a soft pretzel", "soft_pretzel"),  # the baked one keeps its own entry
    ("a baby carrot", "baby_carrot"),  # was a full-size carrot
    ("a french fry", "french_fry"),
    ("a carton of fries", "french_fries"),
    ("a goldfish", "plush_fish"),  # the bare word stays the fish
])
def test_everyday_names_of_the_pieces(text: str, key: str) -> None:
    assert _concept(text) == key
