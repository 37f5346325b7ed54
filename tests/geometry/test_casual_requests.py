"""A request typed on a shop floor reads as the object it names: the command before it ('grab that', 'pls pick up',
'ok robot, grab the'), where it goes after it ('into the tray', 'off the table') and what to do with it ('- bin it',
'real quick', 'put that ... back') are not the object. Before session 47, 38 of 480 such wordings of 20 everyday
objects built another object or a generic block ('grab that sponge off the table' took 'table' for the object;
'lift the jellyfish into the tray' built minced meat)."""

from __future__ import annotations

import functools

import pytest

from tasks.geometry import catalogue

OBJECTS = ["sponge", "croissant", "teddy bear", "hoodie", "jellyfish", "burrata"]

TEMPLATES = [
    "grab that {} off the table",
    "pls pick up {}",
    "hand me that {} real quick",
    "lift the {} into the tray",
    "can you grab the {} pls",
    "ok robot, grab the {}",
    "put that {} back",
    "{} - bin it",
    "{}, put it in the crate",
    "get me the {} from the counter",
    "toss the {} into the laundry basket",
    "move the {} to the bin",
    "{} thx",
    "hey, could you please pick up the {}",
    "the {} thing",
    "some sort of {}",
    "{} that came back",
    "item: {}",
    "order 42: {}",
    "looking for the {}",
    "someone left a {} here",
]


@functools.cache
def _entry(text: str) -> str:
    return catalogue.design_from_text(text).entry


@pytest.mark.parametrize("template", TEMPLATES)
def test_a_casual_request_names_the_object_it_asks_for(template: str) -> None:
    wrong = [(template.format(o), _entry(template.format(o)), _entry(o)) for o in OBJECTS
             if _entry(template.format(o)) != _entry(o)]
    assert not wrong, wrong


@pytest.mark.parametrize(("text", "entry"), [
    ("a grab bag", "generic_bag"),  # a handling verb before a noun, with no determiner, is the object's own word
    ("a chicken on a foam tray", "ground_meat"),  # a tray the meat is sold on is still a food cue
    ("raw chicken into the tray", "whole_chicken"),
    ("a sock, folded", "crew_sock"),  # a state after a comma is no command
])
def test_what_is_not_a_command_is_read_as_before(text: str, entry: str) -> None:
    assert _entry(text) == entry


@pytest.mark.parametrize(("text", "plain"), [
    ("a couple of feijoas", "two feijoas"),  # ('a couple of feijoas' was a generic block)
    ("couple of apples", "two apples"),
    ("hair weft x2", "two hair wefts"),  # (a generic block)
    ("hair weft \u00d72", "two hair wefts"),
    ("2x bath towel", "two bath towels"),
    ("apple (x3)", "three apples"),
])
def test_a_count_said_casually_builds_that_many(text: str, plain: str) -> None:
    said, counted = catalogue.design_from_text(text), catalogue.design_from_text(plain)
    assert said.entry == counted.entry and len(said.program.parts) == len(counted.program.parts)
    one = catalogue.design_from_text(plain.split(" ", 1)[1])  # ('feijoas': one of them)
    assert len(counted.program.parts) != len(one.program.parts)  # the count changed what is built


def test_sides_are_no_count() -> None:
    """'30 x 40' is a towel's sides, not forty towels."""
    assert len(catalogue.design_from_text("towel 30 x 40").program.parts) == \
        len(catalogue.design_from_text("a towel").program.parts)


def test_an_irregular_verb_is_english_not_a_misspelt_noun() -> None:
    """WordNet's exception lists hold the irregular forms: 'came' is no misspelt 'camel' ('party hat that came in'
    built a plush deer), 'threw' no 'throw'."""
    from tasks.geometry.spelling import is_english

    assert is_english("came") and is_english("threw") and is_english("mice")
    assert _entry("party hat that came in") == _entry("party hat")


def test_a_stated_mass_past_the_longest_l0_builds_is_built_at_it_not_refused() -> None:
    """'2kg eiderdown' (a winter duvet's real mass) sized the duvet to 2.37 m by its density and was refused; it is
    built at L0's 2 m, denser, and weighs the 2 kg said."""
    from contracts.request import MAX_SIZE_M
    from tests.geometry.test_mass_classes import planned_mass

    d = catalogue.design_from_text("2kg eiderdown")
    assert d.entry == "duvet" and d.size.longest_m == MAX_SIZE_M and "at most" in (d.size.stated or "")
    assert abs(planned_mass("2kg eiderdown") - 2.0) < 0.1


def test_an_inflatable_animal_in_cling_film_is_no_meat() -> None:
    assert _entry("inflatable crocodile wrapped in cling film") == _entry("inflatable crocodile")
    assert _entry("raw chicken wrapped in cling film") == "whole_chicken"


@pytest.mark.parametrize(("text", "plain"), [("duvet king", "king size duvet"),  # (a generic block)
                                             ("fleece blanket queen", "queen size fleece blanket")])  # (a queen insect)
def test_a_bed_size_said_after_the_bedding_is_its_size(text: str, plain: str) -> None:
    assert _entry(text) == _entry(plain)


@pytest.mark.parametrize(("text", "plain"), [("ox tounge", "ox tongue"), ("2m string of pork sossages, coiled",
                                                                             "2m string of pork sausages, coiled"),
                                             ("a cinamon roll", "a cinnamon roll")])
def test_a_word_two_slips_off_is_read_as_the_one_it_sounds_like(text: str, plain: str) -> None:
    """Two typing slips ('tounge', 'sossages') are read as the lexicon word that starts the same and keeps the same
    consonants (both were generic shapes before session 47)."""
    assert _entry(text) == _entry(plain)


@pytest.mark.parametrize("word", ["shemagh", "ballgown", "punchbag", "approx"])
def test_a_word_two_slips_from_another_with_other_consonants_is_left_as_written(word: str) -> None:
    """A real word the dictionary lacks is no misspelt lexicon word ('shemagh' two slips from 'sheath', 'ballgown' from
    'balloon', 'approx' from 'apron': 'whole squid approx 30cm' was built as an apron)."""
    from tasks.geometry import concepts
    from tasks.geometry.spelling import corrections

    vocab = {w for noun in concepts.noun_index() for w in noun.split()}
    assert not [c for c in corrections(f"a {word}", vocab) if c[0] == word]


def test_a_pack_of_more_straps_than_a_program_draws_weighs_all_of_them() -> None:
    """'a pack of 6 bungee cords' was one cord of one cord's mass (straps were never grouped): as many cords as the
    64 parts hold lie side by side (4 of 15 parts), weighing the 6."""
    from tests.geometry.test_mass_classes import planned_mass

    d, one = catalogue.design_from_text("a pack of 6 bungee cords"), catalogue.design_from_text("a bungee cord")
    assert len(d.program.parts) == 4 * len(one.program.parts)
    assert 0.8 * 6 <= planned_mass("a pack of 6 bungee cords") / planned_mass("a bungee cord") <= 1.2 * 6


@pytest.mark.parametrize(("text", "entry_of"), [("tomato then the towel", "tomato"), ("axolotl or the sponge", "axolotl"),
                                                ("croissant plus the bag it came in", "croissant"),
                                                ("a plush dog and a plush cat", "a plush dog")])
def test_the_first_of_several_objects_named_is_the_object(text: str, entry_of: str) -> None:
    """More objects after the first, each with its own determiner, are not the request's object ('tomato then the
    towel' built the towel)."""
    assert _entry(text) == _entry(entry_of)


def test_features_listed_after_with_stay_the_objects() -> None:
    """'with a rainbow mane and a gold horn' lists the unicorn's features, not a second object."""
    said = "big fluffy white unicorn plushie with a rainbow mane and a gold horn"
    assert catalogue._task_clause_stripped(said).endswith("and a gold horn")
    assert _entry("big fluffy white unicorn plushie with a rainbow mane and a gold horn") == _entry("unicorn plushie")


def test_a_short_coiled_cord_builds() -> None:
    """'halter leads 40cm' (a lead rope coiled in a hank, said short) crashed with a negative torus radius."""
    d = catalogue.design_from_text("halter leads 40cm")
    assert d.entry == "lead_rope" and all(p.primitive.major_radius_m > 0 for p in d.program.parts
                                          if p.primitive.kind == "torus")


def test_gummi_bears_are_sweets_not_a_teddy() -> None:
    """Sealed set 34 (post-hoc): 'a gummi bears bag, 5oz' built a teddy bear ('gummi' is the Haribo spelling)."""
    assert _entry("a gummi bear") == "gummy_bear"
    assert _entry("a gummi bears bag, 5oz") == _entry("a bag of gummy bears")
