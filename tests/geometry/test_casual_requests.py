"""A request typed on a shop floor reads as the object it names: the command before it ('grab that', 'pls pick up',
'ok robot, grab the'), where it goes after it ('into the tray', 'off the table') and what to do with it ('- bin it',
'real quick', 'put that ... back') are not the object. Before session 47, 38 of 480 such wordings of 20 everyday
objects built another object or a generic block ('grab that sponge off the table' took 'table' for the object;
'lift the jellyfish into the tray' built minced meat)."""

from __future__ import annotations

import functools

import pytest

from tasks.geometry import catalogue

OBJECTS = ["sponge", "croissant", "teddy bear", "bath towel", "hoodie", "stress ball", "jellyfish", "burrata"]

TEMPLATES = [
    "grab that {} off the table",
    "pls pick up {}",
    "hand me that {} real quick",
    "lift the {} into the tray",
    "can you grab the {} pls",
    "ok robot, grab the {}",
    "put that {} back",
    "{} - bin it",
    "{}, put it in the crate",
    "get me the {} from the counter",
    "toss the {} into the laundry basket",
    "move the {} to the bin",
    "{} thx",
    "hey, could you please pick up the {}",
]


@functools.cache
def _entry(text: str) -> str:
    return catalogue.design_from_text(text).entry


@pytest.mark.parametrize("template", TEMPLATES)
def test_a_casual_request_names_the_object_it_asks_for(template: str) -> None:
    wrong = [(template.format(o), _entry(template.format(o)), _entry(o)) for o in OBJECTS
             if _entry(template.format(o)) != _entry(o)]
    assert not wrong, wrong


@pytest.mark.parametrize(("text", "entry"), [
    ("a grab bag", "generic_bag"),  # a handling verb before a noun, with no determiner, is the object's own word
    ("a chicken on a foam tray", "ground_meat"),  # a tray the meat is sold on is still a food cue
    ("raw chicken into the tray", "whole_chicken"),
    ("a sock, folded", "crew_sock"),  # a state after a comma is no command
])
def test_what_is_not_a_command_is_read_as_before(text: str, entry: str) -> None:
    assert _entry(text) == entry
