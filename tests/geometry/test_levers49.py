"""Session 49's readings and redraws (issue #35): long coats are coats, not a 0.6 kg fleece jacket ('overcoat' reached
WordNet's 'coating'); a coiled rope is loops crossing round a core with its free end wound round the coil (a smooth
ring read as an inner tube, set 34); a climbing rope and a battle rope are their own ropes at their own mass; a
round cord's stated 'across' far over its own diameter is the coil's size (it built a 4 m coil of a 40 cm cord);
a sheet or block of a material phrase is that material ('a sheet of crepe rubber' was the pancake); a bag of cheese
or of nacho cheese is a pouch of it (a 0.2 kg cheese block)."""

from __future__ import annotations

import pytest

from contracts.errors import InputError
from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tests.geometry.test_mass_classes import planned_mass


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a wool overcoat", "overcoat", 1.8),  # retail: knee-length wool overcoats 1.5-2.2 kg
    ("the khaki trench coat", "trench_coat", 1.2),  # cotton-gabardine trench coats 1.0-1.5 kg
    ("a navy peacoat", "pea_coat", 1.6),  # 32-34 oz melton peacoats 1.4-1.9 kg
])
def test_a_long_coat_is_a_coat_with_lapels_and_buttons_at_its_mass(text: str, entry: str, kg: float) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    groups = {part_group(p.name) for p in design.program.parts}
    assert {"lapel", "button", "sleeve"} <= groups, groups
    assert 0.67 <= planned_mass(text) / kg <= 1.5


def test_a_bare_coat_is_still_the_jacket() -> None:
    assert catalogue.design_from_text("a coat").entry == "jacket"


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a climbing rope", "climbing_rope", 3.8),  # 60 m x 9.8 mm dynamic rope, 61-64 g/m
    ("a coiled 60 m dynamic climbing rope, about 40 cm across the coil", "climbing_rope", 3.8),
    ("a battle rope", "battle_rope", 10.5),  # 38 mm x 15 m, 9-12 kg
    ("a coiled 60 m nylon rope", "rope_length", 3.9),  # 10 mm nylon ~6.5 kg per 100 m
])
def test_a_long_coiled_rope_is_crossing_loops_with_its_end_wound_round(text: str, entry: str, kg: float) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == entry
    groups = {part_group(p.name) for p in design.program.parts}
    assert {"body", "loop", "wrap", "tail"} <= groups, groups
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_coils_size_said_across_is_not_the_cords_diameter() -> None:
    """'40 cm across' of a 60 m rope is its coil (it was taken for a 40 cm cord: a 4 m coil, refused)."""
    design = catalogue.design_from_text("a 60 m climbing rope, about 40 cm across the coil")
    assert design.size.extents_m[:2] == (0.4, 0.4)
    thin = catalogue.design_from_text("a climbing rope, 10 mm")  # a cord's own size is still its diameter
    assert thin.size.longest_m is not None and 0.4 <= thin.size.longest_m <= 0.8


@pytest.mark.parametrize(("text", "material"), [("a sheet of crepe rubber", "rubber"),
                                                ("a block of memory foam", "pu_foam")])
def test_a_portion_of_a_material_phrase_is_that_material(text: str, material: str) -> None:
    concept = catalogue.design_from_text(text).concept
    assert concept is not None and concept.fallback_level == "material"
    assert concept.default_material == material


@pytest.mark.parametrize(("text", "fill", "kg"), [
    ("a bag of cheese", "shredded cheese", 0.23),  # retail 8 oz bags of shredded cheese
    ("a bag of shredded mozzarella", "shredded cheese", 0.23),
    ("a bag of nacho cheese sauce", "cheese sauce", 3.0),  # foodservice dispenser bags 106-140 oz
])
def test_a_bag_of_cheese_is_a_pouch_of_it(text: str, fill: str, kg: float) -> None:
    design = catalogue.design_from_text(text)
    assert design.entry == "generic_pouch"
    assert any(fill in w for w in design.warnings), design.warnings
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_hockey_glove_is_a_padded_gauntlet_glove_at_its_mass() -> None:
    """It was the 40 g knitted glove: now rolls of padding across the fingers and the back of the hand, a flared
    gauntlet cuff with a rolled edge, at a senior hockey glove's 0.35-0.45 kg."""
    design = catalogue.design_from_text("a hockey glove")
    assert design.entry == "hockey_glove"
    names = [p.name for p in design.program.parts]
    assert sum("roll" in n for n in names) >= 8 and "cuff roll" in names, names
    assert 0.67 <= planned_mass("a hockey glove") / 0.4 <= 1.5
    assert catalogue.design_from_text("a glove").entry == "knit_glove"


def test_a_jersey_laid_flat_shows_its_number_and_a_hockey_jersey_its_stripes() -> None:
    """A flat jersey drew no number (only a folded one did: the blind judges named a red T-shirt); a hockey jersey
    was the short-sleeved 0.19 kg football shirt: long sleeves with bands round them and the hem, ~0.45 kg."""
    flat = {part_group(p.name) for p in catalogue.design_from_text("a soccer jersey").program.parts}
    assert "number" in flat, flat
    design = catalogue.design_from_text("a hockey jersey")
    assert design.entry == "hockey_jersey"
    names = " ".join(p.name for p in design.program.parts)
    assert "sleeve stripe" in names and "hem stripe" in names and "number" in names
    assert 0.67 <= planned_mass("a hockey jersey") / 0.45 <= 1.5
    assert catalogue.design_from_text("a jersey").entry == "sports_jersey"


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a suede moccasin", "moccasin", 0.25),  # one adult moccasin 0.2-0.3 kg (was a generic block by the sneaker)
    ("hockey pants", "hockey_pants", 1.4),  # padded senior breezers 1.2-1.6 kg (were 0.55 kg trousers)
    ("a pair of hockey breezers", "hockey_pants", 1.4),  # (an unknown noun: a 0.18 kg generic object)
])
def test_a_moccasin_and_hockey_pants_are_their_own_at_their_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.67 <= planned_mass(text) / kg <= 1.5


def test_a_moccasin_has_its_raised_apron_over_the_toe() -> None:
    groups = {part_group(p.name) for p in catalogue.design_from_text("a moccasin").program.parts}
    assert {"sole", "upper", "apron", "foot opening"} <= groups, groups


def test_a_skirt_flares_from_a_belted_waistband_with_fanned_pleats() -> None:
    """Set 34's skirt was named 'a flat blue tarpaulin with a grommet' (its waistband button): now an A-line whose
    hem is ~1.3x its waist, a waistband with belt loops and eight pleats fanning to the hem, at 0.2-0.4 kg."""
    design = catalogue.design_from_text("a knee-length pleated skirt")
    assert design.entry == "skirt"
    names = [p.name for p in design.program.parts]
    assert sum(n.startswith("belt loop") for n in names) == 4 and sum(n.startswith("pleat") for n in names) == 8
    assert "waistband button" not in names
    assert 0.2 <= planned_mass("a knee-length pleated skirt") <= 0.4


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("hand me that rolled up offcut of veg tan", "leather_piece", 0.3),  # was a generic vegetable ('veg')
    ("a leather offcut", "leather_piece", 0.3),  # 7-8 oz veg-tan ~2.5-3 kg/m2 (was a generic object)
    ("pass me a bivvy bag", "survival_bivvy", 0.3),  # packed polyethylene survival bags 0.1-0.4 kg
    ("grab the casualty bag, the red one", "casualty_bag", 2.0),  # insulated patient wraps 1.5-2.5 kg
])
def test_trade_goods_of_set_34_are_their_own_at_their_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_leather_offcut_looks_like_leather_and_a_leather_bag_is_still_a_bag() -> None:
    concept = catalogue.design_from_text("a leather offcut").concept
    assert concept is not None and concept.finish == "leather"
    assert catalogue.design_from_text("a leather bag").entry == "generic_bag"


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("a bike cover", "protective_cover", 0.6),  # polyester bike / barbecue covers 0.3-1.0 kg (a 0.18 kg generic object)
    ("the bbq cover", "protective_cover", 0.6),
    ("a car cover", "car_cover", 3.0),  # car covers 2-5 kg
    ("the bunched up sail cover", "sail_cover", 2.5),  # acrylic mainsail covers 2-4 kg (was 'up sail cover')
    ("a duvet cover", "duvet_cover", 1.0),  # double/queen cotton 0.8-1.3 kg (was built like the duvet)
    ("a mattress protector", "mattress_protector", 1.2),  # queen 0.9-1.5 kg (was the 4 kg topper)
])
def test_a_cover_is_a_cover_of_cloth_at_its_mass(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.67 <= planned_mass(text) / kg <= 1.5


@pytest.mark.parametrize(("text", "entry"), [("a cushion cover", "box_cushion_cover"), ("a seat cover", "car_seat_cover"),
                                             ("a steering wheel cover", "steering_wheel_cover")])
def test_covers_the_lexicon_already_knew_are_unchanged(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry"), [
    ("can you make a 12 inch dalmatian plush like they'd keep at a fire station", "plush_dalmatian"),  # 'keep'
    ("the lil crinkle ball the cats keep batting around", "crinkle_ball"),  # was a generic ball named 'keep'
    ("a blanket we use on the couch", "throw_blanket"),
    ("can you get me the blue ball", "rubber_ball"),  # the request's own verb stays
    ("cotton string mop head refill", "string_mop"),  # 'refill' was taken for an unknown object
])
def test_a_relative_clause_or_a_refill_word_does_not_name_the_object(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


@pytest.mark.parametrize(("text", "entry", "kg"), [
    ("3 metres of velvet folded up", "fabric_cut", 1.5),  # 3 m x 1.4 m upholstery velvet ~350 g/m2 (a garment)
    ("2 yards of grey wool tweed folded on the cutting table", "fabric_cut", 0.8),  # 1.8 m x 1.5 m at ~300 g/m2
    ("a fuzzy pipe cleaner bent into a zigzag", "pipe_cleaner", 0.0015),  # 100 chenille stems 120-180 g
    ("knitted leg warmers", "leg_warmers", 0.08),  # 60-100 g each (a generic object named 'warmers')
    ("loose nylon coil zipper", "zipper_length", 0.012),  # a 50 cm #5 coil zipper 10-15 g
    ("a ripe aguacate", "avocado", 0.2),  # Spanish for avocado: it was by analogy only
    ("grab the fleece hat outta the lost gear box", "beanie_hat", 0.08),
])
def test_words_of_trades_and_languages_name_their_objects(text: str, entry: str, kg: float) -> None:
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 <= planned_mass(text) / kg <= 2.0


def test_a_punnet_of_berries_is_its_berries_and_a_bare_hat_or_zip_is_not_taken_over() -> None:
    design = catalogue.design_from_text("a punnet of strawberries")
    assert design.entry == "generic_pouch" and any("strawberr" in w for w in design.warnings)
    assert 0.2 <= planned_mass("a punnet of strawberries") <= 0.8  # UK punnets 227-400 g
    assert catalogue.design_from_text("a plush toy in a hat").entry != "beanie_hat"
    assert catalogue.design_from_text("a zip lock bag").entry == "zip_bag"


@pytest.mark.parametrize(("text", "entry"), [
    ("can u make a bed pillow, standard 20x26 in, polyester fill", "pillow"),  # 'can' was read as the object
    ("a round tie-on seat cushion for a kitchen chair", "stool_cushion"),  # 'tie' (a beam, by WordNet)
    ("a glazed ring donut with one bite taken out of it", "donut"),  # the parser's head was 'ring'
    ("half used tube of tattoo aftercare cream", "toothpaste_tube"),  # a generic 'tube' block of 20 g
    ("roll of purple self stick wrap", "elastic_bandage"),  # a sandwich wrap by WordNet
    ("pair of white fencing breeches", "trousers"),
    ("a tie", "necktie"), ("a zip tie", "cable_tie"), ("a hair tie", "hair_scrunchie"),
    ("the squishy yellow thing you squeeze when stressed, shaped like a star", "generic_block"),  # keeps its star
])
def test_more_readings_of_earlier_sets(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_relative_clause_is_cut_only_up_to_its_comma() -> None:
    design = catalogue.design_from_text("the squishy yellow thing you squeeze when stressed, shaped like a star")
    assert design.concept is not None and design.concept.shape_from == "star"


def test_a_folded_sheet_still_too_long_says_so_and_quarters_fit() -> None:
    """'queen size duvet folded in thirds on the bed' (228 cm, one fold across) is still 2.28 m long: refused with
    what to say instead, not the generic 'built so to fit' hint; folded in quarters it builds, at a duvet's mass."""
    with pytest.raises(InputError, match="still 2.28 m long"):
        catalogue.design_from_text("queen size duvet folded in thirds on the bed")
    assert catalogue.design_from_text("queen size duvet folded in quarters").entry == "duvet"
    assert 0.8 <= planned_mass("queen size duvet folded in quarters") <= 3.0  # queen duvets 1.2-2.5 kg


def test_a_question_mark_ends_the_sentence_that_names_the_object() -> None:
    """Set 36 (post-hoc): 'Could you bring me my apron? Canvas one, ...' built a cut of canvas (this session's new
    fabric noun) because '?' was dropped and the two sentences read as one."""
    text = "Could you bring me my apron? Canvas one, covered in slip, hanging on the hook."
    assert catalogue.design_from_text(text).entry == "apron"


@pytest.mark.parametrize(("text", "count", "one"), [
    ("twelve folded t-shirts", 12, "a folded t-shirt"),
    ("Bring me a stack of the medium black tees, like a dozen, still folded.", 12, "a folded t-shirt"),  # (set 36,
    # post-hoc: it was one tee)
    ("3 folded sweaters", 3, "a folded sweater"),
])
def test_a_count_of_garments_is_a_pile_weighing_all_of_them(text: str, count: int, one: str) -> None:
    """A count of garments was dropped (a garment is no good laid side by side): twelve folded T-shirts were one
    T-shirt of 0.15 kg. They are now piled one on another, as many drawn as a program's parts hold, weighing all."""
    design = catalogue.design_from_text(text)
    assert any(s.startswith(f"a stack of {count}") for s in design.concept.states), design.concept.states
    assert 0.7 * count <= planned_mass(text) / planned_mass(one) <= 1.3 * count


@pytest.mark.parametrize(("text", "kg"), [
    ("a bag of rice, the two-and-a-half kilo one", 2.5),  # (set 36, post-hoc: 'the two-and-a-half kilo one' of
    ("a two kilo bag of rice", 2.0),  # spawn was read as no mass at all)
    ("a five pound bag of flour", 2.27),
    ("a twenty five kg sack of rice", 25.0),
])
def test_a_mass_said_in_words_is_the_stated_mass(text: str, kg: float) -> None:
    concept = catalogue.design_from_text(text).concept
    assert concept is not None and concept.stated_mass_kg == pytest.approx(kg, rel=0.01)
    assert planned_mass(text) == pytest.approx(kg, rel=0.05)


def test_a_pound_cake_is_no_mass() -> None:
    concept = catalogue.design_from_text("a pound cake").concept
    assert concept is not None and concept.stated_mass_kg is None


@pytest.mark.parametrize(("text", "entry"), [
    ("Bring me the crown line bag, the red stuff sack.", "stuff_sack"),  # (set 36, post-hoc: a 0.15 kg generic bag)
    ("a floof, the big fluffy towel", "bath_towel"),
    ("the casualty bag, the red one", "casualty_bag"),  # a known first noun keeps its object
    ("a ball, the size of a grape", "rubber_ball"),  # 'the size of' names no object
])
def test_an_appositive_names_the_object_when_the_first_words_are_a_guess(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_rolls_said_stacked_are_rolls_not_a_sheet_of_no_volume() -> None:
    """'two rolls of toilet paper, one stacked on the other' failed: 'stacked' made the roll a stack of its 0.1 mm
    sheet ('program has no volume'); it is two rolls, at two rolls' mass."""
    text = "two rolls of toilet paper, one stacked on the other"
    assert catalogue.design_from_text(text).entry == "toilet_roll"
    assert planned_mass(text) == pytest.approx(planned_mass("two rolls of toilet paper"), rel=0.05)


def test_a_rolls_width_and_bare_length_are_the_sheets() -> None:
    """'elastic crepe bandage roll, 10 cm wide x 4.5 m' was refused as a 4.5 m object: the width stated, the bare
    4.5 m is the sheet's length, rolled (a 4.5 m bandage builds as its ~10 cm roll)."""
    design = catalogue.design_from_text("elastic crepe bandage roll, 10 cm wide x 4.5 m")
    assert design.entry == "elastic_bandage" and design.size.longest_m is None
    assert max(v for v in design.size.extents_m if v is not None) < 0.2
