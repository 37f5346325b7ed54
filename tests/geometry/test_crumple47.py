"""Session 47: crumpled cloths drawn by how they bunch. Blind judges named a crumpled bed sheet, blanket, shirt and
a bunched tablecloth all 'a towel': one thick creased heap served every cloth. A thin cloth (a sheet, a tablecloth,
a napkin, a silk scarf) now crumples into many thin, sharp folds over thin draped flaps; a blanket into a few thick
soft rolls with rolled edges; a towel keeps its creased heap with its woven border; a pattern and a fringe stay on
the heap; a crumpled garment still shows its sleeves' cuffs, its collar and its hem."""

from __future__ import annotations

import pytest

from contracts.shape import MAX_PARTS
from tasks.geometry import catalogue
from tasks.geometry.grammar.goods import SheetParams, sheet
from tasks.geometry.grammar.parts import part_group
from tests.geometry.test_mass_classes import planned_mass


def _parts(text: str, entry: str):  # noqa: ANN202
    d = catalogue.design_from_text(text)
    assert d.entry == entry and d.concept is not None and "crumpled" in d.concept.states, (text, d.entry)
    return d.program.parts


def _groups(parts) -> list[str]:  # noqa: ANN001
    return [part_group(p.name) for p in parts]


def _flap_thickness(parts) -> float:  # noqa: ANN001
    """The thinnest flap's thickness / the heap's mound radius (the mesher's grid is set by the heap's size)."""
    body = next(p for p in parts if p.name == "body")
    return min(p.primitive.size_m[2] for p in parts if part_group(p.name) == "corner") / body.primitive.radii_m[0]


def test_a_thin_sheet_crumples_into_more_and_thinner_folds_than_a_towel() -> None:
    sheet_parts = _parts("a crumpled white bed sheet", "bed_sheet")
    towel_parts = _parts("a crumpled bath towel", "bath_towel")
    assert _groups(sheet_parts).count("fold") >= 2 * _groups(towel_parts).count("fold") >= 10
    assert _flap_thickness(sheet_parts) < 0.8 * _flap_thickness(towel_parts)
    assert "border" in _groups(towel_parts)  # the towel's woven border on its flaps


def test_a_blanket_bunches_into_thick_soft_rolls_a_sheet_does_not() -> None:
    def rolls(parts) -> int:  # noqa: ANN001
        return sum(part_group(p.name) == "fold" and p.primitive.kind == "capsule" for p in parts)

    blanket = _parts("crumpled grey fleece blanket", "throw_blanket")
    assert rolls(blanket) >= 6 and "rolled edge" in _groups(blanket)
    assert rolls(_parts("a crumpled white bed sheet", "bed_sheet")) == 0
    assert rolls(_parts("a crumpled bath towel", "bath_towel")) == 0


def test_a_crumpled_patterned_or_fringed_cloth_keeps_its_pattern_and_fringe() -> None:
    cloth = _groups(_parts("a bunched up tablecloth", "tablecloth"))
    assert cloth.count("stripe") >= 4 and "check" in cloth
    scarf = _groups(_parts("a crumpled silk scarf", "silk_scarf"))
    assert scarf.count("tassel") >= 4 and "stripe" in scarf


@pytest.mark.parametrize("thickness,border,kind", [(0.0002, False, "thin"), (0.00178, False, "thin"),
                                                    (0.00357, True, "terry"), (0.003, False, "terry"),
                                                    (0.004, False, "soft"), (0.00444, True, "terry")])
def test_the_crumple_class_follows_the_cloth_thickness(thickness: float, border: bool, kind: str) -> None:
    from tasks.geometry.grammar.goods import crumple_class

    assert crumple_class(SheetParams(thickness=thickness, border=border)) == kind


@pytest.mark.parametrize("kw", [dict(width=0.8, thickness=0.0002), dict(width=0.78, thickness=0.0003, stripes=9,
                                                                      checks=True, hem=True, fringe=True),
                                dict(width=0.1, thickness=0.0006, stripes=9, fringe=True),
                                dict(width=1.0, thickness=0.005, stripes=9, checks=True, fringe=True),
                                dict(width=0.5, thickness=0.0035, border=True, stripes=9, fringe=True)])
def test_crumpled_cloths_stay_within_the_part_budget(kw: dict) -> None:
    assert len(sheet(SheetParams(state="crumpled", **kw))) <= MAX_PARTS


def test_a_crumpled_shirt_keeps_both_sleeves_their_cuffs_its_collar_and_hem() -> None:
    groups = _groups(_parts("a crumpled shirt on the floor", "long_sleeve_shirt"))
    assert groups.count("sleeve") >= 4 and groups.count("cuff") == 2
    assert "collar" in groups and "hem" in groups and "button" in groups
    tee = _groups(_parts("a crumpled t-shirt in a heap", "t_shirt"))
    assert tee.count("hem") >= 3 and "neckline" in tee  # the short sleeves' hems and the body's


@pytest.mark.parametrize("text,kg", [("a crumpled white bed sheet", 0.6), ("crumpled grey fleece blanket", 1.0),
                                     ("a bunched up tablecloth", 0.5), ("a crumpled silk scarf", 0.05),
                                     ("a crumpled shirt on the floor", 0.22)])
def test_crumpled_cloths_keep_their_mass(text: str, kg: float) -> None:
    assert 0.5 * kg <= planned_mass(text) <= 2.0 * kg
