"""What L1 starts from and what a candidate of it is: the priors (density, friction) and the mass check of an asset
(its request's material words, the concept L0 built), the physical model of a candidate's values, the mass model's
observations, and the physical model a probe runs with outside L1 (the asset's, or one from the priors)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contracts.agents import TargetBand, TargetBehaviour
from contracts.errors import InputError
from contracts.physical import PhysicalModel
from contracts.probes import ProbeResult, ProbeSpec
from contracts.stage import StageContract, load_contract
from tasks.agents.intent import asset_material, asset_targets, concept_of, explicit_numbers
from tasks.agents.vocab import load_material_vocab
from tasks.asset_dir import AssetDir, geometry_info
from tasks.geometry.outputs import L0Asset
from tasks.geometry.shell import Surface
from tasks.physical.mass import MassCheck, mass_check
from tasks.physical.model import build_physical_model, mass_plausible


@dataclass(frozen=True)
class L1Plan:
    """What L1 starts from: target behaviour and priors, the material class and the mass check."""

    targets: TargetBehaviour
    material: str
    mass: MassCheck


def longest_extent_m(asset: L0Asset) -> float:
    """Longest side of the asset's bounding box as L0 built it [m] (the size a typical mass is scaled to): a body L0
    turned onto its resting face (geometry.json `info.reoriented`) is measured in the frame it was built and sized in
    (`info.program.target_extent_m`): a padel ball turned off its seam has a smaller box on the ground's axes, and
    weighed 51 g of its 56-59 g."""
    info = asset.record.get("info") or {}
    built = (info.get("program") or {}).get("target_extent_m")
    if info.get("reoriented") and built:
        return float(max(built))
    return float(np.max(asset.mesh.extents))


def l1_plan(asset: L0Asset, intent: str | None, contract: StageContract | None = None) -> L1Plan:
    """Priors (density, friction) from the asset's request (or the intent given) and its mass check: the material's
    density range x volume, and the typical mass of the concept L0 built when it has one (tasks.physical.mass)."""
    vocab = load_material_vocab()
    contract = contract or load_contract("L1")
    words = asset_targets(asset.record, intent, vocab)
    material = asset_material(asset.record, words, vocab)
    entry = vocab.materials[material]
    priors = {k: words.priors[k] for k in ("density_kg_per_m3", "ground_friction", "gripper_friction")
              if k in words.priors}
    rho = priors["density_kg_per_m3"]
    drange = entry.prior_ranges.get("density_kg_per_m3", (rho / 2, rho * 2))
    field = contract.field("density_kg_per_m3")
    longest = longest_extent_m(asset)
    mass = mass_check(float(np.sum(asset.volumes_m3)), longest, float(asset.mesh.area), material,
                      rho, drange, concept_of(asset.record), entry.shell_wall_thickness_m,
                      "density_kg_per_m3" in explicit_numbers(words.intent)[1], (field.low, field.high),
                      asset.body.enclosed_volume_m3 if asset.shell and asset.body is not None else None,
                      dataclasses.replace(Surface.of(asset.mesh), longest_m=longest))
    priors["density_kg_per_m3"] = mass.density_kg_per_m3
    lo, hi = mass.band_kg
    bands = [TargetBand(metric="mass_kg", unit="kg", low=lo, high=hi, scale="log", source=mass.source)]
    targets = TargetBehaviour(bands=bands, priors=priors, matched_words=words.matched_words, intent=words.intent)
    return L1Plan(targets, material, mass)


def l1_targets(asset: L0Asset, intent: str | None) -> tuple[TargetBehaviour, str, tuple[float, float]]:
    """Priors, the material class and the density range the mass gate admits (l1_plan without the mass record)."""
    plan = l1_plan(asset, intent)
    return plan.targets, plan.material, plan.mass.density_range_kg_per_m3


def physical_from_values(asset: L0Asset, values: dict[str, float], category: str) -> PhysicalModel:
    """The PhysicalModel of a candidate's density and friction."""
    return build_physical_model(asset.particles_m, asset.volumes_m3, asset.spacing_m, values["density_kg_per_m3"],
                                values["ground_friction"], values["gripper_friction"], category)


def mass_result(phys: PhysicalModel, density_range: tuple[float, float]) -> ProbeResult:
    """The mass model's observations (no simulation)."""
    ok = mass_plausible(phys.mass_kg, phys.density_kg_per_m3, density_range)
    return ProbeResult(spec=ProbeSpec(kind="mass"), sim_calls=0,
                       metrics={"mass_kg": phys.mass_kg, "mass_plausibility": float(ok), "volume_m3": phys.volume_m3})


def rigid_probe_values(contract: StageContract, asset_dir: Path, asset: L0Asset, rho: float | None = None,
                       friction: float | None = None) -> dict[str, float]:
    """The density and friction one rigid probe runs with outside L1: the asset's L1 model (else L1's priors), with
    rho and the ground friction overridden when given; InputError outside the L1 contract's bounds."""
    if AssetDir(asset_dir).has("physical"):
        base = AssetDir(asset_dir).physical_model()
        values = {"density_kg_per_m3": base.density_kg_per_m3, "ground_friction": base.ground_friction,
                  "gripper_friction": base.gripper_friction}
    else:
        values = dict(l1_targets(asset, None)[0].priors)
    if rho is not None:
        values["density_kg_per_m3"] = rho
    if friction is not None:
        values["ground_friction"] = friction
    for name, v in values.items():
        if not contract.field(name).contains(float(v)):
            f = contract.field(name)
            raise InputError(f"{name}={v} is outside the L1 contract's bounds [{f.low}, {f.high}] {f.unit}")
    return values


def physical_for(asset_dir: Path, asset: L0Asset, rho: float | None = None) -> PhysicalModel:
    """The asset's L1 model, else one from the intent's priors (probing before L1 ran); rho overrides the density."""
    if AssetDir(asset_dir).has("physical"):
        phys = AssetDir(asset_dir).physical_model()
    else:
        pri = l1_targets(asset, None)[0].priors  # L1's start values, mass check included
        phys = build_physical_model(asset.particles_m, asset.volumes_m3, asset.spacing_m,
                                    float(pri["density_kg_per_m3"]), float(pri["ground_friction"]),
                                    float(pri["gripper_friction"]), geometry_info(asset.record).category)
    if rho is None:
        return phys
    if not (math.isfinite(rho) and rho > 0):
        raise InputError(f"density must be a positive finite number of kg/m^3, got {rho}")
    return phys.model_copy(update={"density_kg_per_m3": float(rho), "mass_kg": float(rho) * phys.volume_m3})
