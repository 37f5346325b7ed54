"""Development set 41's gaps: 60 blind prompts of soft everyday objects from twelve scenes not tried before
(tests/geometry/dev41_prompts.jsonl). The ones that fell back (a material's ball, a generic block or garment), read as
another object (a coiled mooring line as a 3 m rope, a jump rope as a plain rope, a rolled fire hose as a garden hose,
a turnout coat as a light jacket) or weighed off by more than 2x now read as their own entries
(contracts/lexicon/dev41.yaml, tasks/geometry/shapes/dev41.yaml) and weigh within 2x of the set's sourced mass."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tasks.geometry import catalogue
from tests.geometry.test_mass_classes import planned_mass

PROMPTS = {r["id"]: r for r in map(json.loads, (Path(__file__).parent / "dev41_prompts.jsonl").read_text().splitlines())}

FIXED = {  # prompt id: the entry it reads as
    "d41_07": "lead_rope",  # was a 3 m rope, 160 g
    "d41_09": "horse_blanket",  # was a 0.7 kg fleece throw
    "d41_10": "grooming_mitt",  # was a rubber ball
    "d41_13": "dock_line",  # 'mooring line' was a generic block
    "d41_15": "boat_sail",  # was a 47 g generic garment
    "d41_18": "curly_wig",  # was a generic block
    "d41_19": "squeaky_chicken",  # 'rubber chicken prop' was a rubber ball
    "d41_20": "stage_curtain",  # was a 200 g voile curtain
    "d41_22": "chair_cover",  # was a generic block
    "d41_24": "bridal_veil",  # was a generic block
    "d41_27": "bar_mat",  # was a rubber ball
    "d41_28": "wine_bladder",  # was a generic pouch of 310 g
    "d41_29": "bag_of_ice",  # a generic pouch: 0.47 kg unless a weight was said
    "d41_30": "stool_cushion",  # was a 1.1 kg meditation cushion
    "d41_31": "fire_hose",  # was a garden hose, 1.6 kg
    "d41_32": "turnout_coat",  # was a 0.5 kg jacket
    "d41_35": "salvage_cover",  # was a 0.7 kg poly tarp
    "d41_37": "velvet_rope",  # was a 3 m rope, 160 g
    "d41_43": "seed_snack_bag",  # a generic seed pouch of 380 g
    "d41_44": "chest_protector",  # was a generic garment
    "d41_58": "jump_rope",  # was a plain coiled rope
}


@pytest.mark.parametrize("pid", sorted(FIXED))
def test_prompt_reads_as_its_entry(pid: str) -> None:
    text = PROMPTS[pid]["text"]
    assert catalogue.design_from_text(text).entry == FIXED[pid], text


@pytest.mark.parametrize("pid", sorted(FIXED))
def test_prompt_weighs_within_2x(pid: str) -> None:
    text, real = PROMPTS[pid]["text"], PROMPTS[pid]["mass_kg"]
    assert 0.5 * real <= planned_mass(text) <= 2.0 * real, text


@pytest.mark.parametrize(("text", "entry"), [  # other wordings of the same objects
    ("a white nylon dock line", "dock_line"), ("a horse rug", "horse_blanket"), ("a curry mitt", "grooming_mitt"),
    ("a skipping rope", "jump_rope"), ("a black wig", "curly_wig"), ("a bag of ice cubes", "bag_of_ice"),
    ("a fire hose roll", "fire_hose"), ("a firefighter jacket", "turnout_coat"), ("a stanchion rope", "velvet_rope"),
    ("a wedding veil", "bridal_veil"), ("a packed down jacket", "packed_down_jacket"),
    ("a packable down jacket, crumpled into a heap", "puffer_jacket"),  # a packable jacket out of its sack is a
    # (down) jacket, not the packed one
])
def test_other_wordings_read_as_the_entry(text: str, entry: str) -> None:
    assert catalogue.design_from_text(text).entry == entry
