"""Classes development set 13 (120 prompts written in session 27 by two reviewers who never opened the repository)
found missing, misread or slow (#35), fixed by class and checked here on other phrasings than the set's.

Real masses: typical retail or rule figures (the source in each line)."""

from __future__ import annotations

import functools

import numpy as np
import pytest
import trimesh

from contracts.errors import InputError
from contracts.lexicon import load_lexicon
from contracts.request import AssetRequest
from tasks.geometry import catalogue, fill_words, goods_words, pipeline
from tasks.geometry.catalogue import check_text_size
from tasks.geometry.collision import convex_parts
from tasks.geometry.pipeline import proxy_parts
from tasks.probes.rigid import RigidBodySpec, placement_probe
from tests.geometry.helpers import run, settings
from tests.geometry.test_mass_classes import planned_mass


@functools.cache
def _draft_l0(text: str) -> tuple:
    """run() of the text at draft, once per text in this module (both hull tests build 'a ball of chunky yarn': the
    default run's sample of each); the tests only read it."""
    return run(AssetRequest(text=text), settings("draft"))


@pytest.mark.parametrize("text", ["a ball of chunky yarn", "a yarn pom pom"])
def test_a_grooved_near_convex_object_is_proxied_by_its_hull(text: str) -> None:
    """A yarn ball's grooves kept CoACD splitting into its whole budget (40 s on a core): its hull covers it."""
    mesh, _info, proxy, _p, _g, checks = _draft_l0(text)
    assert len(proxy["part_vertex_count"]) == 1
    # the hull's own excess (<= 1/0.93) and CoACD's remeshing (a few percent: its voxel copy is slightly fuller)
    assert 1.0 <= checks.metrics["proxy_volume_ratio"] <= 1.15


@pytest.mark.parametrize("text", ["a ball of chunky yarn", "a stress ball", "a peach", "a marshmallow"])
def test_a_near_convex_object_settles_on_the_table(text: str) -> None:
    """A grooved one's hull is CoACD's faceted root hull (the smooth hull of every vertex of a ball kept rolling in
    pybullet: 11 of 40 throughput requests failed L1's settle gate), smooth ones keep CoACD's parts (a marshmallow's
    one root hull jittered on its flat face)."""
    mesh, _info, proxy, _p, _g, _c = _draft_l0(text)
    hulls = proxy_parts(proxy)
    body = RigidBodySpec(hulls_m=[h.vertices for h in hulls], mass_kg=0.1,
                         center_of_mass_m=np.asarray(pipeline.arrays_to_mesh(mesh).center_mass), friction=0.6)
    m = placement_probe(body, duration_s=3.0)
    assert m["place_settle_time_s"] < 2.0


def test_a_concave_object_is_still_decomposed() -> None:
    """A C-shaped body (volume ~0.5 of its hull) is not replaced by its hull."""
    ring = trimesh.creation.annulus(r_min=0.03, r_max=0.05, height=0.02)
    half = ring.slice_plane([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], cap=True)
    parts = convex_parts(half, settings("draft").coacd)
    assert len(parts) > 1
    assert sum(p.volume for p in parts) < 1.3 * half.volume


def test_a_fraction_before_a_unit_is_its_value() -> None:
    """'5/8" x 50 ft garden hose': the hose is 5/8 inch across (was read as 8 inches: 172 kg of hose)."""
    assert catalogue.normalise_sizes('5/8" x 50 ft garden hose').startswith('0.625"')
    assert catalogue.normalise_sizes("1 1/2 in thick foam pad").startswith("1.5 in")
    assert catalogue.normalise_sizes("a 1/2 lb bag of rice") == "a 1/2 lb bag of rice"  # a mass: size_words reads it
    d = catalogue.design_from_text('5/8" x 50 ft garden hose')
    assert "'0.625\"' is its inner diameter" in (d.concept.stated_mass_source or "")  # (a hose's nominal bore)
    assert 0.5 < d.concept.stated_mass_kg < 4.0  # retail: 15 m of 5/8 in hose 1.5-4.5 kg


@pytest.mark.parametrize("text, kg", [("a full 50 lb sack of horse feed", 22.68), ("a bag of chicken feed, 25 kg", 25.0)])
def test_a_stated_mass_with_no_size_sizes_the_object(text: str, kg: float) -> None:
    """The object is built at the size that weighs the stated mass at its own density (a 50 lb feed sack is ~90 cm;
    it was built at the typical 30 cm and weighed 3 kg, its density clamped)."""
    d = catalogue.design_from_text(text)
    built = d.size.longest_m or d.concept.typical_size_m  # (a feed sack entry is that big already: session 29)
    assert built is not None and built > 0.6
    assert 0.7 * kg < planned_mass(text) < 1.4 * kg


@pytest.mark.parametrize("text, one, n", [("two overripe bananas", "an overripe banana", 2),
                                           ("3 tennis balls", "a tennis ball", 3),
                                           ("two ripe peaches", "a ripe peach", 2)])
def test_a_count_of_goods_builds_that_many(text: str, one: str, n: int) -> None:
    """'two bananas' was one banana (half the mass); the pieces lie side by side, the mass n times one's."""
    many, single = catalogue.design_from_text(text), catalogue.design_from_text(one)
    assert f"{n} of them" in many.concept.states
    assert len(many.program.parts) == n * len(single.program.parts)
    assert planned_mass(text) == pytest.approx(n * planned_mass(one), rel=0.15)


@pytest.mark.parametrize("text", ["a 2 m long pool noodle", "two-tone plush bunny", "a 10 cm stress ball"])
def test_sizes_and_compounds_are_no_count(text: str) -> None:
    assert not any(s.endswith("of them") for s in catalogue.design_from_text(text).concept.states)


@pytest.mark.parametrize("text, entry, kg", [
    ("a roll of conforming bandage", "gauze_roll", 0.02),  # 10 cm x 4 m rolls 15-30 g
    ("a pair of wellies", "rubber_boot", 2.0),  # adult wellingtons 1.6-2.4 kg a pair
    ("a baby nasal aspirator", "bulb_syringe", 0.03),  # 20-40 g
    ("a quilted dressage pad", "saddle_pad", 0.45),  # 0.35-0.6 kg
    ("a muay thai pad", "thai_pad", 1.2),  # 1.0-1.5 kg
    ("a silicone pan lid", "suction_lid", 0.11),  # 90-140 g at 20 cm
    ("a fitted cot sheet", "crib_sheet", 0.2),  # 0.15-0.25 kg
    ("a puppy training pad", "underpad", 0.06),  # 30-90 g
    ("an upper radiator hose", "radiator_hose", 0.28),  # 0.2-0.4 kg
    # sealed set 13's, after its run: a rubber band ball was a scrunchie (0.017x), a shop rag a garment (2.2x), a
    # moving blanket a fleece throw (0.42x)
    ("a ball of rubber bands, 3 in", "rubber_band_ball", 0.22),  # 170-250 g
    ("a red cotton rag", "shop_rag", 0.02),  # 16-24 g
    ("a quilted furniture pad", "moving_blanket", 1.7),  # 1.4-2.3 kg
])
def test_new_entries_build_their_object_at_its_mass(text: str, entry: str, kg: float) -> None:
    """Development set 13's missing classes (a gauze roll was a bread roll, rubber boots a rubber ball, a saddle pad
    and a bed pad generic blocks, a suction lid a garment) on other phrasings."""
    assert catalogue.design_from_text(text).entry == entry
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg


def test_stuffed_with_clothes_is_a_fill() -> None:
    fill = fill_words.read_fill("a duffel bag stuffed with dirty laundry")
    assert fill is not None and fill.key == "clothes" and 100.0 <= fill.bulk_density_kg_per_m3 <= 200.0


@pytest.mark.parametrize("text, longest_m", [
    ("a canvas drop cloth, 9 x 12 ft, folded", 2.0),  # folded twice: 1.8 x 1.4 m
    ("king size duvet, 264 x 229 cm, folded in quarters", 1.4),  # its own count: 1.32 x 1.15 m
    ("4 x 8 ft folding gym mat, folded up", 1.3),  # once: 4 x 4 ft
])
def test_a_big_sheet_said_folded_is_built_folded_to_fit(text: str, longest_m: float) -> None:
    """A folded sheet's stated size is its flat size: one larger than L0 builds is refused only if its folded
    footprint is (a 9 x 12 ft drop cloth 'folded' was refused as a 3.7 m object)."""
    check_text_size(AssetRequest(text=text))
    d = catalogue.design_from_text(text)
    drawn = load_lexicon().entries[d.entry].drawn_state if d.entry in load_lexicon().entries else None
    assert "folded" in d.concept.states or drawn == "folded"  # (or a folded drawing of its own: the tumbling mat)
    mesh = pipeline.arrays_to_mesh(pipeline.mesh_from_text(AssetRequest(text=text), settings("draft"))[0])
    assert float(mesh.extents.max()) <= longest_m


@pytest.mark.parametrize("text", ["an 8 x 10 ft tarp", "a 3 m long pool noodle"])
def test_a_big_object_not_folded_is_still_refused(text: str) -> None:
    with pytest.raises(InputError, match="outside the supported range"):
        check_text_size(AssetRequest(text=text))


@pytest.mark.parametrize("text, n", [("2 metre long pool noodle", None), ("5 pound bag of rice", None),
                                     ("a 2 year old's teddy", None), ("ten pin bowling pin plush", None),
                                     ("a 3-pack of sponges", 3), ("a dozen eggs", 12), ("a bag of 4 tennis balls", 4),
                                     ("two-tone bunny", None), ("four teddy bears", 4)])
def test_group_count_reads_counts_not_units(text: str, n: int | None) -> None:
    assert goods_words.group_count(catalogue.normalise_sizes(text)) == n
