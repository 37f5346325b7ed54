"""Development set 21's misses (#35, session 35): what a reviewer who never saw the lexicon asked for and L0 built
wrong, fixed by class and tested here with other phrasings than the set's (the set itself: docs/blind/dev21/); and
sealed sets 19 and 20's repeat misses (rolled socks, crumpled paper, folded jeans, a deflated beach ball)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, grammar
from tasks.geometry.catalogue import normalise_sizes, parse_size
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.spelling import corrections
from tests.geometry.test_mass_classes import planned_mass


def _groups(text: str) -> list[str]:
    return [part_group(p.name) for p in catalogue.design_from_text(text).program.parts]


@pytest.mark.parametrize(("text", "entry"), [
    ("a queen memory foam topper, rolled", "foam_topper"),  # 'mattress topper twin xl' was a 1 g generic block
    ("a worn paperback", "paperback_book"),  # a bare 'book' / 'paperback' was a 26 g generic block
    ("a magazine rolled into a tube", "magazine"),
    ("a black neck warmer", "neck_gaiter"),
    ("a foam mic cover", "mic_windscreen"),  # 'foam windscreen' was a generic block
    ("a dental dam, blue", "dental_dam"),  # 'rubber dam sheet' was a 245 g ball by WordNet's gloss
    ("a stability pad for physio", "balance_pad"),
    ("a disposable hand warmer", "disposable_hand_warmer"),  # 'air activated hand warmer packet' a 150 g bag
    ("a 5 cm brown leather guitar strap", "guitar_strap"),  # was a 12 g webbing strap
    ("a bungee with hooks", "bungee_cord"),  # was 4 g of cord
    ("a white muslin swaddle", "muslin_swaddle"),  # a cotton baby blanket's weight (0.44 kg for 47 x 47 in)
    ("a dentist chair headrest pillow", "headrest_cushion"),  # was a 1 kg throw cushion
    ("an oshibori towel", "oshibori"),  # was a 0.3 kg hand towel
    ("a foam lumbar roll", "lumbar_roll"),  # was a 0.43 kg bolster
    ("an insulated snow mitten", "ski_mitten"),  # 'ski mitten' was a 52 g knitted wool mitten
    ("knitted baby booties", "knit_bootie"),  # were baby socks of 3 g
    ("a whole california roll before cutting", "maki_roll"),  # 'uncut california roll' was one 4.5 kg piece
    ("a folded gauze sponge", "gauze_pad"),  # was a 47 g kitchen sponge
    ("a glob of therapy putty", "therapy_putty"),  # 'glob' was no portion word: a generic blob
])
def test_dev21_nouns_build_their_own_object(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry


def test_a_longer_noun_ending_on_the_last_word_is_the_head() -> None:
    """'air activated hand warmer packet': the lexicon's 'air activated hand warmer' took 'hand warmer' and left
    'packet' a generic fabric bag; the noun ending on the clause's last word is the head."""
    assert catalogue.design_from_text("an air activated hand warmer packet").entry == "disposable_hand_warmer"


def test_two_letters_typed_in_turn_are_corrected() -> None:
    """'jakcet' (difflib's ratio 0.83, under the cutoff) was unknown: a generic block for a down puffer jacket."""
    assert ("jakcet", "jacket") in corrections("a navy puffer jakcet", {"jacket", "jackfruit"})
    assert catalogue.design_from_text("a crumpled navy puffer jakcet").entry != "generic_block"


def test_a_wearers_age_and_a_bed_size_are_not_lengths() -> None:
    """'0-3 months' made a onesie a generic block; 'twin xl' a mattress topper; a bed's size said by name is the
    mattress's width x length (US standards), a duvet's the cover's (over 2 m only when it is said folded or
    rolled: L0 builds at most 2 m)."""
    assert "month" not in normalise_sizes("a grey baby romper, 3-6 months")
    assert catalogue.design_from_text("a white baby onesie, 6-12 months, folded").entry == "baby_bodysuit"
    assert parse_size(normalise_sizes("a foam mattress topper, queen, rolled up")).extents_m[:2] == pytest.approx(
        (1.52, 2.03))
    assert parse_size(normalise_sizes("a full size fitted sheet")).extents_m[:2] == pytest.approx((1.37, 1.91))
    assert parse_size(normalise_sizes("a king size duvet, folded")).extents_m[:2] == pytest.approx((2.64, 2.28))
    assert not parse_size(normalise_sizes("a king size duvet")).explicit  # laid out, more than L0 builds: typical
    assert normalise_sizes("a half-full bag of rice") == "a half-full bag of rice"  # 'full' only as a bed size


def test_a_sheets_bare_size_beside_a_named_side_is_its_longest_other_side() -> None:
    """'60cm, 10cm thick': the bare 60 cm was dropped and the floor cushion built 16 cm across (40 g)."""
    size = parse_size("a square floor cushion 70 cm, 12 cm thick")
    assert size.longest_m == pytest.approx(0.7) and size.extents_m[2] == pytest.approx(0.12)
    assert 0.3 <= planned_mass("a square floor cushion 70 cm, 12 cm thick") <= 2.5


def test_the_size_of_what_a_tube_is_for_is_not_the_tubes() -> None:
    """'for 3/4 in pipe': the fraction was not read as the purpose's size and the insulation was built 19 mm long."""
    assert 0.03 <= planned_mass("2 m of foam pipe insulation for 1/2 in pipe") <= 0.2


def test_a_slice_of_pizza_is_a_wedge_of_the_pie_it_is_cut_from() -> None:
    """'a slice of pizza' built the whole pizza (0.3 kg; 0.9 kg 'from a 14in pie'); a slice of a round flat food is a
    wedge from its centre, and 'from a 16 inch pizza' sizes the pie."""
    assert "wedge" in catalogue.design_from_text("a slice of pepperoni pizza").concept.states
    assert 0.03 <= planned_mass("a slice of pepperoni pizza") <= 0.12
    assert 0.1 <= planned_mass("a slice of pepperoni pizza from a 16 inch pizza") <= 0.3
    assert 0.07 <= planned_mass("a slice of apple pie") <= 0.25  # (was 0.5 kg)


def test_a_slice_of_a_block_food_is_a_slice_of_it() -> None:
    """'a slice of tamagoyaki' was the whole roll: a portion of the same plan as the entry was taken as the entry."""
    whole, one = planned_mass("a tamagoyaki"), planned_mass("a slice of tamagoyaki")
    assert one < 0.25 * whole


def test_a_hoses_bare_size_is_its_bore_and_a_long_coil_fits() -> None:
    """'50 ft garden hose, 5/8 inch': 5/8 in is the nominal bore (it was the outer diameter, 1.05 kg against ~4 kg);
    100 ft of it is coiled tighter instead of refused as 2.3 m across."""
    assert 2.5 <= planned_mass("a 50 ft garden hose, 5/8 inch, coiled") <= 6.0
    d = catalogue.design_from_text("a 3/4 inch garden hose, 100 ft")
    assert float(grammar.program_extents(d.program, 48).max()) > 0


@pytest.mark.parametrize(("text", "low", "high"), [
    ("a 1.2 m purple resistance band tied in a loop", 0.015, 0.2),
    ("an inflatable balance disc, 35 cm", 0.4, 1.8),  # 'inflatable' took the beach-ball skin: 20 g
    ("a tiny pair of knitted baby booties", 0.012, 0.06),  # 'tiny' shrank a baby's booties again: 3 g
    ("a jumbo marshmallow", 0.004, 0.014),  # the bag's 'jumbo' is the regular 7 g size
    ("a 24 inch bungee cord", 0.03, 0.12),
    ("a dog-eared paperback", 0.1, 0.35),
    ("a muslin swaddle, 120 x 120 cm, bunched up", 0.06, 0.3),
])
def test_dev21_masses_within_2x(text: str, low: float, high: float) -> None:
    assert low <= planned_mass(text) <= high


def test_a_bungee_cord_has_a_hook_at_each_end() -> None:
    parts = catalogue.design_from_text("a black bungee cord with hooks").program.parts
    hooks = [p for p in parts if part_group(p.name) == "hook"]
    ends = {np.sign(p.transform.translation_m[0]) for p in hooks}
    assert len(hooks) >= 6 and ends == {-1.0, 1.0}
    assert all(not np.allclose(p.color_rgb, parts[0].color_rgb, atol=0.1) for p in hooks)  # steel, not the cord


def test_rolled_socks_wear_a_wide_ribbed_cuff_with_stripes_round_the_middle() -> None:
    """A sock ball's narrow band at one end was named a surprise egg (sets 19, 20, dev 21): the turned-over cuff
    covers the middle of an oval bundle, ribbed, with two stripes in a second colour."""
    design = catalogue.design_from_text("a pair of white athletic socks rolled into a ball")
    groups = [part_group(p.name) for p in design.program.parts]
    assert groups.count("stripe") == 2 and groups.count("rib") >= 20
    body = next(p for p in design.program.parts if part_group(p.name) == "body")
    stripe = next(p for p in design.program.parts if part_group(p.name) == "stripe")
    assert not np.allclose(body.color_rgb, stripe.color_rgb, atol=0.1)


def test_a_crumpled_paper_wad_is_faceted_with_folds_in_and_out() -> None:
    """'a ball partly wrapped in paper' (sets 19, 20): fourteen shallow cuts left a round ball with flaps; a wad is
    cut into many facets at uneven depths, with creases standing out and valleys pressed in."""
    parts = catalogue.design_from_text("a crumpled up sheet of notebook paper").program.parts
    ops = {part_group(p.name): p.operation for p in parts}
    assert sum(part_group(p.name) == "facet" for p in parts) >= 20
    assert ops.get("valley") == "subtract" and ops.get("crease") == "union"


def test_folded_jeans_show_their_stitching_patch_and_button_in_their_own_colours() -> None:
    """Folded jeans read as a blue toolbox (sets 19, 20): the pockets' stitching, the leather patch and the button
    carry the entry's colours; a shop-folded pair is ~5-9 cm high, not 12."""
    design = catalogue.design_from_text("folded blue jeans")
    colours = {part_group(p.name): p.color_rgb for p in design.program.parts}
    assert design.entry == "jeans_folded"  # (hand-drawn since session 43: the trouser outline folded at the knees)
    body = np.asarray(colours["thigh"])
    for part in ("pocket stitch", "fly stitch", "button", "hem stitch", "outseam"):
        assert not np.allclose(colours[part], body, atol=0.1), part
    assert float(grammar.program_extents(design.program, 48)[2]) < 0.1


def test_a_deflated_beach_balls_gores_are_wedges_in_turn() -> None:
    """The gores were round petals overlapping their neighbours; each is now a wedge of four pieces, as wide as the
    wedge where they lie, so its colour meets the next along a straight seam."""
    parts = catalogue.design_from_text("a flat deflated beach ball").program.parts
    gores = [p for p in parts if part_group(p.name) == "gore"]
    assert len(gores) == 24 and len({p.name.split()[1] for p in gores}) == 6
    widths = sorted(p.primitive.radii_m[1] for p in gores if p.name.split()[1] == "1")
    assert widths[0] < 0.5 * widths[-1]  # narrow at the cap, wide at the rim


def test_a_cupcake_wears_a_piped_swirl_in_the_colour_said() -> None:
    """'a cupcake with a swirl of pink buttercream' was a muffin with no frosting: a cupcake's swirl is rings
    narrowing to a point, and 'buttercream' or 'icing' names that part for a colour word."""
    design = catalogue.design_from_text("a cupcake with pink buttercream")
    frosting = [p for p in design.program.parts if part_group(p.name).startswith("frosting")]
    radii = [p.primitive.major_radius_m for p in frosting if p.primitive.kind == "torus"]
    assert len(radii) >= 3 and radii == sorted(radii, reverse=True)
    body = next(p for p in design.program.parts if part_group(p.name) == "cup")
    assert frosting[0].color_rgb != body.color_rgb and frosting[0].color_rgb[0] > frosting[0].color_rgb[2]  # pink
    assert catalogue.design_from_text("a blueberry muffin").entry == "muffin"


def test_salmon_nigiri_is_a_slice_of_fish_over_a_rice_mound() -> None:
    """A two-layer block was named a pink eraser: the fish overhangs the rice at both ends and the rice is white."""
    design = catalogue.design_from_text("one salmon nigiri")
    ext = grammar.program_extents(design.program, 64)
    rice = grammar.program_extents(design.program.model_copy(update={"parts": [
        p for p in design.program.parts if part_group(p.name) in ("body", "ground")]}), 64)
    assert ext[0] > 1.1 * rice[0]  # the fish is longer than its rice
    assert 0.015 <= planned_mass("one salmon nigiri") <= 0.06
    assert catalogue.design_from_text("tuna nigiri").entry == "tuna_nigiri"


def test_a_flat_cushion_said_spiky_has_spikes_on_its_top_face() -> None:
    """'spikes are not drawn: the balance cushion is not ball-like': a flat body takes them on its top face."""
    design = catalogue.design_from_text("a spiky wobble cushion")
    spikes = [p for p in design.program.parts if part_group(p.name) == "spike"]
    assert len(spikes) >= 20
    top = max(p.transform.translation_m[2] for p in design.program.parts[:1])
    assert all(p.transform.translation_m[2] > top for p in spikes)
    assert not any("not drawn" in w for w in design.warnings)


def test_a_half_rolled_mat_is_a_roll_with_its_other_half_lying_flat() -> None:
    """'a bamboo sushi mat, half rolled' was drawn fully rolled: half rolled, the sheet's free half lies flat in
    front of the roll, drawn thick enough to be meshed, and the mat keeps its mass."""
    design = catalogue.design_from_text("a half rolled yoga mat")
    assert "tail" in [part_group(p.name) for p in design.program.parts]
    ext = np.sort(grammar.program_extents(design.program, 64))
    rolled = np.sort(grammar.program_extents(catalogue.design_from_text("a rolled yoga mat").program, 64))
    assert ext[2] > 1.5 * rolled[2]  # the flat half makes it longer than the roll alone
    assert 0.5 <= planned_mass("a half rolled yoga mat") / planned_mass("a rolled yoga mat") <= 1.5
