"""Shape-program language: primitives with transforms, colours and smooth union (metres)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from contracts.base import Model

Vec3 = tuple[float, float, float]
RGB = tuple[float, float, float]


class Ellipsoid(Model):
    """Ellipsoid with semi-axes along local x, y, z."""

    kind: Literal["ellipsoid"] = "ellipsoid"
    radii_m: Vec3 = Field(description="semi-axes [m]")


class Superellipsoid(Model):
    """Superellipsoid |x/a|^(2/e2) ... ; e = 1 is an ellipsoid, e -> 0 a box, e = 2 an octahedron."""

    kind: Literal["superellipsoid"] = "superellipsoid"
    radii_m: Vec3 = Field(description="semi-axes [m]")
    exponent_ns: float = Field(default=0.5, gt=0.05, le=2.0, description="north-south (z) roundness exponent e1 [-]")
    exponent_ew: float = Field(default=0.5, gt=0.05, le=2.0, description="east-west (x-y) roundness exponent e2 [-]")


class Capsule(Model):
    """Capsule: segment along local z of the given length, swept by a sphere."""

    kind: Literal["capsule"] = "capsule"
    radius_m: float = Field(gt=0, description="radius [m]")
    length_m: float = Field(ge=0, description="length of the straight segment between the cap centres [m]")


class RoundedBox(Model):
    """Box with rounded edges; size is the full outer extent."""

    kind: Literal["rounded_box"] = "rounded_box"
    size_m: Vec3 = Field(description="full outer extents along x, y, z [m]")
    edge_radius_m: float = Field(default=0.0, ge=0, description="edge rounding radius [m]")


class Cylinder(Model):
    """Cylinder along local z, optionally with rounded rims."""

    kind: Literal["cylinder"] = "cylinder"
    radius_m: float = Field(gt=0, description="radius [m]")
    height_m: float = Field(gt=0, description="full height along z [m]")
    edge_radius_m: float = Field(default=0.0, ge=0, description="rim rounding radius [m]")


class Torus(Model):
    """Torus in the local x-y plane."""

    kind: Literal["torus"] = "torus"
    major_radius_m: float = Field(gt=0, description="distance from the centre to the tube centre [m]")
    minor_radius_m: float = Field(gt=0, description="tube radius [m]")


class Cone(Model):
    """Capped (frustum) cone along local z, rounded by edge_radius."""

    kind: Literal["cone"] = "cone"
    radius_bottom_m: float = Field(ge=0, description="radius at z = -height/2 [m]")
    radius_top_m: float = Field(ge=0, description="radius at z = +height/2 [m]")
    height_m: float = Field(gt=0, description="height [m]")
    edge_radius_m: float = Field(default=0.0, ge=0, description="rounding radius [m]")


Primitive = Annotated[
    Ellipsoid | Superellipsoid | Capsule | RoundedBox | Cylinder | Torus | Cone, Field(discriminator="kind")
]


class Transform(Model):
    """Rigid placement of a part: rotate (XYZ Euler, degrees) about the part's origin, then translate."""

    translation_m: Vec3 = Field(default=(0.0, 0.0, 0.0), description="translation [m]")
    rotation_deg: Vec3 = Field(default=(0.0, 0.0, 0.0), description="XYZ Euler angles [deg]")
    scale: Vec3 = Field(default=(1.0, 1.0, 1.0), description="non-uniform scale applied before rotation [-]")


class Part(Model):
    """One primitive of a program, combined with what came before it."""

    name: str = Field(default="part", description="what the part is, e.g. 'shell', 'head', 'left ear'")
    primitive: Primitive
    transform: Transform = Field(default_factory=Transform)
    color_rgb: RGB = Field(default=(0.8, 0.8, 0.8), description="linear RGB in [0, 1]")
    operation: Literal["union", "subtract", "intersect"] = Field(default="union")
    blend_m: float = Field(default=0.0, ge=0, description="smooth-union blend radius with the parts before [m]")


MAX_PARTS = 64  # parts in one ShapeProgram
MAX_PRINT_CHARS = 32  # characters of one printed line pair (a pack's product name)


class Print(Model):
    """Words printed on a part's outer face, as a pack's label carries its product's name (colour only: no relief)."""

    text: str = Field(min_length=1, max_length=MAX_PRINT_CHARS, pattern=r"^[A-Z0-9 &'.,-]+$",
                      description="the words, upper case (one or two lines, split at a space)")
    part: str = Field(default="label", description="name of the part whose outer face carries the print")
    color_rgb: RGB | None = Field(default=None, description="ink, linear RGB in [0, 1]; None: black or white, "
                                                            "whichever stands out on the part's colour")


class ShapeProgram(Model):
    """A watertight shape: parts combined in order (smooth union / subtract / intersect) as signed distances."""

    name: str = Field(description="object name, e.g. 'plush turtle'")
    category: str = Field(description="catalogue category the program came from, e.g. 'plush_animal'")
    parts: list[Part] = Field(min_length=1, max_length=MAX_PARTS)
    target_extent_m: Vec3 | None = Field(
        default=None, description="if given, the mesh is scaled to this bounding box (x, y, z) [m]"
    )
    prints: list[Print] = Field(default_factory=list, max_length=2, description="words printed on parts' faces")
