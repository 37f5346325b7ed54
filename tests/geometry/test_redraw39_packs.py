"""Redraw 39, packs: retail packs the blind judges still misread get the printed picture a shopper knows them by: a
pack of diapers shows one diaper laid open, a bag of flour an ear of wheat, a bag of cat litter a cat's head, a milk
pouch a milk bottle (tasks/geometry/grammar/goods.py emblem_parts)."""

from __future__ import annotations

import functools

import pytest

from tasks.geometry import catalogue, pouch_words
from tasks.geometry.concepts import read_text
from tasks.geometry.grammar.goods import emblem_parts
from tasks.geometry.grammar.parts import part_group


@functools.cache
def _program(text: str):  # noqa: ANN202
    return catalogue.design_from_text(text).program


@pytest.mark.parametrize(("text", "entry", "emblem", "count"), [
    ("pack of baby diapers", "diaper_pack", "diaper", 5),
    ("pack of adult diapers", "diaper_pack", "diaper", 5),
    ("bag of flour", "bag_of_flour", "wheat", 14),
    ("a 5 lb paper sack of all purpose flour", "bag_of_flour", "wheat", 14),
    ("1 liter milk pouch", "milk_bag", "bottle", 3),
])
def test_a_pack_shows_the_picture_that_names_it(text: str, entry: str, emblem: str, count: int) -> None:
    assert read_text(text).entry.key == entry
    marks = [p for p in _program(text).parts if part_group(p.name) == "emblem"]
    assert len(marks) == count == len(emblem_parts(emblem, 0.2))
    assert any(part_group(p.name) == "label" for p in _program(text).parts)


def test_a_bag_of_sugar_keeps_its_plain_label() -> None:
    assert read_text("bag of sugar").entry.key == "bag_of_sugar"
    assert not any(part_group(p.name) == "emblem" for p in _program("bag of sugar").parts)


def test_a_bag_of_cat_litter_shows_a_cats_head() -> None:
    reading = read_text("small cat litter bag")
    assert reading.pouch is not None
    assert pouch_words.pack_look(reading.pouch, "small cat litter bag")["emblem"] == "cat"
    marks = [p for p in _program("small cat litter bag").parts if part_group(p.name) == "emblem"]
    assert sum(p.operation == "union" for p in marks) == 3  # the face and two ears
    assert sum(p.operation == "subtract" for p in marks) == 2  # its eyes


def test_the_new_emblems_stay_on_their_label() -> None:
    for kind in ("wheat", "cat", "bottle", "diaper"):
        for p in emblem_parts(kind, 0.2):
            x, y, _z = p.transform.translation_m
            assert abs(x) < 0.26 and abs(y) < 0.2, (kind, p.name)
