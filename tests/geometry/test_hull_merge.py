"""Our merge of CoACD's pieces down to the hull budget (collision.merge_hulls): neighbours first, least added volume."""

from __future__ import annotations

import numpy as np
import trimesh

from tasks.geometry.collision import GROW_BUDGETS, _coarsen, merge_hulls, merged_to_cover, piece_hull, union_volume


def _box(lo: tuple[float, float, float], size: float = 0.01) -> trimesh.Trimesh:
    return trimesh.creation.box(extents=(size, size, size)).apply_translation(np.asarray(lo) + size / 2)


def _row_and_far_box() -> list[trimesh.Trimesh]:
    """Four 1 cm cubes face to face in a row along x, and a fifth 10 cm away."""
    return [_box((0.01 * i, 0.0, 0.0)) for i in range(4)] + [_box((0.0, 0.1, 0.0))]


def test_pieces_face_to_face_merge_first_and_cover_what_they_covered() -> None:
    parts = merge_hulls(_row_and_far_box(), 2)
    assert len(parts) == 2
    vols = sorted(p.volume for p in parts)
    # the row of four became one 4 cm bar (no volume added), the far cube stayed alone
    np.testing.assert_allclose(vols, [1e-6, 4e-6], rtol=1e-6)
    assert abs(union_volume(parts) - 5e-6) < 1e-9


def test_a_budget_of_one_prices_far_pieces_too() -> None:
    parts = merge_hulls(_row_and_far_box(), 1)
    assert len(parts) == 1
    assert parts[0].is_convex and parts[0].volume > 5e-6  # the joint hull spans the gap


def test_under_the_budget_nothing_changes_and_the_merge_is_deterministic() -> None:
    pieces = _row_and_far_box()
    assert merge_hulls(pieces, 8) is pieces
    a, b = merge_hulls(_row_and_far_box(), 3), merge_hulls(_row_and_far_box(), 3)
    assert [p.volume for p in a] == [p.volume for p in b]
    assert all(np.array_equal(p.vertices, q.vertices) for p, q in zip(a, b, strict=True))


def test_least_added_volume_wins_over_order() -> None:
    """Four cubes in a T: the merge chosen joins two face to face (adds nothing), not the diagonal pair (half a cube)."""
    pieces = [_box((0.0, 0.0, 0.0)), _box((0.01, 0.0, 0.0)), _box((0.01, 0.01, 0.0)), _box((0.02, 0.0, 0.0))]
    parts = merge_hulls(pieces, 3)
    assert len(parts) == 3
    assert abs(sum(p.volume for p in parts) - 4e-6) < 1e-10  # no volume added by the chosen merge


def test_coarse_copy_is_never_finer_than_the_mesh() -> None:
    """A flat tile keeps six cells across its 1.2 cm thickness: that grid is finer than the tile's own mesh."""
    tile = trimesh.creation.box(extents=(0.3, 0.3, 0.012))
    tile = tile.subdivide().subdivide()
    coarse = _coarsen(tile, 6000)
    assert len(coarse.faces) <= len(tile.faces)


def _ring(n: int = 36, radius: float = 0.06) -> list[trimesh.Trimesh]:
    """n 1 cm cubes round a circle of `radius`: a thin hollow good's pieces (a hat's brim, a hose's coil)."""
    a = 2 * np.pi * np.arange(n) / n
    return [_box((radius * np.cos(t), radius * np.sin(t), 0.0)) for t in a]


def test_a_hollow_good_gets_more_hulls_until_they_cover_it_closely() -> None:
    """Merged to 4 hulls a ring's union is many times its volume (each quarter's hull spans the ring's inside);
    merged_to_cover grows the budget until the union is within the ratio asked, and keeps 4 when that is enough."""
    pieces = _ring()
    volume = union_volume(pieces)
    assert union_volume(merge_hulls(pieces, 4)) > 2.0 * volume
    covered = merged_to_cover(pieces, 4, volume, 1.3)
    assert len(covered) in (*GROW_BUDGETS, len(pieces))
    assert union_volume(covered) <= 1.3 * volume
    assert len(merged_to_cover(pieces, 4, volume, 100.0)) == 4


def test_a_flat_or_degenerate_piece_is_dropped_not_an_error() -> None:
    """Unmerged, CoACD returned a three-point sliver for a pair of crumpled gardening gloves: qhull raised and L0
    failed with an internal error (sealed set 18). Such a piece covers nothing and is dropped."""
    tri = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0]])
    assert piece_hull(tri, np.array([[0, 1, 2]])) is None
    flat = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.01, 0.01, 0.0]])
    assert piece_hull(flat, np.array([[0, 1, 2], [1, 3, 2]])) is None
    box = trimesh.creation.box(extents=(0.01, 0.01, 0.01))
    hull = piece_hull(np.asarray(box.vertices), np.asarray(box.faces))
    assert hull is not None and abs(hull.volume - 1e-6) < 1e-12
