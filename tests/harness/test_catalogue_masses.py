"""The offline catalogue's objects get plausible masses in L1: every entry's prior mass passes L1's mass gate, and
objects whose real mass is common knowledge get about that mass (the material their words name sets the density)."""

from __future__ import annotations

import functools

import pytest

from contracts.errors import InputError
from tasks.agents.intent import match_material, targets_from_intent
from tasks.agents.vocab import load_material_vocab
from tasks.geometry import catalogue
from tasks.geometry.meshing import mesh_program
from tasks.physical.model import DENSITY_BAND_SLACK, MASS_RANGE_KG, mass_plausible

# entry -> (typical real mass at about the catalogue's size [kg], what it is)
TYPICAL_MASS_KG = {
    "peach": (0.15, "a peach, ~7.5 cm"),
    "tomato": (0.15, "a large tomato, ~7.5 cm"),
    "banana": (0.15, "a banana"),
    "water_balloon": (0.3, "a water balloon, ~8 cm"),
    "rolled_towel": (0.4, "a rolled bath towel"),
    "folded_towel": (0.5, "a folded bath towel"),
    "sock_ball": (0.06, "a pair of rolled socks"),
    "marshmallow": (0.007, "a large marshmallow"),
    "beach_ball": (0.2, "a 40 cm beach ball"),
    "foam_earplug": (0.00025, "a foam earplug"),
    "dough_ball": (0.45, "a pizza dough ball, ~9 cm"),
    "plush_turtle": (0.25, "a 25 cm plush turtle"),
    "bread_loaf": (0.8, "a loaf of bread"),
}
FACTOR = 4.0  # the prior mass within this factor of the real one; the L1 band (density range) must contain it


@functools.cache
def _prior(name: str) -> tuple[float, float, tuple[float, float], str]:
    """(volume, prior density, density range, material) as L1 derives them for the entry's first keyword."""
    program = catalogue.program_for(name)
    text = f"a {catalogue.entry_keywords(name)[0]} {program.name} {catalogue.entry_category(name)}".lower()
    vocab = load_material_vocab()
    material = match_material(text, vocab)
    density = targets_from_intent(text, {}, vocab).priors["density_kg_per_m3"]
    drange = vocab.materials[material].prior_ranges["density_kg_per_m3"]
    try:
        volume = float(mesh_program(program, 32).volume)
    except (ValueError, InputError):  # a long thin good 32 cells cannot resolve (a 1.4 m stole 3 cm thick): L0's draft grid
        volume = float(mesh_program(program, 48).volume)
    return volume, density, drange, material


def _gate_failures(names: list[str]) -> list[str]:
    failures = []
    for name in names:
        volume, density, drange, material = _prior(name)
        mass = volume * density
        if not (MASS_RANGE_KG[0] <= mass <= MASS_RANGE_KG[1] and mass_plausible(mass, density, drange)):
            failures.append(f"{name} ({material}): {mass:.4g} kg")
    return failures


ENTRIES = sorted(catalogue.entry_names())


def test_a_sample_of_catalogue_entries_passes_the_mass_gate_at_its_prior() -> None:
    """Every fourth hand-written object (a fixed sample; the whole catalogue in the slow sweep below)."""
    assert not _gate_failures(ENTRIES[::4]), _gate_failures(ENTRIES[::4])


@pytest.mark.slow
def test_every_catalogue_entry_passes_the_mass_gate_at_its_prior() -> None:
    """No catalogue object is refused by L1 whatever density it is given (the foam earplug was, at 2 g's floor; the
    beach ball was, as solid rubber: 33 kg; a hung pleated curtain, drawn as a 0.33 m^3 solid, 85 kg)."""
    failures = _gate_failures(ENTRIES)
    assert not failures, failures


@pytest.mark.parametrize("name", sorted(TYPICAL_MASS_KG))
def test_objects_get_about_their_real_mass(name: str) -> None:
    """A peach was 6 g of PU foam, a water balloon 10 g, a rolled towel 47 g; each now names a material whose density
    gives about the real mass, and whose plausible band holds it."""
    real, what = TYPICAL_MASS_KG[name]
    volume, density, (dlo, dhi), material = _prior(name)
    prior = volume * density
    assert real / FACTOR <= prior <= real * FACTOR, f"{what}: {prior * 1e3:.3g} g as {material}, real ~{real * 1e3:g} g"
    assert volume * dlo / DENSITY_BAND_SLACK <= real <= volume * dhi * DENSITY_BAND_SLACK, (what, material)
