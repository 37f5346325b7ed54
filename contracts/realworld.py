"""The real-world validation set (contracts/measured/realworld.yaml) and the `bench realworld` report: published
measurements of everyday soft objects beside what DeformSmith builds from each object's plain name (issue #39)."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from contracts.base import Model
from contracts.yaml_io import load_yaml

REALWORLD_YAML = Path(__file__).resolve().parent / "measured" / "realworld.yaml"


class Source(Model):
    """Where a measurement is published."""

    citation: str = Field(min_length=10, description="authors, year, title, journal / the body and rule number / the "
                          "database and entry")
    url: str | None = Field(default=None, description="where the publication or rule can be read")
    checked_url: str | None = Field(default=None, description="the page the value was checked against when the set "
                                    "was curated (a copy or a quotation of the source); None: taken from the cited "
                                    "publication and not re-checked")


class ValueRange(Model):
    """A published value or range [low, high] (a single value: low == high)."""

    low: float = Field(gt=0)
    high: float = Field(gt=0)

    @model_validator(mode="after")
    def _ordered(self) -> ValueRange:
        """low <= high."""
        if self.low > self.high:
            raise ValueError(f"range low {self.low} > high {self.high}")
        return self


class MassMeasurement(Model):
    """The object's mass as published (a food database's portion, a ball's rule)."""

    mass_kg: ValueRange
    basis: str = Field(description="what was weighed, e.g. 'medium fruit, 2-2/3 in diameter'")
    source: Source


class ModulusMeasurement(Model):
    """A published Young's modulus of the object's material."""

    youngs_modulus_pa: ValueRange
    method: str = Field(description="how it was measured: 'uniaxial compression of cylinders', 'small-strain "
                        "dynamic test', ...")
    source: Source


class LoadDeformation(Model):
    """A rule's squeeze test: a load between two flat plates and the ball's deformation under it (tennis)."""

    load_n: float = Field(gt=0, description="load on the ball [N]")
    deformation_m: ValueRange = Field(description="plate-to-plate deformation under the load [m]")
    diameter_m: ValueRange = Field(description="the ball's diameter in the same rule [m]")
    source: Source


class RuleDrop(Model):
    """A regulation ball's rebound test: dropped from a height onto a rigid surface, it must rebound into a band."""

    drop_height_m: float = Field(gt=0, description="drop height, floor to the bottom of the ball [m]")
    rebound_height_m: ValueRange = Field(description="rebound band, floor to the bottom of the ball [m]")
    surface: str = Field(description="what the rule drops it on (concrete, steel plate, granite, the playing floor)")
    diameter_m: float = Field(gt=0, description="the rule's ball diameter (its drag area in flight) [m]")
    temperature_c: float | None = Field(default=None, description="the rule's test temperature [degC]")
    source: Source

    @property
    def rebound_ratio(self) -> ValueRange:
        """The band as rebound height / drop height [-]."""
        return ValueRange(low=self.rebound_height_m.low / self.drop_height_m,
                          high=self.rebound_height_m.high / self.drop_height_m)


ObjectKind = Literal["ball", "food", "household"]


class RealWorldObject(Model):
    """One everyday object: its plain name (what the bench builds), the lexicon concept that name should build and
    what is published about it."""

    name: str = Field(min_length=2, description="the plain name the bench builds, e.g. 'tennis ball'")
    concept: str = Field(description="lexicon key the name should build (contracts/lexicon)")
    kind: ObjectKind
    mass: MassMeasurement | None = None
    modulus: ModulusMeasurement | None = None
    squeeze: LoadDeformation | None = None
    rebound: RuleDrop | None = None
    notes: str = ""

    @model_validator(mode="after")
    def _measured(self) -> RealWorldObject:
        """At least one measurement, and a rebound rule only on a ball."""
        if not (self.mass or self.modulus or self.squeeze or self.rebound):
            raise ValueError(f"{self.name}: no measurement")
        if self.rebound is not None and self.kind != "ball":
            raise ValueError(f"{self.name}: a rebound rule belongs to a ball")
        return self


class RealWorldSet(Model):
    """The whole validation set."""

    version: int = Field(ge=1)
    objects: list[RealWorldObject]

    @model_validator(mode="after")
    def _unique(self) -> RealWorldSet:
        """Object names are unique."""
        names = [o.name for o in self.objects]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"duplicate object names: {', '.join(dup)}")
        return self


def load_realworld(path: Path = REALWORLD_YAML) -> RealWorldSet:
    """The validation set from its YAML file."""
    return RealWorldSet.model_validate(load_yaml(Path(path).read_text(encoding="utf-8")))


# -- the report ------------------------------------------------------------------------------------------------------
Quantity = Literal["mass_kg", "youngs_modulus_pa", "squeeze_modulus_pa", "rebound_ratio"]


class Comparison(Model):
    """One measured quantity beside ours."""

    quantity: Quantity
    measured: ValueRange
    ours: float | None = Field(description="our figure (None: not produced, e.g. the build failed)")
    ratio: float | None = Field(default=None, description="ours / the nearest end of the measured range (1 inside "
                                "it); log-scale quantities only")
    passed: bool | None = Field(description="the criterion holds (None: nothing to judge)")
    criterion: str = Field(description="what passing means, e.g. 'within 2x of the range'")


class OurFigures(Model):
    """What DeformSmith built for one object (L0-L2 draft and, for a regulation ball, the rule's drop)."""

    concept: str | None = None
    material_class: str | None = None
    mass_kg: float | None = None
    density_kg_per_m3: float | None = None
    youngs_modulus_pa: float | None = None
    poisson_ratio: float | None = None
    damping_rate_per_s: float | None = None
    viscosity_pa_s: float | None = Field(default=None, description="L2's Kelvin-Voigt viscosity: the loss in the "
                                         "material a rule drop's impact takes [Pa s]")
    effective_modulus_pa: float | None = Field(default=None, description="L2's specimen compression (the material)")
    object_effective_modulus_pa: float | None = Field(default=None, description="L2's compression of the object")
    impact_speed_m_per_s: float | None = Field(default=None, description="rule drop: speed at impact after the fall "
                                               "under the material's damping (the engine's) [m/s]")
    restitution: float | None = Field(default=None, description="rule drop: COM speed out / in at the ground [-]")
    rebound_ratio_vacuum: float | None = Field(default=None, description="rule drop: restitution^2 [-]")
    rebound_ratio: float | None = Field(default=None, description="rule drop as the asset does it in our engine: "
                                        "rise / drop height, fall and rise under the material's damping [-]")
    rebound_ratio_air: float | None = Field(default=None, description="rule drop: the impact's restitution with a "
                                            "fall and rise through air instead (what the material alone gives) [-]")
    rebound_sim: dict[str, float] = Field(default_factory=dict, description="the impact probe's raw figures")


class ObjectReport(Model):
    """One object of the report."""

    name: str
    kind: ObjectKind
    expected_concept: str
    status: Literal["ok", "failed"]
    error: str | None = None
    ours: OurFigures
    comparisons: list[Comparison]
    wall_s: float


class ReportSummary(Model):
    """The set's headline figures."""

    objects: int
    built: int
    concept_matches: int
    modulus_measured: int
    modulus_within_2x: int
    mass_measured: int
    mass_within_2x: int
    rule_balls: int
    rebound_in_band: int


class RealWorldReport(Model):
    """`deformsmith bench realworld --json`."""

    device: str
    quality: str
    simulated: bool = Field(description="False with --no-sim: L0-L1 and the priors only, no MPM")
    summary: ReportSummary
    objects: list[ObjectReport]
