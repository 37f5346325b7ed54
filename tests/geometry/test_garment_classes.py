"""Garment and carried-goods classes (#35), checked on phrasings of their own: trousers lie flat with two legs apart
below a waistband, a scarf is a long thin flat strip with a fringe, a film carrier bag has two handle loops, a
drawstring backpack its cords and a backpack its straps, a puffer its quilted baffles, and a flat good folded in half
is a double layer half as long."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from tasks.geometry import catalogue
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import mesh_program, sample_program


def _design(text: str) -> catalogue.Design:
    d = catalogue.design_from_text(text)
    assert d.concept is not None, text
    return d


def _groups(d: catalogue.Design) -> list[str]:
    return [part_group(p.name) for p in d.program.parts if p.operation == "union"]


def _top(program, resolution: int = 96) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """(silhouette from above (x, y), height of the top surface over it in cells) from the signed distances."""
    field, _, _ = sample_program(program, resolution)
    inside = np.asarray(field < 0)
    top = np.where(inside.any(axis=2), inside.shape[2] - np.argmax(inside[:, :, ::-1], axis=2), 0)
    return inside.any(axis=2), top


def _runs(line: np.ndarray) -> int:
    """Separate runs of True along a line."""
    return int(np.sum(np.diff(np.concatenate([[0], line.astype(int), [0]])) == 1))


def _mass(d: catalogue.Design) -> float:
    assert d.concept is not None and d.concept.density_kg_per_m3
    return d.concept.density_kg_per_m3 * float(mesh_program(d.program, 64).volume)


def test_a_pair_of_trousers_is_one_garment_with_two_legs_apart_below_a_waistband() -> None:
    d = _design("a pair of khaki cargo pants laid flat")
    assert d.entry == "trousers"
    groups = _groups(d)
    assert groups.count("leg") == 2 and groups.count("waistband") == 1  # one pair, not two laid over each other
    mask, _ = _top(d.program)
    xs = np.flatnonzero(mask.any(axis=1))
    hem_end, waist_end = xs[0], xs[-1]  # the legs end at -x, the waist at +x
    near_hems = mask[hem_end + (waist_end - hem_end) // 10]
    below_crotch = mask[hem_end + (waist_end - hem_end) // 2]
    near_waist = mask[waist_end - 3]
    assert _runs(near_hems) == 2 and _runs(below_crotch) == 2 and _runs(near_waist) == 1
    gap_hem = np.flatnonzero(near_hems)
    gap_hem = np.diff(gap_hem).max()
    gap_crotch = np.diff(np.flatnonzero(below_crotch)).max()
    assert gap_hem > gap_crotch >= 2  # the crotch gap widens towards the hems
    ext = mesh_program(d.program, 64).extents
    assert ext[2] < 0.12 * ext[0]  # laid flat


def test_a_scarf_is_a_long_thin_flat_strip_with_a_fringe_and_rolls_up() -> None:
    d = _design("a striped wool scarf")
    assert d.entry == "scarf"
    ext = mesh_program(d.program, 64).extents
    length, width, thick = sorted(ext, reverse=True)
    assert 1.3 <= length <= 2.0 and 0.12 <= width <= 0.3 and length > 6 * width and width > 3 * thick
    assert _groups(d).count("tassel") >= 6
    rolled = _design("a rolled-up cashmere muffler")
    assert rolled.entry == "scarf" and rolled.concept is not None and rolled.concept.states == ["rolled"]
    r = mesh_program(rolled.program, 64).extents
    assert r.max() < 2.5 * r.min() and r.max() < 0.4  # a roll, not a strip
    assert _mass(rolled) == pytest.approx(_mass(d), rel=0.3)  # the same scarf
    loop = _design("a fleece scarf lying in a loose loop")
    assert loop.concept is not None and loop.concept.states == ["loop"]
    lmask, _ = _top(loop.program)
    assert (ndimage.binary_fill_holes(lmask) & ~lmask).sum() < 0.01 * lmask.sum()  # open: a U, not a ring
    assert _runs(lmask[lmask.shape[0] * 3 // 4]) == 2  # its two arms


def test_a_film_carrier_bag_has_two_handle_loops_and_is_thin() -> None:
    d = _design("a white plastic supermarket bag")
    assert d.concept is not None and d.concept.body_plan == "bag"
    mask, _ = _top(d.program)
    holes, n = ndimage.label(ndimage.binary_fill_holes(mask) & ~mask)
    sizes = ndimage.sum(np.ones_like(holes), holes, range(1, n + 1))
    assert (sizes > 4).sum() == 2  # a loop through each handle
    ext = mesh_program(d.program, 64).extents
    assert ext[2] < 0.1 * ext.max()
    assert _groups(d).count("crease") >= 5


def test_drawstring_backpacks_have_cords_and_backpacks_straps_and_a_handle() -> None:
    sack = _design("a red cinch sack")
    assert sack.entry == "drawstring_backpack"
    groups = _groups(sack)
    assert groups.count("cord") >= 8 and "casing" in groups
    mask, _ = _top(sack.program)
    body_rows = np.flatnonzero(mask.any(axis=1))
    mid = mask[body_rows[len(body_rows) // 2]]
    assert _runs(mid) == 3  # a cord, the body, a cord: the cords lie apart from the sides
    pack = _design("a kids rucksack")
    assert pack.entry == "backpack"
    groups = _groups(pack)
    assert groups.count("strap") >= 4 and "handle" in groups and "pocket" in groups
    ext = mesh_program(pack.program, 64).extents
    assert np.argmax(ext) == 2  # standing
    assert 0.5 <= _mass(pack) / 0.5 <= 2.0


def _groove_count(program, column_share: float, along_y: bool = False) -> int:  # noqa: ANN001
    """Grooves (dips of at least a cell between higher ground) along x (or y) in the top surface at a y (or x) share of
    the width (length)."""
    mask, top = _top(program, 128)
    if along_y:
        mask, top = mask.T, top.T
    ys = np.flatnonzero(mask.any(axis=0))
    y = ys[0] + int(column_share * (ys[-1] - ys[0]))
    line = top[:, y][mask[:, y]].astype(float)
    dips = 0
    for i in range(2, len(line) - 2):
        if line[i] <= line[i - 1] and line[i] < line[i + 1] and max(line[: i].max(), 0) - line[i] >= 1 \
                and line[i + 1:].max() - line[i] >= 1:
            dips += 1
    return dips


def test_puffer_garments_and_duvets_are_quilted_thick_and_weigh_as_padded() -> None:
    puffer, plain = _design("a quilted navy gilet"), _design("a navy fleece vest")
    assert puffer.entry == plain.entry == "gilet"
    e_puff, e_plain = (mesh_program(d.program, 64).extents for d in (puffer, plain))
    assert e_puff[2] > 1.6 * e_plain[2]  # puffy
    assert _groove_count(puffer.program, 0.3) >= 4 and _groove_count(plain.program, 0.3) == 0
    assert 1.0 <= _mass(puffer) / _mass(plain) <= 2.0  # a padded vest weighs a little more, not its volume more
    coat = _design("a padded winter parka")
    assert "zip" in _groups(coat) and _groove_count(coat.program, 0.3) >= 4
    assert 0.5 <= _mass(coat) / 0.8 <= 2.0
    duvet = _design("a king size comforter")
    assert duvet.entry == "duvet"
    assert _groove_count(duvet.program, 0.3) >= 3 and _groove_count(duvet.program, 0.3, along_y=True) >= 3  # squares


@pytest.mark.parametrize("noun", ["rug", "hand towel"])
def test_a_flat_good_folded_in_half_is_a_double_layer_half_as_long(noun: str) -> None:
    flat = _design(f"a {noun} lying flat")
    folded = _design(f"a {noun} folded in half")
    assert folded.concept is not None and folded.concept.states == ["folded"]
    ef = mesh_program(flat.program, 96).extents
    eh = mesh_program(folded.program, 96).extents
    assert eh[2] == pytest.approx(2 * ef[2], rel=0.25)  # two layers
    long_axis = int(np.argmax(ef))
    assert eh[long_axis] == pytest.approx(ef[long_axis] / 2, rel=0.12)  # folded across its length
    assert _mass(folded) == pytest.approx(_mass(flat), rel=0.2)  # the same mat
    thirds = _design(f"a {noun} folded in thirds")
    et = mesh_program(thirds.program, 96).extents
    assert et[2] == pytest.approx(3 * ef[2], rel=0.25) and et[long_axis] == pytest.approx(ef[long_axis] / 3, rel=0.15)


def test_a_folded_tee_is_a_neat_thin_rectangle_with_its_collar_and_sleeve_folds() -> None:
    d = _design("a neatly folded black tshirt")
    assert d.entry == "t_shirt" and d.concept is not None and d.concept.states == ["folded"]
    ext = mesh_program(d.program, 64).extents
    assert ext[2] < 0.2 * ext[:2].min()
    groups = _groups(d)
    assert groups.count("sleeve") == 2 and "collar band" in groups
