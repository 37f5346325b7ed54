"""The object lexicon (data under contracts/lexicon/): everyday deformable objects with their body plan, colours,
material, typical size and typical mass with its source (SI units)."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from pydantic import Field, ValidationError, model_validator

from contracts.base import Model
from contracts.errors import InputError
from contracts.yaml_io import load_yaml

LEXICON_DIR = Path(__file__).with_name("lexicon")
MATERIALS_FILE = Path(__file__).parent / "vocab" / "materials.yaml"
COLORS_FILE = LEXICON_DIR / "colors.yaml"


@functools.lru_cache(maxsize=1)
def material_densities() -> dict[str, float]:
    """Vocabulary material class -> prior density [kg/m^3] (contracts/vocab/materials.yaml)."""
    raw = load_yaml(MATERIALS_FILE.read_text(encoding="utf-8"))["materials"]
    return {k: float(v["priors"]["density_kg_per_m3"]) for k, v in raw.items()}


class LexiconEntry(Model):
    """One everyday object: how to build it and what the real one is like."""

    key: str = Field(description="stable concept key, e.g. 'plush_turtle'")
    nouns: list[str] = Field(min_length=1, description="nouns and synonyms that name it (singular; plurals by code); "
                             "'(generic)' for the generic_* concepts, which no noun names")
    plan: str | None = Field(default=None, description="grammar body plan (tasks/geometry/grammar); with a catalogue "
                             "shape too, the plan draws the object only in what the drawing lacks: a state ('folded', "
                             "'rolled'), stated sheet sizes, a curl")
    catalogue: str | None = Field(default=None, description="hand-written program in tasks/geometry/catalogue.yaml "
                                  "that draws the object as it is usually seen, instead of its plan")
    params: dict[str, Any] = Field(default_factory=dict, description="body-plan parameters")
    drawn_state: str | None = Field(default=None, description="the state its hand-written shape shows ('rolled', "
                                    "'folded', 'crumpled', 'a pair': a pair of shoes drawn and weighed as the pair): a request that says so is drawn, "
                                    "not warned about nor doubled")
    colors: dict[str, str] = Field(default_factory=dict, description="part or part group -> colour word")
    material: str = Field(description="vocabulary material class (contracts/vocab/materials.yaml)")
    category: str
    size_m: float = Field(ge=0.005, le=2.0, description="typical longest extent [m]")
    mass_kg: float = Field(gt=0, le=25.0, description="typical mass of the real object at size_m [kg]")
    mass_source: str = Field(min_length=8, description="where mass_kg comes from (the kind of reference)")
    hollow: bool = Field(default=False, description="a hollow shell (ball, squeeze toy, bath toy, inflatable)")
    wall_m: float | None = Field(default=None, gt=0, le=0.02, description="shell wall thickness of a hollow object [m]")
    sheet: bool = Field(default=False, description="a hollow object that is one layer drawn as a thin solid (a flat "
                        "band, a sleeve): its built surface counts the layer twice, so its shell is half the area")
    density_kg_per_m3: float | None = Field(default=None, gt=0, description="effective density of the solid object "
                                            "when the material class's prior does not describe it [kg/m^3]")
    finish: str | None = Field(default=None, description="how its surface looks when not as its material class "
                               "(tasks.render.finish.FINISHES: 'fish' for a fillet's fat lines, 'rice' for cooked rice)")
    takes_shape: bool = Field(default=False, description="made in any shape: 'a cat cushion' is a cushion shaped "
                              "like a cat")
    empty_mass_kg: float | None = Field(default=None, gt=0, le=25.0, description="mass of a filled object (a "
                                        "hot-water bottle, a gel pack) with nothing in it [kg]; its source is in "
                                        "mass_source")
    walled: bool = Field(default=False, description="its walls hold their shape with nothing in it (a tub, a carton box, "
                         "an egg box): said empty it weighs empty_mass_kg as built, not squashed flat like a bag")
    restitution: float | None = Field(default=None, gt=0.0, le=1.0, description="coefficient of restitution of the "
                                      "real object on a hard floor, e = sqrt(rebound height / drop height), where its "
                                      "governing body or maker publishes a rebound rule; L2 calibrates the material's "
                                      "loss to it instead of the material class's prior [-]")
    restitution_source: str | None = Field(default=None, min_length=8, description="the rule restitution is derived "
                                           "from (document, drop height and rebound band)")
    restitution_drop_m: float | None = Field(default=None, gt=0.0, le=10.0, description="the rule's drop height, "
                                             "floor to the bottom of the ball (its source is restitution_source): L2 "
                                             "calibrates the loss at the speed of a fall from it [m]")
    inflation_gauge_pa: float | None = Field(default=None, gt=0.0, le=1.0e6, description="internal gauge pressure "
                                             "(over the ambient) of a pressurised hollow ball; L2 adds the gas's "
                                             "contact stiffness to its shell's wall as a modulus "
                                             "(tasks.realworld.inflation) [Pa]")
    inflation_source: str | None = Field(default=None, min_length=8, description="where inflation_gauge_pa comes "
                                         "from (a rule, or what is commonly cited, and how it was converted)")
    hardness_shore_a: tuple[float, float] | None = Field(default=None, description="the Shore A hardness range of "
                                                         "its rubber where a rule or maker publishes it; L2's "
                                                         "modulus band for the rubber is Gent's E at its ends [-]")
    hardness_source: str | None = Field(default=None, min_length=8, description="where hardness_shore_a comes from")
    posed_by: str | None = Field(default=None, description="a body-plan entry that shows this (hand-written) object "
                                 "sitting or lying when asked ('a dog lying down'): its shape is used then")

    @model_validator(mode="after")
    def _check(self) -> LexiconEntry:
        if self.plan is None and self.catalogue is None:
            raise ValueError(f"{self.key}: give a plan or a catalogue shape (or both: the plan for its states)")
        if self.material not in material_densities():
            raise ValueError(f"{self.key}: material '{self.material}' is not in contracts/vocab/materials.yaml")
        if self.hollow and self.wall_m is None and self.density_kg_per_m3 is None:
            raise ValueError(f"{self.key}: a hollow object needs wall_m (or an effective density)")
        if (self.restitution is None) != (self.restitution_source is None):
            raise ValueError(f"{self.key}: give restitution and restitution_source together")
        if (self.restitution is None) != (self.restitution_drop_m is None):
            raise ValueError(f"{self.key}: give restitution with its rule's drop height (restitution_drop_m) together")
        if (self.inflation_gauge_pa is None) != (self.inflation_source is None):
            raise ValueError(f"{self.key}: give inflation_gauge_pa and inflation_source together")
        if (self.hardness_shore_a is None) != (self.hardness_source is None):
            raise ValueError(f"{self.key}: give hardness_shore_a and hardness_source together")
        if self.hardness_shore_a is not None and not (10.0 <= self.hardness_shore_a[0] <= self.hardness_shore_a[1]
                                                      <= 90.0):
            raise ValueError(f"{self.key}: hardness_shore_a must be a low <= high range within Shore A 10-90")
        if self.inflation_gauge_pa is not None and not (self.hollow and self.wall_m is not None):
            raise ValueError(f"{self.key}: an inflation pressure needs a hollow object with a wall (wall_m)")
        return self

    @property
    def solid_density_kg_per_m3(self) -> float:
        """Density of the object's solid volume, or of its wall when hollow [kg/m^3]."""
        return self.density_kg_per_m3 or material_densities()[self.material]


class Lexicon(Model):
    """All entries (key -> entry) and the colour words (word -> linear RGB)."""

    entries: dict[str, LexiconEntry]
    colors: dict[str, tuple[float, float, float]]


def _read(path: Path) -> list[dict[str, Any]]:
    raw = load_yaml(path.read_text(encoding="utf-8")) or {}
    defaults = raw.get("defaults", {})
    out = []
    for key, fields in (raw.get("entries") or {}).items():
        merged = {**defaults, **(fields or {})}
        if "params" in defaults and "params" in (fields or {}):
            merged["params"] = {**defaults["params"], **fields["params"]}
        if "colors" in defaults and "colors" in (fields or {}):
            merged["colors"] = {**defaults["colors"], **fields["colors"]}
        out.append({"key": key, **merged})
    return out


@functools.lru_cache(maxsize=1)
def load_lexicon() -> Lexicon:
    """Every entry of contracts/lexicon/*.yaml (except colors.yaml), validated; duplicate keys are an error."""
    entries: dict[str, LexiconEntry] = {}
    for path in sorted(LEXICON_DIR.glob("*.yaml")):
        if path.name == COLORS_FILE.name:
            continue
        for raw in _read(path):
            try:
                entry = LexiconEntry(**raw)
            except ValidationError as exc:
                raise InputError(f"{path.name}: entry '{raw.get('key')}': {exc.errors()[0]['msg']}") from exc
            if entry.key in entries:
                raise InputError(f"{path.name}: duplicate lexicon key '{entry.key}'")
            entries[entry.key] = entry
    colors = load_yaml(COLORS_FILE.read_text(encoding="utf-8"))["colors"]
    for entry in entries.values():
        unknown = sorted(set(entry.colors.values()) - set(colors))
        if unknown:
            raise InputError(f"lexicon entry '{entry.key}': unknown colour words {unknown} (add them to colors.yaml)")
    return Lexicon(entries=entries, colors={k: tuple(float(x) for x in v) for k, v in colors.items()})
