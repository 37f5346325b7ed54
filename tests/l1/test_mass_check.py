"""Credible mass: L1's mass band is the material's density range x volume and, when L0 names the object
(contracts.concept.ConceptMatch), its typical mass at the built size; hollow objects get an effective density.

References (real objects, not the fixtures' own numbers):
- tennis ball, ITF Rules of Tennis, appendix I: 56.0-59.4 g at 6.54-6.86 cm (a hollow rubber core with felt);
- racquetball, USA Racquetball rules: 2.25 in (57.15 mm), ~1.4 oz (39.7 g), hollow rubber;
- kitchen sponge: the 'Toast Sponge' (inventorspot.com), 12.5 x 13 x 1.5 cm, ~20 g: ~82 kg/m^3 as a whole object.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest
from l1_assets import asset_of, write_l0_dir

from contracts.concept import ConceptMatch
from contracts.errors import InputError
from contracts.request import AssetRequest
from flows.l1_physical import run_l1
from tasks.physical.plan import L1Plan, l1_plan
from tasks.geometry.outputs import load_l0
from tasks.physical.mass import concept_band, mass_check, typical_mass_at_size

TENNIS_BALL = (0.0577, 0.067)  # ITF: mid-range mass [kg] at the mid-range diameter [m]
RACQUETBALL = ConceptMatch(concept="rubber_ball", noun="ball", body_plan="ball", category="ball",
                           fallback_level="exact", default_material="rubber", hollow=True, typical_mass_kg=0.0397,
                           typical_size_m=0.05715, mass_source="racquetball, USA Racquetball rules")
KITCHEN_SPONGE = ConceptMatch(concept="kitchen_sponge", noun="sponge", body_plan="block", category="household",
                              fallback_level="exact", default_material="sponge", typical_mass_kg=0.020,
                              typical_size_m=0.13, mass_source="Toast Sponge, inventorspot.com")
TOAST_SPONGE_DENSITY = 0.020 / (0.125 * 0.13 * 0.015)  # [kg/m^3], ~82


def _hollow_scaled(mass_kg: float, size_m: float, to_m: float) -> float:
    """A shell's mass at another size (area scaling)."""
    return mass_kg * (to_m / size_m) ** 2


def _plan(text: str, concept: ConceptMatch | None) -> tuple[L1Plan, float]:
    """L1's plan for a text's built mesh (with a ConceptMatch in its record) and the mass it starts from [kg]."""
    asset = asset_of(AssetRequest(text=text), concept)
    plan = l1_plan(asset, None)
    return plan, plan.targets.priors["density_kg_per_m3"] * float(asset.volumes_m3.sum())


def test_a_hollow_rubber_ball_weighs_tens_of_grams_not_solid_rubber() -> None:
    """A 7 cm hollow rubber ball: ~60 g as the real one (a tennis ball scaled to 7 cm: ~63 g), not ~150 g of solid
    rubber; with no typical mass, a 3 mm rubber shell gives the same order."""
    real = _hollow_scaled(*TENNIS_BALL, 0.07)
    _, solid_kg = _plan("a rubber ball 7 cm", None)
    assert solid_kg > 2 * real  # the old behaviour: the solid volume at rubber's density
    hollow, m = _plan("a rubber ball 7 cm", RACQUETBALL)
    assert 0.02 <= m <= 0.1 and real / 1.5 <= m <= real * 1.5, m
    assert hollow.mass.effective_density and hollow.mass.band_kg[0] <= m <= hollow.mass.band_kg[1]
    assert hollow.mass.checks == ["typical mass of rubber_ball (racquetball, USA Racquetball rules)"]
    assert any("hollow" in n for n in hollow.mass.notes)
    assert hollow.targets.band("mass_kg").source == hollow.mass.source
    no_mass = RACQUETBALL.model_copy(update={"typical_mass_kg": None, "typical_size_m": None})
    shell, shell_kg = _plan("a rubber ball 7 cm", no_mass)
    assert real / 2 <= shell_kg <= real * 1.5 and "3 mm shell" in shell.mass.source


def test_a_kitchen_sponge_gets_within_2x_of_a_real_one() -> None:
    """A 10 x 7 x 3 cm kitchen sponge: the sponge-rubber density range gives ~70 g, ~4x a real one (~17 g at the
    Toast Sponge's whole-object density); the typical mass of the named object moves it within 2x."""
    asset = asset_of(AssetRequest(text="a kitchen sponge 10 x 7 x 3 cm"))
    real = TOAST_SPONGE_DENSITY * float(asset.volumes_m3.sum())
    _, old_kg = _plan("a kitchen sponge 10 x 7 x 3 cm", None)
    assert old_kg > 3 * real
    plan, m = _plan("a kitchen sponge 10 x 7 x 3 cm", KITCHEN_SPONGE)
    assert real / 2 <= m <= real * 2, (m, real)
    assert plan.mass.checks == ["typical mass of kitchen_sponge (Toast Sponge, inventorspot.com)"]
    assert plan.mass.effective_density and any("outside the typical" in n for n in plan.mass.notes)


def test_the_concept_l0_records_binds_a_sponges_mass() -> None:
    """End to end with the lexicon: L0's own ConceptMatch for a kitchen sponge puts it within 2x of a real one."""
    asset = asset_of(AssetRequest(text="a kitchen sponge 10 x 7 x 3 cm"))
    concept = asset.record["info"].get("concept") or {}
    if not (concept.get("typical_mass_kg") or concept.get("typical_mass_range_kg")):
        pytest.skip("L0 records no ConceptMatch with a typical mass for this text yet")
    plan = l1_plan(asset, None)
    real = TOAST_SPONGE_DENSITY * float(asset.volumes_m3.sum())
    m = plan.targets.priors["density_kg_per_m3"] * float(asset.volumes_m3.sum())
    assert real / 2 <= m <= real * 2 and any(c.startswith("typical mass of") for c in plan.mass.checks), (m, real)


def test_the_band_uses_the_concept_when_present_and_the_density_range_otherwise() -> None:
    """No concept: density range x volume. A concept whose range meets it: the intersection, both checks named.
    One that misses it: the concept's range, an effective density inside the L1 contract's bounds."""
    volume, size = 2.0e-4, 0.1
    plain = mass_check(volume, size, 0.02, "gel", 1020.0, (1000.0, 1050.0))
    assert plain.band_kg == pytest.approx((0.2, 0.21)) and plain.checks == ["density range of gel (1000-1050 kg/m^3)"]
    assert plain.density_kg_per_m3 == 1020.0 and not plain.effective_density
    gel_pack = ConceptMatch(concept="gel_pack", body_plan="cushion", category="household", fallback_level="exact",
                            default_material="gel", typical_mass_range_kg=(0.15, 0.205), mass_source="listing")
    both = mass_check(volume, size, 0.02, "gel", 1020.0, (1000.0, 1050.0), gel_pack)
    assert both.band_kg == pytest.approx((0.2, 0.205))
    assert both.checks == ["density range of gel (1000-1050 kg/m^3)", "typical mass of gel_pack (listing)"]
    assert both.density_range_kg_per_m3 == pytest.approx((1000.0, 1025.0))
    light = gel_pack.model_copy(update={"typical_mass_range_kg": (0.02, 0.05)})
    moved = mass_check(volume, size, 0.02, "gel", 1020.0, (1000.0, 1050.0), light, density_bounds=(10.0, 2000.0))
    assert moved.band_kg == pytest.approx((0.02, 0.05)) and moved.effective_density
    assert moved.density_kg_per_m3 == pytest.approx(math.sqrt(0.02 * 0.05) / volume)
    assert moved.checks == ["typical mass of gel_pack (listing)"]
    assert any("outside the typical" in n for n in moved.notes)
    feather = gel_pack.model_copy(update={"typical_mass_range_kg": (1e-4, 2e-4)})
    clamped = mass_check(volume, size, 0.02, "gel", 1020.0, (1000.0, 1050.0), feather, density_bounds=(10.0, 2000.0))
    assert clamped.density_kg_per_m3 == 10.0 and "clamped" in clamped.notes[-1]
    lo, hi = clamped.density_range_kg_per_m3
    assert lo <= 10.0 <= hi  # the gate admits the density L1 can reach


def test_typical_mass_scales_with_volume_for_a_solid_and_area_for_a_shell() -> None:
    solid = KITCHEN_SPONGE.model_copy(update={"typical_size_m": 0.1})
    assert typical_mass_at_size(solid, 0.2) == pytest.approx(0.02 * 8)
    assert typical_mass_at_size(solid.model_copy(update={"hollow": True}), 0.2) == pytest.approx(0.02 * 4)
    assert concept_band(solid, 0.1) == pytest.approx((0.01, 0.04))


@pytest.mark.skipif(not hasattr(ConceptMatch, "mass_estimate_kg"), reason="ConceptMatch has no lexicon density")
def test_a_lexicon_density_gives_the_mass_from_the_built_geometry() -> None:
    """With the lexicon's density (ConceptMatch.mass_estimate_kg), the typical mass follows the built volume (a
    stated 20 x 3 x 3 cm sponge is not 8x a 10 cm one) or, hollow, the wall: area x wall x density."""
    sponge = KITCHEN_SPONGE.model_copy(update={"typical_size_m": 0.1, "typical_mass_kg": 0.018,
                                               "density_kg_per_m3": 90.0})
    assert typical_mass_at_size(sponge, 0.2, volume_m3=1.8e-4, area_m2=0.03) == pytest.approx(90.0 * 1.8e-4)
    assert typical_mass_at_size(sponge, 0.2) == pytest.approx(0.018 * 8)  # no geometry given: size scaling
    ball = RACQUETBALL.model_copy(update={"density_kg_per_m3": 950.0, "wall_thickness_m": 0.004})
    area, volume = 4 * math.pi * 0.035 ** 2, 4 / 3 * math.pi * 0.035 ** 3
    check = mass_check(volume, 0.07, area, "rubber", 950.0, (900.0, 1000.0), ball)
    assert check.typical_mass_kg == pytest.approx(area * 0.004 * 950.0)  # ~58 g, a tennis ball's order
    assert _hollow_scaled(*TENNIS_BALL, 0.07) / 1.5 <= check.typical_mass_kg <= _hollow_scaled(*TENNIS_BALL, 0.07)
    no_wall = ball.model_copy(update={"wall_thickness_m": None})  # hollow without a wall: never the solid volume
    assert typical_mass_at_size(no_wall, 0.07, volume, area) == pytest.approx(_hollow_scaled(0.0397, 0.05715, 0.07))


def test_a_concept_of_another_material_does_not_bind_the_mass() -> None:
    """A 'foam ball' is not the lexicon's hollow rubber ball: foam's density range only, and the record says why."""
    plan, m = _plan("a soft foam ball 8 cm", RACQUETBALL)
    assert plan.material == "pu_foam" and plan.mass.checks == ["density range of pu_foam (12-100 kg/m^3)"]
    assert m < 0.03 and "is for rubber" in plan.mass.notes[0]


def test_a_stated_density_stays_the_prior() -> None:
    plan = l1_plan(asset_of(AssetRequest(text="a rubber ball 7 cm", material_intent="rubber, density 980 kg/m3"),
                            RACQUETBALL), None)
    assert plan.targets.priors["density_kg_per_m3"] == 980.0 and not plan.mass.effective_density


def test_a_malformed_concept_is_one_clear_error() -> None:
    asset = asset_of(AssetRequest(text="a rubber ball 7 cm"))
    asset.record["info"]["concept"] = {"concept": "ball", "fallback_level": "guess"}
    with pytest.raises(InputError, match="info.concept is not a valid ConceptMatch"):
        l1_plan(asset, None)


@pytest.fixture(scope="module")
def ball_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An L0 directory of a 7 cm rubber ball, its geometry.json carrying the racquetball ConceptMatch."""
    out = write_l0_dir(AssetRequest(text="a rubber ball 7 cm"), tmp_path_factory.mktemp("l0") / "ball")
    record = json.loads((out / "geometry.json").read_text(encoding="utf-8"))
    record["info"]["concept"] = RACQUETBALL.model_dump(mode="json")
    (out / "geometry.json").write_text(json.dumps(record), encoding="utf-8")
    return out


def test_l1_on_a_fixture_record_with_a_concept_freezes_the_real_mass(ball_template: Path, tmp_path: Path,
                                                                     prefect_api: str) -> None:
    """The full L1 flow on a geometry record with a ConceptMatch: the hollow ball passes every gate at ~60 g and
    physical.json says which check applied; without the concept, the same ball is solid rubber."""
    ball = tmp_path / "ball"
    shutil.copytree(ball_template, ball)
    phys, outcome = run_l1(ball)
    assert outcome.passed and phys is not None
    real = _hollow_scaled(*TENNIS_BALL, float(max(load_l0(ball).mesh.extents)))
    assert real / 1.5 <= phys.mass_kg <= real * 1.5, phys.mass_kg
    record = json.loads((ball / "physical.json").read_text(encoding="utf-8"))
    assert record["mass_check"]["checks"] == ["typical mass of rubber_ball (racquetball, USA Racquetball rules)"]
    band = next(b for b in record["targets"]["bands"] if b["metric"] == "mass_kg")
    assert band["source"].startswith("typical mass of rubber_ball") and band["low"] <= phys.mass_kg <= band["high"]
    geometry = json.loads((ball / "geometry.json").read_text(encoding="utf-8"))
    del geometry["info"]["concept"]
    (ball / "geometry.json").write_text(json.dumps(geometry), encoding="utf-8")
    solid = l1_plan(load_l0(ball), None)
    assert solid.mass.checks == ["density range of rubber (900-1000 kg/m^3)"] and solid.mass.band_kg[0] > 2 * real
