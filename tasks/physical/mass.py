"""L1's mass check: the material's density range times the volume, and the named object's typical mass when L0 knows
it (contracts.concept.ConceptMatch). A hollow object built as its shell (L0's ParticleBody) has the wall's mass over
the shell's particles; one built solid gets an effective density: the shell's mass over the enclosed volume, so that
the solid MPM body weighs what the real, hollow one weighs."""

from __future__ import annotations

import math

from pydantic import Field

from contracts.base import Model
from contracts.concept import ConceptMatch
from tasks.geometry.shell import Surface, concept_wall_m, fitted_wall_m
from tasks.physical.model import MASS_RANGE_KG

SOLID_EXPONENT = 3.0  # a solid's mass scales with its volume: (length ratio)^3
HOLLOW_EXPONENT = 2.0  # a shell of fixed wall thickness scales with its area: (length ratio)^2
CONCEPT_BAND_FACTOR = (0.5, 2.0)  # plausible mass around the typical mass at the built size, when L0 gives no range
STATED_BAND_FACTOR = (0.9, 1.1)  # a mass the request states (or its fill gives): within 10 % of it


class MassCheck(Model):
    """What L1's mass gate checks and the density it starts from, with the reason (SI units)."""

    band_kg: tuple[float, float] = Field(description="plausible mass of the object as built [kg]")
    density_kg_per_m3: float = Field(gt=0, description="density prior: the material's, or an effective density "
                                     "(object mass / enclosed volume) [kg/m^3]")
    density_range_kg_per_m3: tuple[float, float] = Field(description="densities the mass gate admits [kg/m^3]")
    checks: list[str] = Field(description="which checks set the band: 'density range of <material>' and/or "
                              "'typical mass of <concept> (<source>)'")
    source: str = Field(description="one line naming the band's sources (TargetBand.source)")
    typical_mass_kg: float | None = Field(default=None, description="typical mass of the named object at the built "
                                          "size [kg]")
    effective_density: bool = Field(default=False, description="the density prior is an object mass over the "
                                    "enclosed volume, not the material's")
    notes: list[str] = Field(default_factory=list, description="why the band or the density prior moved")


def typical_mass_at_size(concept: ConceptMatch, longest_m: float, volume_m3: float | None = None,
                         area_m2: float | None = None, surface: Surface | None = None) -> float | None:
    """The named object's typical mass as built [kg]: from its built geometry when the lexicon gives its density
    (volume x density; when hollow, the wall's true volume on the built `surface` x density, the wall fitted to the
    typical mass when the lexicon gives one: shell_estimate; without a surface, wall area x wall thickness x density:
    ConceptMatch.mass_estimate_kg), else its typical mass scaled to the built size, x (L / L_typical)^3 for a solid,
    ^2 for a hollow shell."""
    return _typical(concept, longest_m, volume_m3, area_m2, surface)[0]


def shell_estimate(concept: ConceptMatch, surface: Surface) -> tuple[float, str] | None:
    """A hollow concept's mass on its built surface and how it was found: its wall's density x the true volume of
    its wall (tasks.geometry.shell: Steiner's formula, not area x wall, which over-states a thick curved wall), the
    wall fitted so that the surface at the typical size holds the typical mass (concept_wall_m: the same wall L0
    builds the shell of), the lexicon's when there is no typical mass; None when it does not apply (solid, no wall or
    density, a one-layer sheet: weighed by half its area x wall) or no wall at that density holds the typical mass on
    this shape (a KONG toy's 120 g is more than its built solid at rubber's 950 kg/m^3: area x wall, as before)."""
    density, wall = concept.density_kg_per_m3, concept.wall_thickness_m
    if not concept.hollow or concept.sheet or density is None or wall is None:
        return None
    built = concept_wall_m(concept, surface)
    if built is None or (built == wall and concept.typical_mass_kg is not None and concept.typical_size_m is not None
                         and fitted_wall_m(surface, concept.typical_mass_kg, concept.typical_size_m, density) is None):
        return None
    how = f"a {built * 1e3:.3g} mm wall's true volume"
    if built != wall:
        how += (f" (the wall fitted to {_g(concept.typical_mass_kg or 0.0)} at {concept.typical_size_m:g} m on this "
                f"shape; the lexicon's {wall * 1e3:g} mm)")
    return density * surface.shell_volume_m3(built), f"its density {density:g} kg/m^3 x {how}"


def _typical(concept: ConceptMatch, longest_m: float, volume_m3: float | None,
             area_m2: float | None, surface: Surface | None = None) -> tuple[float | None, str]:
    """typical_mass_at_size and how it was found (for the record)."""
    estimate = getattr(concept, "mass_estimate_kg", None)
    density = getattr(concept, "density_kg_per_m3", None)
    wall = getattr(concept, "wall_thickness_m", None)
    shell = shell_estimate(concept, surface) if surface is not None and estimate is not None else None
    if shell is not None and shell[0] > 0:
        return shell
    if estimate is not None and volume_m3 and area_m2 is not None and (not concept.hollow or wall is not None):
        m = estimate(volume_m3, area_m2)
        if m is not None and m > 0:
            how = f"a {wall * 1e3:g} mm wall" if concept.hollow and wall else "the built volume"
            return float(m), f"its density {density:g} kg/m^3 x {how}"
    if concept.typical_mass_kg is None:
        if concept.typical_mass_range_kg is None:
            return None, ""
        lo, hi = concept.typical_mass_range_kg
        return math.sqrt(lo * hi), "the middle of L0's range"
    if concept.typical_size_m is None:
        return concept.typical_mass_kg, f"{_g(concept.typical_mass_kg)}, not scaled (no typical size)"
    exponent = HOLLOW_EXPONENT if concept.hollow else SOLID_EXPONENT
    if concept.mass_size_exponents is not None:  # an unknown object: as the lexicon's objects grow (concepts)
        exponent = concept.mass_size_exponents[longest_m > concept.typical_size_m]
    m = concept.typical_mass_kg * (longest_m / concept.typical_size_m) ** exponent
    return m, (f"{_g(concept.typical_mass_kg)} at {concept.typical_size_m:g} m x ({longest_m:.3g} m / "
               f"{concept.typical_size_m:g} m)^{exponent:g}")


def concept_band(concept: ConceptMatch, longest_m: float, volume_m3: float | None = None,
                 area_m2: float | None = None, surface: Surface | None = None) -> tuple[float, float] | None:
    """The plausible mass of the named object as built [kg]: [0.5, 2] x its typical mass as built
    (typical_mass_at_size), L0's range when only that is known."""
    scalable = concept.typical_mass_kg is not None and concept.typical_size_m is not None
    has_density = getattr(concept, "density_kg_per_m3", None) is not None
    if concept.typical_mass_range_kg is not None and not scalable and not has_density:
        lo, hi = sorted(concept.typical_mass_range_kg)
        if lo > 0:
            return lo, hi
    m = typical_mass_at_size(concept, longest_m, volume_m3, area_m2, surface)
    if m is None:
        return None
    return m * CONCEPT_BAND_FACTOR[0], m * CONCEPT_BAND_FACTOR[1]


WALL_MATERIAL_RATIO = 3.0  # an object this many times lighter than its stated material is made of it, not solid [-]


def concept_applies(concept: ConceptMatch | None, material: str, material_density_low: float | None = None) -> bool:
    """The concept's typical mass and hollowness describe this object: the request's material is the concept's own
    (a 'foam ball' is not the lexicon's hollow rubber ball, so a ball's typical mass does not bind it), or the object
    is far lighter than a solid of the stated material (its own effective density below the material's lowest /
    WALL_MATERIAL_RATIO): the material is what its walls or uppers are made of ('a rubber climbing shoe' weighs a
    shoe, not a shoe-shaped block of rubber)."""
    if concept is None:
        return False
    if concept.default_material is None or concept.default_material == material:
        return True
    own = getattr(concept, "density_kg_per_m3", None)
    return (own is not None and material_density_low is not None and not concept.hollow
            and own * WALL_MATERIAL_RATIO < material_density_low)


def _clamp_band(lo: float, hi: float) -> tuple[float, float]:
    """A mass band within what a robot hand can hold (MASS_RANGE_KG)."""
    lo, hi = max(lo, MASS_RANGE_KG[0]), min(hi, MASS_RANGE_KG[1])
    return (lo, hi) if lo <= hi else (hi, hi)


def _g(kg: float) -> str:
    """A mass for a message, in g below 1 kg."""
    return f"{kg * 1e3:.3g} g" if kg < 1.0 else f"{kg:.3g} kg"


def mass_check(volume_m3: float, longest_m: float, area_m2: float, material: str, density_prior: float,
               density_range: tuple[float, float], concept: ConceptMatch | None = None,
               shell_wall_m: float | None = None, stated_density: bool = False,
               density_bounds: tuple[float, float] = (0.0, math.inf),
               enclosed_volume_m3: float | None = None, surface: Surface | None = None) -> MassCheck:
    """The mass band, density prior and gate range of an object of this volume, material and (optional) concept.

    volume_m3 is what the particles fill; enclosed_volume_m3, when given and larger, the mesh's: the particles are a
    hollow object's shell (L0's ParticleBody), the concept's wall mass is found from the mesh (its area x wall, at most
    its volume) and spread over the shell, so the density prior is the wall's (not an effective density over the
    enclosed volume). surface: the built mesh's measures (tasks.geometry.shell.Surface), with which a hollow concept's
    wall is weighed by its true volume, fitted to its typical mass (shell_estimate); without it, area x wall.

    With no concept that applies: the material's density range x volume (a hollow concept with no typical mass but
    a wall thickness: the shell's mass). With one: the intersection of that band with [0.5, 2] x the concept's typical
    mass as built (typical_mass_at_size), or that range alone when they do not meet (or the object is hollow), the
    density prior moved towards the typical mass (an effective density = typical mass / volume when outside the
    material's range), clamped to density_bounds. A density stated in the request (stated_density) stays the prior.
    """
    if volume_m3 <= 0 or longest_m <= 0:
        raise ValueError(f"need a positive volume and size, got {volume_m3} m^3, {longest_m} m")
    dlo, dhi = density_range
    by_density = _clamp_band(dlo * volume_m3, dhi * volume_m3)
    density_check = f"density range of {material} ({dlo:g}-{dhi:g} kg/m^3)"
    stated = getattr(concept, "stated_mass_kg", None) if concept is not None else None
    if stated:  # the request gives the mass ('1 kg', 'half full of rice'): it binds whatever the material
        check = f"mass given by the request ({concept.stated_mass_source or _g(stated)})"  # type: ignore[union-attr]
        band = _clamp_band(stated * STATED_BAND_FACTOR[0], stated * STATED_BAND_FACTOR[1])
        return _finish(band, stated, volume_m3, density_prior, None, [check], stated, True, stated_density,
                       density_bounds, [f"the request gives {_g(stated)}: effective density = that mass / volume"])
    enclosed = enclosed_volume_m3 if enclosed_volume_m3 is not None else volume_m3
    shell = enclosed > volume_m3 * (1.0 + 1e-9)
    applies = concept_applies(concept, material, dlo)
    cband = concept_band(concept, longest_m, enclosed, area_m2, surface) if applies and concept is not None else None
    notes: list[str] = []
    if concept is not None and not applies:
        notes.append(f"the typical mass of {concept.concept} is for {concept.default_material}; the request names "
                     f"{material}: density range only")
    if cband is None:
        wall = getattr(concept, "wall_thickness_m", None) or shell_wall_m
        if applies and concept is not None and concept.hollow and wall:
            return _shell_check(volume_m3, area_m2, material, density_prior, density_range, concept, wall,
                                stated_density, density_bounds, notes)
        return MassCheck(band_kg=by_density, density_kg_per_m3=density_prior, density_range_kg_per_m3=density_range,
                         checks=[density_check], source=density_check, notes=notes)
    assert concept is not None
    typical, how = _typical(concept, longest_m, enclosed, area_m2, surface)
    if typical is None:
        typical, how = math.sqrt(cband[0] * cband[1]), "the middle of L0's range"
    typical_check = f"typical mass of {concept.concept} ({concept.mass_source or 'lexicon'})"
    notes.append(f"typical mass of {concept.concept} as built: {_g(typical)} ({how})")
    lo, hi = max(by_density[0], cband[0]), min(by_density[1], cband[1])
    own = getattr(concept, "density_kg_per_m3", None)
    own_outside = own is not None and not dlo <= own <= dhi  # the lexicon's effective density of this object
    if not concept.hollow and lo <= hi and not own_outside:
        band, checks, effective = (lo, hi), [density_check, typical_check], False
    else:
        band, checks, effective = _clamp_band(*cband), [typical_check], True
        if concept.hollow and shell:
            notes.append(f"hollow {concept.concept} built as its shell ({volume_m3 * 1e6:.3g} cm^3 of particles in "
                         f"{enclosed * 1e6:.3g} cm^3): density = wall mass / shell volume")
        elif concept.hollow:
            notes.append(f"hollow {concept.concept}: effective density = shell mass / enclosed volume")
        elif own_outside:
            notes.append(f"{concept.concept} has its own effective density {own:g} kg/m^3, outside the {density_check}: "
                         f"its typical mass as built")
        else:
            notes.append(f"the {density_check} gives {_g(by_density[0])}-{_g(by_density[1])} at this volume, outside "
                         f"the typical {_g(cband[0])}-{_g(cband[1])} of {concept.concept}: effective density "
                         f"= typical mass / volume")
    target = min(max(typical, band[0]), band[1])
    return _finish(band, target, volume_m3, density_prior, density_range if not effective else None, checks,
                   typical, effective, stated_density, density_bounds, notes)


def _shell_check(volume_m3: float, area_m2: float, material: str, density_prior: float,
                 density_range: tuple[float, float], concept: ConceptMatch, shell_wall_m: float, stated_density: bool,
                 density_bounds: tuple[float, float], notes: list[str]) -> MassCheck:
    """A hollow object with no typical mass: a shell of the lexicon's (else the material's) wall thickness over the
    surface, at the material's density."""
    shell_m3 = min(area_m2 * shell_wall_m, volume_m3)
    dlo, dhi = density_range
    # the wall thickness is a class value, uncertain by about 2x either way: the concept band's factors
    band = _clamp_band(dlo * shell_m3 * CONCEPT_BAND_FACTOR[0], dhi * shell_m3 * CONCEPT_BAND_FACTOR[1])
    check = (f"density range of {material} ({dlo:g}-{dhi:g} kg/m^3) over a {shell_wall_m * 1e3:g} mm shell "
             f"({shell_m3 * 1e6:.3g} cm^3)")
    notes.append(f"hollow {concept.concept} with no typical mass: effective density = shell mass / enclosed volume")
    target = min(max(density_prior * shell_m3, band[0]), band[1])
    return _finish(band, target, volume_m3, density_prior, None, [check], None, True, stated_density,
                   density_bounds, notes)


def _finish(band: tuple[float, float], target_kg: float, volume_m3: float, density_prior: float,
            material_range: tuple[float, float] | None, checks: list[str], typical: float | None, effective: bool,
            stated_density: bool, density_bounds: tuple[float, float], notes: list[str]) -> MassCheck:
    """The density prior at the target mass (clamped to the contract's bounds) and the gate's density range."""
    rng = (band[0] / volume_m3, band[1] / volume_m3)
    if material_range is not None:  # the band lies inside the material's: the gate keeps the tighter of the two
        rng = (max(rng[0], material_range[0]), min(rng[1], material_range[1]))
    density = target_kg / volume_m3
    blo, bhi = density_bounds
    if not blo <= density <= bhi:
        clamped = min(max(density, blo), bhi)
        notes.append(f"effective density {density:.3g} kg/m^3 clamped to the L1 contract's [{blo:g}, {bhi:g}] "
                     f"kg/m^3: {_g(clamped * volume_m3)}")
        density = clamped
        rng = (min(rng[0], density), max(rng[1], density))
        band = _clamp_band(min(band[0], density * volume_m3), max(band[1], density * volume_m3))
    if stated_density:
        density = density_prior
    return MassCheck(band_kg=band, density_kg_per_m3=density, density_range_kg_per_m3=rng, checks=checks,
                     source="; ".join(checks), typical_mass_kg=typical, effective_density=effective and not
                     stated_density, notes=notes)
