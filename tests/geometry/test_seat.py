"""A standing soft toy gets a flat base it can lean on (canonical.seat_flat): the plush penguin of #36 stood on a
rounded bottom that held a lean of 6 deg, and fell over when the robot set it down 2 deg off its rest pose."""

from __future__ import annotations

import pytest
import trimesh

from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources
from tasks.geometry.canonical import SEAT_TIP_DEG, seat_flat, tip_angle_deg
from tests.geometry.helpers import settings


def _standing_egg() -> trimesh.Trimesh:
    """An egg on its round end: the centre of mass 5 cm over a base a few mm wide."""
    egg = trimesh.creation.icosphere(subdivisions=4)
    egg.vertices *= [0.03, 0.03, 0.05]
    egg.apply_translation([0.0, 0.0, 0.05])
    return egg


def test_tip_angle_is_the_lean_the_base_holds() -> None:
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.2))
    box.apply_translation([0.0, 0.0, 0.1])
    assert tip_angle_deg(box) == pytest.approx(26.565, abs=0.01)  # atan(0.05 / 0.1)
    assert tip_angle_deg(_standing_egg()) < 10.0  # within 2 mm of the table: a disc of ~8 mm radius


def test_a_rounded_bottom_is_cut_flat_just_enough_and_a_wide_base_is_left_alone() -> None:
    egg = _standing_egg()
    seated, cut = seat_flat(egg)
    assert 0.0 < cut <= 0.06 * 0.1 + 1e-9
    assert seated.is_watertight and seated.bounds[0][2] == pytest.approx(0.0, abs=1e-9)
    assert tip_angle_deg(seated) > tip_angle_deg(egg) + 5.0
    assert seated.volume == pytest.approx(egg.volume, rel=0.02)  # a few mm off the bottom
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.2))
    same, none = seat_flat(box)
    assert none == 0.0 and same is box


@pytest.mark.parametrize("text", ["a plush penguin 18 cm", "a teddy bear 25 cm tall"])
def test_standing_plush_toys_stand_on_a_base_and_keep_their_size(text: str) -> None:
    mesh, info = sources.build_mesh(AssetRequest(text=text), settings())
    m = pipeline.arrays_to_mesh(mesh)
    assert info.category == "plush_animal"
    assert tip_angle_deg(m) >= SEAT_TIP_DEG - 0.5
    stated = 0.18 if "penguin" in text else 0.25
    assert max(m.extents) == pytest.approx(stated, rel=0.02)
