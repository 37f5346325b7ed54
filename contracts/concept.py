"""What L0 understood a request to be: the lexicon concept, how it was found, and its typical real mass (SI units)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, SerializerFunctionWrapHandler, model_serializer

from contracts.base import Model

# How a concept was found, best first: the lexicon names the noun (or one of its synonyms); the noun is unknown but
# WordNet says it is a kind of an object the lexicon knows ("spaniel" < "dog"); the text names a body plan
# ("a four-legged plush", "a ring-shaped ..."); a category, from the text ("a plush animal", "a vegetable") or from
# WordNet ("okapi" < ... < "mammal"); WordNet's definition gives its shape and material ("puck: a vulcanized rubber
# disk"); only a material ("a foam thing"); nothing at all (a generic soft block). Everything after "synonym" is
# built by analogy, and says so.
FallbackLevel = Literal["exact", "synonym", "hypernym", "body_plan", "category", "gloss", "material", "generic"]
NAMED_LEVELS = ("exact", "synonym")


class ConceptMatch(Model):
    """The lexicon concept L0 built for a request, with the fallback taken and the typical mass of the real object."""

    concept: str = Field(description="lexicon key of the object built, e.g. 'plush_turtle'; 'generic_<plan>' when "
                         "the noun is unknown and only a body plan or category was understood")
    noun: str | None = Field(default=None, description="the head noun read from the text, e.g. 'turtle'")
    body_plan: str = Field(description="grammar body plan the shape program came from, e.g. 'quadruped'")
    category: str = Field(description="object category, e.g. 'plush_animal', 'fruit', 'baked_good'")
    fallback_level: FallbackLevel = Field(description="how the concept was found (contracts.concept.FallbackLevel)")
    fallback_note: str | None = Field(default=None, description="one line saying which fallback was taken and why")
    shape_from: str | None = Field(default=None, description="concept whose shape was used ('shaped like X'), "
                                   "when it differs from the object's own")
    default_material: str | None = Field(default=None, description="vocabulary material class the object is "
                                         "usually made of (contracts/vocab/materials.yaml)")
    hollow: bool = Field(default=False, description="a hollow object (ball, squeeze toy, bath toy): its mass is a "
                         "shell's, not the solid volume's")
    wall_thickness_m: float | None = Field(default=None, gt=0, description="shell wall of a hollow object [m]")
    sheet: bool = Field(default=False, description="a hollow object of one layer drawn as a thin solid (a flat band, a "
                        "sleeve): both faces of its built surface are that layer, so its shell is half the area")
    density_kg_per_m3: float | None = Field(default=None, gt=0, description="density of the object's solid volume "
                                            "(of its wall when hollow) from the lexicon: the material class's prior "
                                            "or the object's own effective density [kg/m^3]")
    typical_mass_kg: float | None = Field(default=None, gt=0, description="typical mass of the real object at its "
                                          "typical size [kg]")
    typical_size_m: float | None = Field(default=None, gt=0, description="longest extent the typical mass refers "
                                         "to [m]")
    mass_size_exponents: tuple[float, float] | None = Field(
        default=None, description="an object whose make-up is unknown: its typical mass x (built / typical size)^k "
        "with k the first exponent below the typical size and the second above it; None: 3 for a solid, 2 for a "
        "hollow shell")
    typical_mass_range_kg: tuple[float, float] | None = Field(
        default=None, description="plausible mass range of the real object at the built size [kg]")
    mass_source: str | None = Field(default=None, description="where the typical mass comes from (a product "
                                    "listing, a nutrition database, a standard)")
    finish: str | None = Field(default=None, description="the look of its surface in the stills when not its "
                               "material's (the lexicon entry's `finish`)")
    restitution: float | None = Field(default=None, gt=0.0, le=1.0, description="the real object's coefficient of "
                                      "restitution on a hard floor from the lexicon (a ball's rebound rule); L2 "
                                      "calibrates the material's loss to it when its material is the concept's [-]")
    restitution_source: str | None = Field(default=None, description="the rule the restitution is derived from")
    restitution_drop_m: float | None = Field(default=None, gt=0.0, description="the rule's drop height from the "
                                             "lexicon: L2 calibrates the loss at the speed of a fall from it (absent "
                                             "from the dump when None) [m]")
    inflation_gauge_pa: float | None = Field(default=None, gt=0.0, description="a pressurised hollow ball's internal "
                                             "gauge pressure from the lexicon; L0 records it with a shell, L2 adds "
                                             "the gas's stiffness to the wall (absent from the dump when None) [Pa]")
    inflation_source: str | None = Field(default=None, description="where inflation_gauge_pa comes from")
    youngs_modulus_range_pa: tuple[float, float] | None = Field(
        default=None, description="the rubber's Young's modulus band from the lexicon's Shore A hardness (Gent's "
        "relation); L2 tests the material against it when its material is the concept's (absent from the dump when "
        "None) [Pa]")
    youngs_modulus_source: str | None = Field(default=None, description="the hardness and its source the band comes "
                                              "from")
    colors: dict[str, str] = Field(default_factory=dict, description="part name -> colour word applied from the "
                                   "text")
    analogy: list[str] = Field(default_factory=list, description="how an unknown noun was understood, step by step "
                               "(WordNet's definition, the kind of thing it is, what lent the shape and mass)")
    states: list[str] = Field(default_factory=list, description="states the text put the object in and the shape "
                              "took ('rolled', 'folded', 'stacked'); states the shape cannot show are in warnings")
    stated_mass_kg: float | None = Field(default=None, gt=0, description="the object's mass as the request gives "
                                         "it: stated ('1 kg', '2 lb') or from a stated fill ('half full of rice': "
                                         "the fill's share of the bag's capacity x its bulk density + the empty "
                                         "bag); L1 takes it over the typical mass and the material's density [kg]")
    stated_mass_source: str | None = Field(default=None, description="where stated_mass_kg comes from (the words "
                                           "read, and for a fill its capacity, bulk density and source)")

    @model_serializer(mode="wrap")
    def _omit_absent_keys(self, handler: SerializerFunctionWrapHandler) -> Any:
        """The inflation keys, the rule's drop height and the hardness band are left out of the dump when None (every
        concept but a pressurised ball, a rule ball, a rubber of published hardness), so records and cache keys from
        before them are unchanged."""
        out = handler(self)
        if isinstance(out, dict):
            for key in ("inflation_gauge_pa", "inflation_source", "restitution_drop_m", "youngs_modulus_range_pa",
                        "youngs_modulus_source"):
                if out.get(key, 0.0) is None:
                    out.pop(key)
        return out

    @property
    def by_analogy(self) -> bool:
        """True when the object was not found by name in the lexicon (any fallback)."""
        return self.fallback_level not in NAMED_LEVELS

    def analogy_line(self) -> str | None:
        """One line for a person: what was built by analogy and why (None for a named object)."""
        if not self.by_analogy:
            return None
        return f"built by analogy: {self.fallback_note or self.concept}"

    def mass_estimate_kg(self, volume_m3: float, area_m2: float) -> float | None:
        """The object's mass from its built geometry: wall area x wall thickness x density when hollow (half the area
        for a one-layer sheet), else volume x density [kg]; None when the lexicon gave no density (a material-only
        fallback)."""
        if self.density_kg_per_m3 is None:
            return None
        if self.hollow and self.wall_thickness_m is not None:
            area = area_m2 / 2.0 if self.sheet else area_m2
            return min(area * self.wall_thickness_m, volume_m3) * self.density_kg_per_m3
        return volume_m3 * self.density_kg_per_m3
