"""Sizes that measure a thin good's material and servings of soft desserts (#35), on phrasings other than the fifth
blind set's: a sheet's thickness binds to the sheet (a rolled mat keeps the roll's size), a rope's length and
diameter to the rope (a long one coiled), a band's length to the band laid flat, a tube's outer and inner diameters to the tube; 'a jello cup' is one snack cup's
jelly, not a 300 ml mould.

Real masses: typical retail or reference figures for the object as described (the source in each line)."""

from __future__ import annotations

import pytest

from tasks.geometry import catalogue, grammar
from tasks.geometry.dims_words import _measures
from tests.geometry.test_mass_classes import planned_mass

# phrase -> (concept, longest built extent band [m], shortest built extent band [m], real mass [kg], source)
CASES: dict[str, tuple[str, tuple[float, float], tuple[float, float], float, str]] = {
    "an exercise mat, 8 mm thick, rolled into a tube": (
        "yoga_mat", (0.5, 0.75), (0.1, 0.2), 1.5, "retail 8 mm TPE/PVC exercise mats 1.2-1.8 kg"),
    "a rolled-up yoga mat with a thickness of 4 mm": (
        "yoga_mat", (0.5, 0.75), (0.07, 0.16), 0.9, "retail 4 mm PVC yoga mats 0.8-1.2 kg"),
    "a camping mat 12 mm thick, rolled": (
        "sleeping_pad", (0.45, 0.75), (0.1, 0.25), 0.4, "retail closed-cell foam camping mats 0.3-0.5 kg"),
    "a 5 m length of 12 mm rope": (
        "rope_length", (0.25, 0.6), (0.008, 0.05), 0.45,
        "rope makers' tables: 12 mm nylon ~9 kg per 100 m, 12 mm polyester ~11 kg per 100 m"),
    "two metres of 6 mm cord": (
        "cord_length", (0.15, 0.45), (0.004, 0.03), 0.04, "6 mm accessory cord ~2.2 kg per 100 m"),
    "a 1.5 m rope, 10 mm thick": (
        "rope_length", (0.1, 0.4), (0.008, 0.04), 0.1, "10 mm nylon rope ~6.5 kg per 100 m"),
    "a loop resistance band, 41 inches": (
        "resistance_band", (0.6, 1.1), (0.002, 0.05), 0.17,
        "retail 41 in (208 cm loop) medium pull-up bands, 2.2 cm wide: 0.15-0.2 kg"),
    # a tube's outer and inner diameters bind to the tube; it weighs its wall
    "50 cm of silicone tube, ID 6 mm, OD 9 mm": (
        "tubing", (0.08, 0.16), (0.004, 0.03), 0.02, "0.5 m x pi/4 (9^2 - 6^2) mm^2 = 17.7 cm^3 of silicone at 1.15 g/cm^3"),
    "one metre of aquarium air tubing, 4 mm inner diameter and 6 mm outer diameter": (
        "tubing", (0.15, 0.3), (0.004, 0.03), 0.019, "1 m x pi/4 (6^2 - 4^2) mm^2 = 15.7 cm^3 of PVC / silicone"),
    "2 m of latex tubing with a 6 mm bore": (
        "tubing", (0.3, 0.6), (0.005, 0.05), 0.085, "2 m of 6 mm ID, ~9.5 mm OD latex tubing: 88 cm^3 at 0.95 g/cm^3"),
    "a jelly cup": ("jelly", (0.05, 0.08), (0.025, 0.06), 0.11, "retail 4 oz (113 g) gelatin snack cups"),
    "a cup of lime jello": ("jelly", (0.05, 0.08), (0.025, 0.06), 0.11, "retail 4 oz (113 g) gelatin snack cups"),
    "a pudding snack cup, turned out": ("jelly", (0.05, 0.08), (0.025, 0.06), 0.1,
                                        "retail 3.25-4 oz (92-113 g) pudding snack cups"),
}


@pytest.mark.parametrize("text", sorted(CASES))
def test_material_sizes_bind_to_the_material(text: str) -> None:
    concept, (lo, hi), (tlo, thi), _real, _source = CASES[text]
    d = catalogue.design_from_text(text)
    assert d.entry == concept, (text, d.entry)
    ext = grammar.program_extents(d.program, 64)
    ext = d.size.resolve(ext) if d.size.explicit else ext
    assert lo <= ext.max() <= hi, (text, ext)
    assert tlo <= ext.min() <= thi, (text, ext)


@pytest.mark.parametrize("text", sorted(CASES))
def test_material_sized_goods_weigh_what_they_are(text: str) -> None:
    _concept, _size, _thin, real, source = CASES[text]
    mass = planned_mass(text)
    assert 0.5 <= mass / real <= 2.0, f"{text}: {mass * 1e3:.3g} g, real ~{real * 1e3:g} g ({source})"


def test_a_thicker_sheet_weighs_more_and_rolls_fatter() -> None:
    thin = catalogue.design_from_text("a yoga mat 4 mm thick, rolled up")
    thick = catalogue.design_from_text("a yoga mat 10 mm thick, rolled up")
    assert grammar.program_extents(thick.program, 64).min() > 1.15 * grammar.program_extents(thin.program, 64).min()
    assert planned_mass("a yoga mat 10 mm thick, rolled up") > 1.5 * planned_mass("a yoga mat 4 mm thick, rolled up")


@pytest.mark.parametrize("text, expect", [
    ("a 3 m length of 10 mm rope", [("length", 3.0), (None, 0.01)]),
    ("a mat 6mm thick", [("thickness", 0.006)]),
    ("rope, diameter 8 mm, 2 m long", [("diameter", 0.008), ("length", 2.0)]),
    ("3 m of 10 mm OD 7 mm ID hose", [(None, 3.0), ("diameter", 0.01), ("inner", 0.007)]),
    ("tube, I.D. 4 mm, outside diameter 7 mm", [("inner", 0.004), ("diameter", 0.007)]),
])
def test_measures_say_what_they_measure(text: str, expect: list[tuple[str | None, float]]) -> None:
    got = [(w, round(v, 4)) for w, v, _s in _measures(text)]
    assert got == [(w, round(v, 4)) for w, v in expect]


def test_a_plain_sheet_or_strip_keeps_its_stated_size() -> None:
    d = catalogue.design_from_text("a bath towel 140 cm long")
    assert d.size.extents_m[0] == pytest.approx(1.4)
