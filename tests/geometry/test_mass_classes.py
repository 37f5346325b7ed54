"""Objects L1 weighed wrongly, fixed by class (#35), checked on phrasings other than the blind prompts that showed
them: noun-noun compounds take their last noun as the head; thin shells and films weigh their wall (area x wall x
density), never the air inside; 'X-shaped Y' weighs what Y weighs; a long plush keeps its stuffed cross-section;
gloves are rubber or knit by their material word; a family word ('foam', 'latex') keeps the concept's material.

Real masses: typical retail or reference figures for the object as described (the range in each source line)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from contracts.lexicon import load_lexicon
from contracts.request import AssetRequest
from contracts.stage import load_contract
from tasks.agents.intent import asset_material, asset_targets, concept_of
from tasks.agents.vocab import load_material_vocab
from tasks.geometry import catalogue, grammar, pipeline
from tasks.geometry.catalogue import normalise_sizes, parse_size
from tasks.geometry.concepts import PLUSH_MASS_EXPONENT_UP
from tasks.geometry.shell import Surface
from tasks.physical.mass import mass_check

# phrase -> the lexicon concept it builds
CONCEPTS: dict[str, str] = {
    "a cheese croissant": "croissant",
    "an almond croissant": "croissant",
    "a ball of bread dough ready to rise": "dough_ball",
    "a cotton oven mitt": "oven_mitt",
    "a denim oven mitt": "oven_mitt",
    "a neoprene elbow sleeve": "compression_sleeve",
    "a compression calf sleeve": "compression_sleeve",
    "a white plastic carrier bag": "carrier_bag",
    "a crumpled plastic shopping bag": "carrier_bag",
    "a zip-lock freezer bag": "zip_bag",
    "a blue latex balloon": "balloon_party",
    "a helium balloon": "balloon_party",
    "latex exam gloves": "disposable_glove",
    "a blue nitrile glove": "disposable_glove",
    "a latex blue glove": "glove_rubber",
    "a pair of yellow rubber household gloves": "glove_rubber",
    "a wool glove": "knit_glove",
    "a rubber wrist band": "rubber_wristband",
    "a flat blue exercise band": "therapy_band",
    "a yellow therapy band": "therapy_band",
    "a heart-shaped cushion": "cushion",
    "a star-shaped plush pillow": "plush_toy_pillow",
    "a cushion shaped like a cat": "cushion",
    "a long plush snake": "plush_snake",
    "a foam garden kneeler": "knee_pad",
    "a foam kneeling mat for gardening": "knee_pad",
}

# phrase -> (real mass [kg], source): L1's planned mass must be within 2x
MASSES: dict[str, tuple[float, str]] = {
    "a cheese croissant": (0.057, "USDA FoodData Central: croissant, cheese, medium 57 g"),
    "a cotton oven mitt": (0.1, "retail listings of quilted cotton oven mitts (80-130 g)"),
    "a neoprene elbow sleeve": (0.08, "retail listings of 3-5 mm neoprene elbow and knee sleeves (60-150 g)"),
    "a white plastic carrier bag": (0.0055, "HDPE T-shirt carrier bags, 15-20 um (4-7 g)"),
    "a crumpled plastic shopping bag": (0.0055, "HDPE T-shirt carrier bags, 15-20 um (4-7 g)"),
    "a zip-lock freezer bag": (0.006, "quart freezer bags, 2.7 mil LDPE with a zip track (5-7 g)"),
    "a deflated beach ball": (0.15, "retail listings of 40-50 cm vinyl beach balls (0.1-0.25 kg)"),
    "a blue latex balloon": (0.0035, "12 in latex party balloons, 3-4 g of latex"),
    "a deflated party balloon": (0.0035, "12 in latex party balloons, 3-4 g of latex"),
    "latex exam gloves": (0.005, "disposable nitrile or latex exam gloves, size M, 4-6 g each"),
    "a blue nitrile glove": (0.005, "disposable nitrile or latex exam gloves, size M, 4-6 g each"),
    "a pair of yellow rubber household gloves": (0.075, "household latex gloves, 60-90 g a pair"),
    "a rubber wrist band": (0.006, "202 x 12 x 2 mm silicone wristbands (5-7 g)"),
    "a yellow therapy band": (0.06, "1.5 m latex therapy bands (40-90 g by resistance)"),
    "a flat blue exercise band": (0.06, "1.5 m latex therapy bands (40-90 g by resistance)"),
    "a heart-shaped cushion": (0.35, "retail listings of 40 cm heart-shaped cushions (0.25-0.5 kg)"),
    "a star-shaped plush pillow": (0.3, "retail listings of 30-40 cm plush star pillows (0.2-0.4 kg)"),
    "a cushion shaped like a cat": (0.35, "retail listings of 40 cm cat-shaped cushions (0.25-0.5 kg)"),
    "a plush snake one metre long": (0.3, "retail listings of 40 in (1 m) plush snakes (0.25-0.4 kg)"),
    "a foam garden kneeler": (0.2, "retail listings of 45 x 25 cm EVA foam garden kneelers (0.15-0.25 kg)"),
    "a foam knee pad": (0.5, "retail listings of pairs of gel and foam work knee pads (0.4-0.6 kg the pair; built as the pair)"),
    # stuffed toys weigh their sourced mass at the built size, whatever the grammar's body volume or pose
    "a soft toy rabbit with long floppy ears": (0.2, "Jellycat Bashful Bunny medium, 31 cm, ~0.2 kg"),
    "a stuffed elephant sitting up": (0.25, "retail listings of 25 cm plush elephants (0.2-0.4 kg)"),
    "a handmade sock monkey": (0.2, "retail listings of 45-50 cm sock monkeys (0.15-0.3 kg)"),
    "a plush kitten curled up asleep": (0.2, "retail listings of 30 cm plush cats (0.15-0.3 kg)"),
    # a heavier grade of the good's material, named before its noun
    "a memory foam bed pillow": (1.3, "retail listings of standard 60 x 40 x 12 cm memory-foam pillows (1-1.8 kg)"),
    "a memory foam seat cushion": (0.9, "retail listings of 45 x 35 x 7 cm memory-foam seat cushions (0.7-1.3 kg)"),
    "a neoprene pencil case": (0.07, "retail listings of 20 cm neoprene zip pencil cases (50-90 g)"),
    "a neoprene sleeve for a 13 inch laptop": (0.22, "retail listings of 13 in neoprene laptop sleeves (0.15-0.3 kg)"),
    "a gel cold pack": (0.45, "retail listings of 25 x 15 cm reusable gel packs (0.35-0.55 kg)"),
    "a zip-up toiletry bag": (0.1, "retail listings of 22 cm zipped toiletry bags (60-150 g)"),
}


@functools.cache  # (a pure function of the text: tests of several classes ask for the same texts)
def planned_mass(text: str) -> float:
    """L1's planned mass [kg] of a text as L0 builds it at draft: the mass check's density x the mesh volume, with
    the material L1 reads (tasks.agents.intent) and the L1 contract's density bounds."""
    request = AssetRequest(text=text)
    mesh_arrays, info = pipeline.mesh_from_text(request, pipeline.settings_from_contract("draft"))
    mesh = pipeline.arrays_to_mesh(mesh_arrays)
    record = {"info": {"concept": info.concept.model_dump(mode="json") if info.concept else None},
              "request": request.model_dump(mode="json")}
    vocab = load_material_vocab()
    words = asset_targets(record, None, vocab)
    material = asset_material(record, words, vocab)
    rho = words.priors["density_kg_per_m3"]
    drange = vocab.materials[material].prior_ranges.get("density_kg_per_m3", (rho / 2, rho * 2))
    field = load_contract("L1").field("density_kg_per_m3")
    check = mass_check(float(mesh.volume), float(mesh.extents.max()), float(mesh.area), material, rho, drange,
                       concept_of(record), vocab.materials[material].shell_wall_thickness_m, False,
                       (field.low, field.high), surface=Surface.of(mesh))  # as L1 (tasks.physical.plan.l1_plan)
    return check.density_kg_per_m3 * float(mesh.volume)


def assert_builds_at_its_mass(text: str, entry: str, kg: float) -> None:
    """The request builds the lexicon entry `entry` and L1 plans its mass within 2x of the real `kg` (the check of
    every development list's and redraw's goods)."""
    assert catalogue.design_from_text(text).entry == entry, text
    mass = planned_mass(text)
    assert 0.5 <= mass / kg <= 2.0, f"{text}: {mass:.3g} kg, real ~{kg:g} kg"


@pytest.mark.parametrize("text", sorted(CONCEPTS))
def test_phrase_builds_its_concept(text: str) -> None:
    d = catalogue.design_from_text(text)
    assert d.concept is not None and d.entry == CONCEPTS[text], (text, d.entry)


@pytest.mark.parametrize("text", sorted(MASSES))
def test_planned_mass_within_2x_of_the_real_one(text: str) -> None:
    real, source = MASSES[text]
    mass = planned_mass(text)
    assert 0.5 <= mass / real <= 2.0, f"{text}: {mass * 1e3:.3g} g, real ~{real * 1e3:g} g ({source})"


def test_an_inflated_balloon_does_not_weigh_its_air() -> None:
    """A 28 cm party balloon holds ~9 l of air (~11 g): its mass is the latex's ~3.5 g, below the old 10 kg/m^3."""
    assert planned_mass("a red inflated balloon, latex") < 0.007


@pytest.mark.parametrize("text,metres", [("a plush snake about a metre long", 1.0),
                                         ("half a metre long plush caterpillar", 0.5),
                                         ("a foot tall teddy", 0.3048), ("a plush snake with a foot", None)])
def test_number_words_before_a_unit_are_sizes(text: str, metres: float | None) -> None:
    size = parse_size(normalise_sizes(text))
    given = [v for v in (*size.extents_m, size.longest_m) if v is not None]
    assert (given[0] if given else None) == (pytest.approx(metres) if metres else None)


def test_a_stretched_plush_keeps_its_density_and_a_bigger_one_scales_as_its_area() -> None:
    """'a long plush snake' is stretched along its length: the same stuffing per length, so its mass follows the
    built volume; a snake scaled up evenly grows as length^1.5 (retail plush: big ones are stuffed looser), not
    length^3."""
    typical = catalogue.design_from_text("a plush snake")
    long_ = catalogue.design_from_text("a long plush snake")
    big = catalogue.design_from_text("a plush snake 1.2 m long")
    assert long_.concept is not None and typical.concept is not None and big.concept is not None
    assert long_.concept.density_kg_per_m3 == pytest.approx(typical.concept.density_kg_per_m3)
    ratio = 1.2 / (typical.concept.typical_size_m or 1.0)
    assert typical.concept.density_kg_per_m3 is not None
    assert big.concept.density_kg_per_m3 == pytest.approx(
        typical.concept.density_kg_per_m3 * ratio ** (PLUSH_MASS_EXPONENT_UP - 3), rel=0.05)


def test_a_shell_weighs_its_area_times_its_wall() -> None:
    """The film rule: a glove twice as long has four times the rubber (area), not eight (volume)."""
    small, large = planned_mass("a nitrile exam glove 20 cm long"), planned_mass("a nitrile exam glove 40 cm long")
    assert np.log2(large / small) == pytest.approx(2.0, abs=0.3)


@pytest.mark.parametrize("text", ["a tortilla 20 cm across", "a cotton cloth 30 x 30 cm"])
def test_a_thin_good_with_stated_sides_builds(text: str) -> None:
    """A sheet 2-8 mm thick with its sides stated is built (the stretch is measured on its parts' box when the coarse
    grid misses its thickness), not refused as having no volume."""
    from tasks.geometry import catalogue, grammar

    design = catalogue.design_from_text(text)
    ext = grammar.program_extents(design.program, 96)
    assert ext[2] < 0.05 * ext[0] and ext[0] > 0.15


def drawn_mass_kg(key: str) -> float:
    """A hand-drawn entry's mass as L0 draws it: its density over its catalogue shape's volume at size_m (the draft
    mesh, 48 cells), the check that its density is the sourced mass over the built volume."""
    from tasks.geometry.catalogue_programs import catalogue_program  # lazy: the redraw tests' slow density checks only
    from tasks.geometry.meshing import mesh_program  # lazy: the redraw tests' slow density checks only

    e = load_lexicon().entries[key]
    prog = catalogue_program(str(e.catalogue))
    scale = e.size_m / float(np.max(grammar.program_extents(prog, 48)))
    return float(e.solid_density_kg_per_m3 * mesh_program(prog, 48).volume * scale ** 3)

