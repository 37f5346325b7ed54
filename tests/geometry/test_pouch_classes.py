"""Classes the fifth blind set missed (#35), checked on phrasings other than its own: a container noun with a fill is
a sealed pouch weighed by its fill ('a bag of frozen peas', 'a saline bag'), a vacuum-packed piece lies on its
sealed film, a bean bag is a small filled square (not a bean bag chair); slump words settle a round soft body
(flat base, wider than tall, by degree), and panel words give a ball its seams.

Real masses: typical retail or reference figures for the object as described (the source in each line)."""

from __future__ import annotations

import numpy as np
import pytest

from tasks.geometry import catalogue, concepts, grammar
from tasks.geometry.fill_words import read_fill
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.pouch_words import stated_volume_m3, vacuum_contents
from tests.geometry.test_mass_classes import planned_mass

# phrase -> (concept, parts that must be there, longest side band [m], real mass [kg], source)
POUCHES: dict[str, tuple[str, set[str], tuple[float, float], float, str]] = {
    "a bag of frozen garden peas": ("generic_pouch", {"body", "end seal", "crimp"}, (0.18, 0.32), 0.5,
                                    "retail frozen peas: 454 g-1 kg bags (~25 x 18 cm for 500 g)"),
    "a 1 kg bag of frozen mixed veg": ("generic_pouch", {"body", "end seal", "crimp"}, (0.25, 0.42), 1.0,
                                       "stated 1 kg; retail 1 kg frozen vegetable bags ~30 x 22 cm"),
    "a 250 ml pouch of water for a drip": ("generic_pouch", {"body", "port", "hanger tab"}, (0.12, 0.25), 0.26,
                                           "250 ml 0.9 % saline bags, ~0.26-0.28 kg filled (medical supply)"),
    "a packet of penne pasta": ("generic_pouch", {"body", "end seal", "crimp"}, (0.18, 0.32), 0.5,
                                "retail 500 g bags of penne (~25 x 15 cm)"),
    "a sack of play sand, 40 cm long": ("generic_pouch", {"body"}, (0.36, 0.44), 9.0,
                                        "retail play sand sacks: 10-15 kg, ~45 x 30 cm; 40 cm ~8-10 kg"),
    "a bag of blueberries from the freezer": ("generic_pouch", {"body"}, (0.18, 0.32), 0.5,
                                              "retail frozen blueberries: 400-600 g bags"),
    "a sack of potting soil": ("generic_pouch", {"body"}, (0.5, 0.75), 6.0,
                               "the bag a user means unsized: 20-30 l sacks of potting soil, 5-10 kg (independent "
                               "prompt writers: 'bag of potting soil' 5 kg, '20 litre bag' 8 kg; docs/blind/dev38; "
                               "a 1-2 l houseplant sack is the exception, said with its size)"),
    "a lentil bag": ("generic_pouch", {"body"}, (0.18, 0.32), 0.5, "retail 500 g bags of dried lentils"),
    "a litre bag of iv saline": ("generic_pouch", {"body", "port"}, (0.22, 0.36), 1.05,
                                 "1000 ml 0.9 % saline bags 1.03-1.08 kg filled (medical supply)"),
    "a 2 l saline bag": ("iv_bag", {"body", "port"}, (0.3, 0.5), 2.1,
                         "2000 ml irrigation saline bags ~2.1 kg filled"),
    "a toss bean bag for a kids' game": ("small_bean_bag", {"body", "seam"}, (0.08, 0.13), 0.1,
                                         "retail 10 cm toss bean bags (80-120 g)"),
    "a cornhole beanbag full of corn, 15 cm square": ("cornhole_bag", {"body"}, (0.14, 0.17), 0.45,
                                                       "ACL rules: 15 x 15 cm bags of 15.5-16.5 oz (0.44-0.47 kg)"),
    "a frozen gel pack": ("reusable_ice_pack", {"body"}, (0.2, 0.3), 0.45,
                          "retail 25 x 15 cm reusable gel ice packs (0.35-0.55 kg)"),
}

# phrase -> (the piece's concept, real mass [kg], source)
VACUUM_PACKED: dict[str, tuple[str, float, str]] = {
    "a vacuum-packed sirloin steak": ("steak", 0.3, "butcher listings: 10-12 oz sirloin steaks (280-340 g)"),
    "a pork chop sealed in vacuum film": ("pork_chop", 0.2,
                                                                "USDA: pork loin chop, raw, 170-225 g"),
    "a chicken breast in a vacuum bag": ("chicken_breast", 0.22, "USDA: chicken breast, raw, 174-240 g"),
    "a vac-packed salmon fillet": ("salmon_fillet", 0.14, "retail salmon portions 110-170 g"),
    "a raw chicken thigh fillet sealed in a vacuum bag": ("chicken_thigh", 0.11,
                                                          "retail boneless chicken thighs ~100-130 g each"),
}


def _design(text: str) -> catalogue.Design:
    return catalogue.design_from_text(text)


def _longest(d: catalogue.Design) -> float:
    ext = grammar.program_extents(d.program, 48)
    return float(d.size.resolve(ext).max()) if d.size.explicit else float(ext.max())


@pytest.mark.parametrize("text", sorted(POUCHES))
def test_a_container_with_a_fill_is_a_sealed_pouch(text: str) -> None:
    concept, parts, (lo, hi), _real, _source = POUCHES[text]
    d = _design(text)
    assert d.entry == concept, (text, d.entry)
    assert d.concept is not None and d.concept.body_plan == "pouch"
    groups = {part_group(p.name).split()[0] for p in d.program.parts} | {part_group(p.name) for p in d.program.parts}
    assert parts <= groups, (text, groups)
    assert lo <= _longest(d) <= hi, (text, _longest(d))
    ext = np.sort(grammar.program_extents(d.program, 48))
    assert ext[0] < 0.45 * ext[2], (text, ext)  # a flat, pillowy bag, never a block or a ball


@pytest.mark.parametrize("text", sorted(POUCHES))
def test_a_pouch_weighs_its_fill(text: str) -> None:
    _concept, _parts, _size, real, source = POUCHES[text]
    mass = planned_mass(text)
    assert 0.5 <= mass / real <= 2.0, f"{text}: {mass * 1e3:.3g} g, real ~{real * 1e3:g} g ({source})"


@pytest.mark.parametrize("text", sorted(VACUUM_PACKED))
def test_a_vacuum_packed_piece_lies_on_its_sealed_film(text: str) -> None:
    concept, real, source = VACUUM_PACKED[text]
    d = _design(text)
    assert d.entry == concept, (text, d.entry)
    film = [p for p in d.program.parts if p.name == "film"]
    assert film, [p.name for p in d.program.parts]
    assert "vacuum-packed" in d.concept.states  # type: ignore[union-attr]
    bare = catalogue.design_from_text(vacuum_contents(concepts.normalise(text)) or text)
    with_film, without = grammar.program_extents(d.program, 48), grammar.program_extents(bare.program, 48)
    assert with_film[0] > 1.15 * without[0] and with_film[2] < 1.05 * without[2]  # a flat border, no taller
    mass = planned_mass(text)
    assert 0.5 <= mass / real <= 2.0, f"{text}: {mass * 1e3:.3g} g, real ~{real * 1e3:g} g ({source})"


@pytest.mark.parametrize("text, litres", [("a 500 ml bag", 0.5), ("1.5 litre pouch", 1.5), ("a 2 l bladder", 2.0),
                                          ("16 fl oz of juice", 0.47), ("a 20 cm bag", None)])
def test_a_stated_volume_is_read_in_litres(text: str, litres: float | None) -> None:
    v = stated_volume_m3(text)
    assert (v is None) if litres is None else abs(v * 1e3 - litres) < 0.02 * litres, (text, v)


def test_new_fills_are_read() -> None:
    for text, key in (("a bag of frozen peas", "peas"), ("filled with whole corn", "corn"),
                      ("a bag of sweetcorn", "sweetcorn"), ("a bag of saline", "water"), ("dried pasta", None)):
        fill = read_fill(text)
        assert (fill is None and key is None) or (fill is not None and fill.key == key), (text, fill)


def test_a_bean_bag_chair_is_still_a_chair_and_a_bean_bag_is_a_toss_bag() -> None:
    assert _design("a big bean bag chair").entry == "bean_bag_chair"
    assert _design("a beanbag").entry == "small_bean_bag"
    assert not any("ruffle" in p.name for p in _design("a bean bag, 12 cm").program.parts)


# ---- slump and panels ----------------------------------------------------------------------------------------------
def _hw(text: str) -> tuple[float, float, np.ndarray]:
    """(height / width, share of the footprint's area in the bottom slice vs the widest slice, extents)."""
    from tasks.geometry.meshing import mesh_program

    mesh = mesh_program(_design(text).program, 56)
    ext = mesh.extents
    z = mesh.vertices[:, 2]
    bottom = mesh.vertices[z < z.min() + 0.03 * ext[2]]
    return float(ext[2] / ext[:2].max()), float(np.ptp(bottom[:, 0]) / ext[0]) if len(bottom) else 0.0, ext


@pytest.mark.parametrize("text, most", [
    ("a slumping ball of bread dough after its rise", 0.55),
    ("a proved dough ball sitting on a board", 0.55),
    ("a sagging sand-filled slam ball", 0.8),
    ("a ball of cookie dough, a bit slumped", 0.85),  # (the mozzarella is hand-drawn since session 43)
    ("a squashed bocconcini", 0.8),  # (the burrata is drawn by hand, split and slumped, since session 47)
])
def test_slump_words_settle_a_round_body_on_a_flat_base(text: str, most: float) -> None:
    ratio, base, _ext = _hw(text)
    assert ratio <= most, (text, ratio)
    assert base >= 0.35, (text, base)  # a flat underside, not a ball touching the table at a point
    assert "slumped" in (_design(text).concept.states or [])  # type: ignore[union-attr]


def test_slump_is_proportional_to_its_degree_word() -> None:
    slight, _b, _e = _hw("a slightly slumped bocconcini")  # (the mozzarella is drawn by hand since session 43, the
    very, _b, _e = _hw("a very slumped bocconcini")  # burrata since session 47)
    plain, _b, _e = _hw("a bocconcini")
    assert very < slight < plain


def test_a_ball_without_slump_words_stays_round() -> None:
    for text in ("a ball of mozzarella", "a slam ball", "a stress ball"):
        assert "slumped" not in (_design(text).concept.states or []), text  # type: ignore[union-attr]


@pytest.mark.parametrize("text", ["a slam ball with stitched panels", "a paneled leather medicine ball",
                                  "a medicine ball with stitched seams", "a crossfit wall ball"])
def test_panel_words_give_a_ball_seams_from_pole_to_pole(text: str) -> None:
    seams = [p for p in _design(text).program.parts if p.name.startswith("panel seam")]
    assert len(seams) >= 3, text


def test_a_beach_ball_has_coloured_panels() -> None:
    colours = {tuple(np.round(p.color_rgb, 2)) for p in _design("an inflatable beach ball").program.parts}
    assert len(colours) >= 4
