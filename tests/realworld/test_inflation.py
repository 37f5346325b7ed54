"""A pressurised ball's gas as a modulus added to its shell's wall (issue #39, session 33; tasks.realworld.inflation):
the formula against a hand computation and the ITF squeeze, the lexicon's pressures and their sources, the records
(geometry.json `particles`, the material's gas_modulus_pa, a specimen without it), and the MPM: a shell at the wall
modulus is as stiff against the floor as the rubber and the gas together."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from contracts.asset_dir import ParticleBody
from contracts.concept import ConceptMatch
from contracts.lexicon import LexiconEntry, load_lexicon
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.realworld import load_realworld
from contracts.sim import SimConfig
from contracts.stage import load_contract
from tasks.geometry import pipeline
from tasks.mpm.scene import ball_particles
from tasks.probes.mpm_probe import body_inputs
from tasks.probes.probe import ProbeContext
from tasks.realworld.impact import impact
from tasks.realworld.inflation import (adiabatic_secant_stiffness_n_per_m, gas_contact_stiffness_n_per_m,
                                       gas_wall_modulus_pa, shell_inflation, shell_point_stiffness_n_per_m)

RUBBER_PA, NU = 1.58e6, 0.48  # the rubber L2 adopted for the tennis ball (sessions 27-28), the engine's nu


def test_the_gas_modulus_against_a_hand_computation() -> None:
    """Tennis: R 33 mm, t 3.2 mm, 82 kPa: k_gas = 2 pi R p = 17.0 kN/m; dE = k R sqrt(3 (1 - nu^2)) / (4 t^2)
    = 17002 x 0.033 x 1.5195 / 4.096e-5 = 20.8 MPa, near the 24 MPa the session-32 sweep put the shell in its band."""
    k = gas_contact_stiffness_n_per_m(0.033, 82e3)
    assert k == pytest.approx(2 * 3.14159265 * 0.033 * 82e3, rel=1e-6) == pytest.approx(17002.0, rel=1e-4)
    de = gas_wall_modulus_pa(0.033, 0.0032, 82e3, NU)
    assert de == pytest.approx(17002.1 * 0.033 * 1.51947 / 4.096e-5, rel=1e-4) == pytest.approx(20.8e6, rel=2e-3)
    # the definition: a shell at dE has the gas's contact stiffness (Reissner's point load)
    assert shell_point_stiffness_n_per_m(de, 0.0032, 0.033, NU) == pytest.approx(k, rel=1e-12)
    # proportional to the pressure, to the square of R over t
    assert gas_wall_modulus_pa(0.033, 0.0032, 41e3, NU) == pytest.approx(de / 2, rel=1e-12)
    assert gas_wall_modulus_pa(0.066, 0.0064, 82e3, NU) == pytest.approx(de, rel=1e-12)


def test_rubber_and_gas_are_as_stiff_as_the_itf_squeeze_and_the_rubber_alone_is_not() -> None:
    """The ITF forward deformation (0.559-0.737 cm under 80 N between two plates: each contact half of it) is a
    per-contact stiffness of 21.7-28.6 kN/m; the lexicon's tennis shell (its 4 mm wall, 82.7 kPa) with the rubber's
    1.58 MPa is within 1.5x of it, the rubber shell alone ~10x under it."""
    obj = next(o for o in load_realworld().objects if o.name == "tennis ball")
    sq = obj.squeeze
    assert sq is not None
    band = (2 * sq.load_n / sq.deformation_m.high, 2 * sq.load_n / sq.deformation_m.low)
    entry = load_lexicon().entries["tennis_ball"]
    assert entry.inflation_gauge_pa is not None and entry.wall_m is not None
    r = 0.25 * (sq.diameter_m.low + sq.diameter_m.high)
    rubber = shell_point_stiffness_n_per_m(RUBBER_PA, entry.wall_m, r, NU)
    both = rubber + gas_contact_stiffness_n_per_m(r, entry.inflation_gauge_pa)
    assert band[0] / 1.5 < both < band[1] * 1.5
    assert rubber < band[0] / 5.0
    # the wall modulus carries both: Reissner at E + dE is the rubber's and the gas's stiffness
    e_wall = RUBBER_PA + gas_wall_modulus_pa(r, entry.wall_m, entry.inflation_gauge_pa, NU)
    assert shell_point_stiffness_n_per_m(e_wall, entry.wall_m, r, NU) == pytest.approx(both, rel=1e-12)


def test_the_adiabatic_gas_is_nothing_in_a_squeeze_and_a_fifth_at_a_rule_drop() -> None:
    """Why the linear term alone: the gas's adiabatic volume stiffness at the ITF squeeze's ~3 mm per contact is a
    few per cent of k_gas; at the rule drop's deepest deflection (a 57 g ball at 7.06 m/s on k_gas: ~12 mm) a fifth."""
    r, t, p = 0.0335, 0.004, 82.7e3
    k = gas_contact_stiffness_n_per_m(r, p)
    assert adiabatic_secant_stiffness_n_per_m(r, t, p, 0.003) < 0.03 * k
    deepest = 7.06 * math.sqrt(0.057 / k)  # 1/2 m v^2 = 1/2 k d^2
    assert 0.1 * k < adiabatic_secant_stiffness_n_per_m(r, t, p, deepest) < 0.4 * k


def test_the_lexicon_gives_a_pressure_with_its_source_to_the_pressurised_balls_alone() -> None:
    """Tennis ~0.8-0.9 bar over the ambient, padel a little lower; no pressure for the racquetball and squash ball
    (no source, unpressurised) and none for a duck; a pressure needs its source, and a hollow object with a wall."""
    lex = load_lexicon().entries
    tennis, padel = lex["tennis_ball"], lex["padel_ball"]
    assert tennis.inflation_gauge_pa is not None and padel.inflation_gauge_pa is not None
    assert 80e3 <= tennis.inflation_gauge_pa <= 90e3 and 60e3 < padel.inflation_gauge_pa < tennis.inflation_gauge_pa
    assert "12 psi" in str(tennis.inflation_source) and "4.6-5.2" in str(padel.inflation_source)
    pressurised = {k for k, e in lex.items() if e.inflation_gauge_pa is not None}
    assert pressurised == {"tennis_ball", "padel_ball"}
    base = {"key": "x", "nouns": ["x"], "plan": "ball", "material": "rubber", "category": "ball", "size_m": 0.06,
            "mass_kg": 0.05, "mass_source": "a test entry", "hollow": True, "wall_m": 0.004}
    with pytest.raises(ValueError, match="together"):
        LexiconEntry(**base, inflation_gauge_pa=80e3)
    with pytest.raises(ValueError, match="together"):
        LexiconEntry(**base, inflation_source="a source long enough")
    with pytest.raises(ValueError, match="hollow"):
        LexiconEntry(**{**base, "hollow": False, "wall_m": None}, inflation_gauge_pa=80e3,
                     inflation_source="a source long enough")


def _concept(**kw: object) -> ConceptMatch:
    return ConceptMatch(concept="tennis_ball", noun="tennis ball", body_plan="catalogue:tennis_ball", category="ball",
                        fallback_level="exact", default_material="rubber", hollow=True, wall_thickness_m=0.004, **kw)


def test_a_pressurised_shell_records_its_gas_and_a_solid_its_record_of_before() -> None:
    """geometry.json `particles`: the gas's pressure and source on a pressurised ball's shell alone; a solid's (the
    default) and the concept's dumps carry no new keys; L2's inflation record from the shell's."""
    concept = _concept(inflation_gauge_pa=82.7e3, inflation_source="12 psi over the ambient")
    shell = ParticleBody(kind="shell", wall_m=0.004, requested_wall_m=0.004, spacing_m=0.002, volume_m3=5e-5,
                         enclosed_volume_m3=4.0 / 3.0 * math.pi * 0.0335 ** 3)
    solid = ParticleBody(kind="solid", requested_wall_m=0.004, spacing_m=0.003, volume_m3=1.5e-4,
                         enclosed_volume_m3=1.5e-4, reason=pipeline.SHELL_OPT_IN)
    gassed = pipeline.with_gas(shell, concept)
    assert gassed.gauge_pressure_pa == 82.7e3 and gassed.model_dump()["gauge_pressure_source"] == "12 psi over the ambient"
    assert pipeline.with_gas(solid, concept) is solid and pipeline.with_gas(shell, _concept()) is shell
    assert "gauge_pressure_pa" not in solid.model_dump(mode="json") and "gauge_pressure_pa" not in shell.model_dump()
    assert "inflation_gauge_pa" not in _concept().model_dump(mode="json")
    assert ParticleBody.model_validate(gassed.model_dump(mode="json")) == gassed
    rec = shell_inflation(gassed, NU)
    assert rec is not None and shell_inflation(shell, NU) is None and shell_inflation(solid, NU) is None
    assert rec["radius_m"] == pytest.approx(0.0335, rel=1e-9)
    assert rec["gas_modulus_pa"] == pytest.approx(gas_wall_modulus_pa(0.0335, 0.004, 82.7e3, NU), rel=1e-12)
    assert "homogenised" in str(rec["model"]) and "not a gas simulation" in str(rec["model"])


def test_a_material_without_gas_is_the_material_of_before_and_a_specimen_has_no_gas() -> None:
    """gas_modulus_pa 0 (every material but a gas shell's) leaves the dump (the cache keys) and the Lame parameters as
    they were; with a gas the object's wall is E + dE, a specimen of the material E alone."""
    plain = Material(youngs_modulus_pa=RUBBER_PA, poisson_ratio=NU, damping_rate_per_s=1.0)
    assert "gas_modulus_pa" not in plain.model_dump() and plain.specimen() is plain
    assert plain.mu_pa == RUBBER_PA / (2.0 * (1.0 + NU)) and plain.wall_modulus_pa == RUBBER_PA
    gas = plain.model_copy(update={"gas_modulus_pa": 13e6})
    assert gas.model_dump()["gas_modulus_pa"] == 13e6 and gas.wall_modulus_pa == RUBBER_PA + 13e6
    assert gas.mu_pa == pytest.approx((RUBBER_PA + 13e6) / (2.0 * (1.0 + NU)), rel=1e-12)
    assert gas.specimen() == plain
    pos, vol = ball_particles(0.03, 0.006)
    phys = PhysicalModel(density_kg_per_m3=1000.0, volume_m3=float(vol.sum()), mass_kg=float(vol.sum()) * 1000.0,
                         particle_count=len(pos), particle_spacing_m=0.006, ground_friction=0.5, gripper_friction=0.8,
                         center_of_mass_m=(0.0, 0.0, 0.03), extents_m=(0.06,) * 3, category="ball")
    ctx = ProbeContext(SimpleNamespace(particles_m=pos, volumes_m3=vol), load_contract("L2"), phys, gas)
    assert body_inputs(ctx)["material"] == gas  # the object: its wall with the gas
    assert body_inputs(ctx, "cube")["material"] == plain  # a specimen of the material: the rubber


def test_an_mpm_shell_at_the_wall_modulus_has_the_rubber_and_gas_contact_stiffness() -> None:
    """A tennis-sized ball (R 33.5 mm, 57 g) as a shell of two particle layers (8 mm at 4 mm: ~1.4k particles)
    landing at 4 m/s (slower, its deflection is under a grid cell): at the wall modulus of 82.7 kPa its contact time in
    our MPM is a half period on the rubber's and the gas's stiffness, pi sqrt(m / (k_rubber + k_gas)), within 20 %;
    the rubber shell alone's on k_rubber's, and the gas shortens it as the formula says (contact stiffness ~ E)."""
    r, wall, mass, p = 0.0335, 0.008, 0.057, 82.7e3
    pos, vol = ball_particles(r, 0.004, wall)
    pos = pos + np.array([0.0, 0.0, r])
    phys = PhysicalModel(density_kg_per_m3=mass / float(vol.sum()), volume_m3=float(vol.sum()), mass_kg=mass,
                         particle_count=len(pos), particle_spacing_m=0.004, ground_friction=0.5, gripper_friction=0.8,
                         center_of_mass_m=(0.0, 0.0, r), extents_m=(2 * r,) * 3, category="ball")
    rubber = Material(youngs_modulus_pa=RUBBER_PA, poisson_ratio=NU)
    gas = rubber.model_copy(update={"gas_modulus_pa": gas_wall_modulus_pa(r, wall, p, NU)})
    k_rubber = shell_point_stiffness_n_per_m(RUBBER_PA, wall, r, NU)
    k_both = k_rubber + gas_contact_stiffness_n_per_m(r, p)
    times = {}
    for name, material in (("rubber", rubber), ("gas", gas)):
        out = impact(pos, vol, phys, material, 4.0, SimConfig(device="cpu", cpu_threads=1))
        assert out["finite"] == 1.0
        times[name] = out["contact_time_s"]
    assert times["gas"] == pytest.approx(math.pi * math.sqrt(mass / k_both), rel=0.2)
    assert times["rubber"] == pytest.approx(math.pi * math.sqrt(mass / k_rubber), rel=0.2)
    assert times["rubber"] / times["gas"] == pytest.approx(math.sqrt(k_both / k_rubber), rel=0.2)
