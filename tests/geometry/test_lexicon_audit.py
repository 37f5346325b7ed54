"""Fixes from the audit of the lexicon's own objects (session 37): each entry named by its first noun, rendered, and
named back by a judge who had not seen the lexicon (docs/blind/audit37/)."""

from __future__ import annotations

import pytest

from contracts.lexicon import load_lexicon
from tasks.agents.intent import rigid_object


def test_no_lexicon_noun_is_refused_as_a_rigid_object() -> None:
    """'a baby spoon' is the silicone weaning spoon of the lexicon, not a metal spoon: every noun of every entry reads
    as deformable."""
    refused = [(key, noun) for key, entry in load_lexicon().entries.items() for noun in entry.nouns
               if noun != "(generic)" and rigid_object(f"a {noun}") is not None]
    assert refused == []


@pytest.mark.parametrize("text", ["a spoon", "a metal spoon", "a chair", "a brick", "a pot"])
def test_the_rigid_words_alone_are_still_refused(text: str) -> None:
    assert rigid_object(text) is not None


def _draft_mesh(text: str):  # noqa: ANN202
    from contracts.request import AssetRequest
    from tasks.geometry import pipeline, sources

    settings = pipeline.settings_from_contract("draft")
    arrays, _ = sources.build_mesh(AssetRequest(text=text), settings)
    return pipeline.arrays_to_mesh(arrays), settings


def test_the_coarse_copy_for_coacd_keeps_a_thin_walls_volume() -> None:
    """A straw hat's brim is thinner than the coarse grid's cells: the copy CoACD decomposes kept 5 % of the hat (its
    proxy covered the crown's top only); now it keeps the volume within 15 % or CoACD gets the mesh itself."""
    from tasks.geometry.collision import COARSE_VOLUME_TOLERANCE, _coarsen

    mesh, settings = _draft_mesh("a straw hat")
    coarse = _coarsen(mesh, settings.coacd.max_input_faces)
    assert abs(coarse.volume / mesh.volume - 1.0) <= COARSE_VOLUME_TOLERANCE


def test_a_thin_gently_curved_good_is_proxied_within_the_gate() -> None:
    """A necktie is one CoACD piece at the draft threshold (its hull 2.3x its volume: L0's 'proxy hugs mesh' gate
    failed on 'a necktie'); a finer threshold splits it."""
    from tasks.geometry.collision import convex_parts, union_volume

    mesh, settings = _draft_mesh("a necktie")
    parts = convex_parts(mesh, settings.coacd)
    assert len(parts) > 1 and 0.9 <= union_volume(parts) / mesh.volume <= 1.6


def test_a_floor_pouf_is_not_frilled_like_a_bath_pouf() -> None:
    """'pouf' alone is the floor cushion (the judge saw a pile of frilled coasters: the bath pouf's ruffles were
    drawn on it); a bath, shower or mesh pouf keeps its ruffles."""
    from tasks.geometry.concepts import relief_of

    lex = load_lexicon().entries
    assert relief_of("a pouf", lex["pouf"]) == (None, False)
    assert relief_of("a grey knitted pouf", lex["pouf"])[0] != "ruffles"
    assert relief_of("a pink shower pouf", lex["bath_pouf"])[0] == "ruffles"


def test_a_fruit_in_the_objects_own_name_does_not_colour_it() -> None:
    """'an apple fritter' was an apple's red (the fruit before a food colours it: 'a strawberry jelly' is red); the
    fruit inside the object's own noun is its name, not its flavour's colour."""
    from tasks.geometry.catalogue import design_from_text

    def main_colour(text: str) -> tuple[float, ...]:
        parts = design_from_text(text).program.parts
        return tuple(parts[0].color_rgb)

    fritter = main_colour("an apple fritter")
    assert not (fritter[0] > 0.6 and fritter[1] < 0.2)  # not red
    jelly = main_colour("a strawberry jelly")
    assert jelly[0] > 0.6 and jelly[1] < 0.2  # red
