"""The stills a user sees: a material's finish (gloss, grain, mottle) and a scale bar that tells the size (#35: a makeup
pad read as a plate, tofu and a marshmallow as soap)."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
import trimesh
import yaml

from tasks.render.finish import FINISHES, MATTE, finish_for, value_noise
from tasks.render.scale_bar import _text_mask, bar_length_m, draw_scale_bar, length_label
from tasks.render.views import render_view, write_renders


def _ball(radius_m: float, rgb: tuple[int, int, int] = (200, 200, 200)) -> trimesh.Trimesh:
    ball = trimesh.creation.icosphere(subdivisions=4, radius=radius_m)
    ball.visual.vertex_colors = np.tile([*rgb, 255], (len(ball.vertices), 1))
    return ball


def _inked_columns(img: np.ndarray, rows: slice) -> np.ndarray:
    return np.flatnonzero((img[rows].max(axis=2) < 100).any(axis=0))


@pytest.mark.parametrize(("metres_per_pixel", "width", "length", "label"), [
    (0.001, 384, 0.1, "10 cm"), (0.0002, 384, 0.02, "2 cm"), (0.004, 384, 0.2, "20 cm"),
    (0.01, 384, 1.0, "1 m"), (0.00001, 384, 0.001, "1 mm"), (0.03, 384, 2.0, "2 m"), (0.0005, 384, 0.05, "5 cm")])
def test_the_bar_is_the_longest_round_length_within_a_third_of_the_width(metres_per_pixel: float, width: int,
                                                                         length: float, label: str) -> None:
    got = bar_length_m(metres_per_pixel, width)
    assert got == pytest.approx(length) and length_label(got) == label
    assert got <= 0.32 * width * metres_per_pixel < 2.5 * got  # no shorter round length would do


def test_the_bar_is_drawn_at_its_length_in_pixels() -> None:
    """The drawn bar spans its length / metres per pixel (to a pixel), in the bottom-left corner, with a label."""
    img = np.full((384, 384, 3), 255, np.uint8)
    length = draw_scale_bar(img, 0.0005)
    bar_rows = slice(384 - 12, 384 - 6)
    cols = _inked_columns(img, bar_rows)
    assert length == pytest.approx(0.05)
    assert abs((cols.max() - cols.min() + 1) - 0.05 / 0.0005) <= 1 and cols.min() < 20
    label_rows = slice(384 - 40, 384 - 16)
    assert _inked_columns(img, label_rows).size > 10  # the label "5 cm" is inked above it
    assert (img[:300] == 255).all()  # nothing else is touched


def test_the_font_draws_every_character_of_a_label() -> None:
    mask = _text_mask("0123456789. cm", 2)
    assert mask.shape == (14, 2 * (6 * 14 - 1)) and mask.any()
    with pytest.raises(KeyError):
        _text_mask("5 in", 1)  # a unit the font (and SI) does not hold


def test_a_small_object_shows_a_small_bar_and_a_large_one_a_large_bar() -> None:
    """The same sphere at 3 cm and 60 cm across looks alike but for its bar: 1 cm against 20 cm."""
    small = render_view(_ball(0.015), "front", 384, MATTE, scale_bar=True)
    large = render_view(_ball(0.30), "front", 384, MATTE, scale_bar=True)
    rows = slice(384 - 12, 384 - 6)
    assert _inked_columns(small, rows).size == pytest.approx(_inked_columns(large, rows).size, abs=2)  # same pixels
    frame = {r: 2 * r / 0.85 for r in (0.015, 0.30)}  # ortho height of each frame [m]
    assert bar_length_m(frame[0.015] / 384, 384) == pytest.approx(0.01)
    assert bar_length_m(frame[0.30] / 384, 384) == pytest.approx(0.2)


def test_a_glossy_finish_has_a_highlight_a_matte_one_does_not() -> None:
    """Rubber and gel show a white highlight on a coloured ball (a channel at 255 where the albedo's red is 150);
    matte does not."""
    ball = _ball(0.05, (150, 40, 40))
    glossy = render_view(ball, "front", 128, FINISHES["gel"]).astype(int)
    matte = render_view(ball, "front", 128, MATTE).astype(int)
    on = matte.min(axis=2) < 250
    assert (glossy[on][:, 1] > 150).sum() > 5  # green far above the albedo's only in a highlight
    assert (matte[on][:, 1] < 80).all()


def test_a_foams_grain_shows_on_a_sponge_and_fades_on_a_mattress() -> None:
    """The same grain (1.2 mm pores) breaks up the shading of a 10 cm ball (pixel 0.3 mm) and not of a 2 m one
    (5 mm pixels: below two pixels a grain is faded, not aliased)."""
    def roughness(radius: float, finish) -> float:  # noqa: ANN001
        img = render_view(_ball(radius), "front", 256, finish).astype(float).mean(axis=2)
        core = img[100:156, 100:156]
        return float(np.abs(np.diff(core, axis=1)).mean())
    foam = FINISHES["pu_foam"]
    assert roughness(0.05, foam) > 3 * roughness(0.05, MATTE)
    assert roughness(1.0, foam) < 1.5 * roughness(1.0, MATTE)


def test_finishes_follow_the_material_then_the_category() -> None:
    assert finish_for("sponge") is FINISHES["sponge"]
    assert finish_for(None, "baked_good") is FINISHES["bread"]
    assert finish_for("nonexistent", None) is MATTE
    materials = set(yaml.safe_load(
        (Path(__file__).parents[2] / "contracts" / "vocab" / "materials.yaml").read_text())["materials"])
    assert set(FINISHES) == materials  # every material class has its finish


def test_the_noise_is_deterministic_and_smooth() -> None:
    pts = np.random.default_rng(3).uniform(-5, 5, (500, 3))
    a, b = value_noise(pts, 1), value_noise(pts, 1)
    assert np.array_equal(a, b) and 0.0 <= a.min() and a.max() < 1.0 and a.std() > 0.1
    near = value_noise(pts + 1e-4, 1)
    assert np.abs(near - a).max() < 1e-2  # continuous


def test_the_written_stills_carry_the_bar(tmp_path: Path) -> None:
    write_renders(_ball(0.03), tmp_path, 128, FINISHES["rubber"])
    img = iio.imread(tmp_path / "front.png")
    assert _inked_columns(img, slice(128 - 8, 128 - 3)).size > 5


def test_every_lexicon_look_is_a_finish_and_reaches_the_concept() -> None:
    """An entry's `finish` names one of LOOKS or the white powder of DUSTED, joined by '+' (a typo would silently fall
    back to its material's), and the concept L0 records carries it to the stills."""
    from contracts.lexicon import load_lexicon
    from tasks.geometry import catalogue
    from tasks.render.finish import DUSTED, LOOKS

    looks = {w for e in load_lexicon().entries.values() if e.finish for w in e.finish.split("+")}
    assert looks and looks <= set(LOOKS) | {DUSTED}
    concept = catalogue.design_from_text("a salmon fillet").concept
    assert concept is not None and concept.finish == "fish"
    assert finish_for(concept.default_material, concept.category, concept.finish) is LOOKS["fish"]


def test_a_fillet_shows_pale_fat_lines_across_it() -> None:
    """The 'fish' look draws pale lines across a salmon-coloured slab: along its length the top's brightness rises and
    falls about every 11 mm; the plain gel finish is even."""
    from tasks.render.finish import LOOKS

    slab = trimesh.creation.box((0.15, 0.06, 0.02)).subdivide().subdivide()
    slab.visual.vertex_colors = np.tile([230, 102, 77, 255], (len(slab.vertices), 1))
    top = {}
    for name, fin in (("fish", LOOKS["fish"]), ("gel", FINISHES["gel"])):
        img = render_view(slab, "top", 256, fin).astype(float)
        row = img[128, 40:216, 2]  # blue rises towards white on a line
        top[name] = row
    def lines(row: np.ndarray) -> int:  # runs of pixels 30 levels above their neighbourhood's median
        from scipy.ndimage import median_filter
        above = (row - median_filter(row, size=15, mode="nearest")) > 30
        return int(np.count_nonzero(np.diff(above.astype(int)) == 1))
    assert lines(top["fish"]) >= 8 and lines(top["gel"]) == 0  # ~11 lines over the slab's middle 11 cm
