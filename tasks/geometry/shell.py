"""A hollow object's wall on its built surface (issue #39): the volume of the shell of thickness t inside a closed
surface, and the wall thickness whose shell weighs a hollow concept's typical mass.

The shell's volume is the enclosed volume less that of the inner parallel body (the points deeper than t), by
Steiner's formula: V_shell(t) = A t - M t^2 + (2 pi chi / 3) t^3, A the area, M the integrated mean curvature
(0.5 x the sum over edges of length x signed dihedral angle), chi the Euler characteristic (2 pi chi the integrated
Gauss curvature). For a sphere it is 4/3 pi (R^3 - (R - t)^3) (an icosphere of 6.8 cm with a 4 mm wall: within
0.1 %); exact for a smooth surface while t is under its smallest radius of curvature, an approximation at sharp
edges (a 10 x 5 x 2 cm box with a 5 mm wall: 5 % over); capped past the polynomial's first turning point and at the
enclosed volume.

Area x thickness, which the lexicon's walls were fitted with (wall = typical mass / (density x area)), over-states
a thick curved wall's volume by M t^2 (a 4 mm wall of a 6.8 cm ball: 12 %), so the walls L0 and L1 built weighed
less than the lexicon's mass (a tennis ball 52.9 g against 58 g). fitted_wall_m fits the wall to the typical mass on
the shell's true volume of the built surface scaled to the typical size instead.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import trimesh
from scipy.optimize import brentq

from contracts.concept import ConceptMatch

@dataclass(frozen=True)
class Surface:
    """What a shell's volume needs of a closed surface (SI units)."""

    area_m2: float
    volume_m3: float
    mean_curvature_m: float  # the integral of the mean curvature over the surface [m]
    euler: int  # the Euler characteristic (2 for a sphere-like surface)
    longest_m: float  # the longest side of its bounding box [m]

    @classmethod
    def of(cls, mesh: trimesh.Trimesh) -> Surface:
        """The measures of a closed mesh: M = 0.5 sum |e| theta_e over its edges, theta_e the angle between the two
        faces' normals, positive where convex, negative where concave."""
        edges = mesh.face_adjacency_edges
        lengths = np.linalg.norm(mesh.vertices[edges[:, 0]] - mesh.vertices[edges[:, 1]], axis=1)
        signed = np.where(mesh.face_adjacency_convex, 1.0, -1.0) * mesh.face_adjacency_angles
        return cls(area_m2=float(mesh.area), volume_m3=float(abs(mesh.volume)),
                   mean_curvature_m=0.5 * float(np.sum(lengths * signed)), euler=int(mesh.euler_number),
                   longest_m=float(np.max(mesh.extents)))

    def _poly(self, wall_m: float, scale: float) -> float:
        a, m = self.area_m2 * scale**2, self.mean_curvature_m * scale
        return a * wall_m - m * wall_m**2 + 2.0 * math.pi * self.euler / 3.0 * wall_m**3

    def reach_m(self, scale: float = 1.0) -> float:
        """The thickest wall the formula holds for on this surface scaled by `scale` [m]: the first t > 0 where the
        shell stops growing, dV/dt = A - 2 M t + 2 pi chi t^2 = 0 (a sphere's radius); inf when it never does."""
        a, m, c = self.area_m2 * scale**2, self.mean_curvature_m * scale, 2.0 * math.pi * self.euler
        if c:
            roots = [r.real for r in np.roots([c, -2.0 * m, a]) if abs(r.imag) <= 1e-9 * abs(r) and r.real > 0]
        else:
            roots = [a / (2.0 * m)] if m > 0 else []
        return min(roots) if roots else math.inf

    def shell_volume_m3(self, wall_m: float, scale: float = 1.0) -> float:
        """The volume within wall_m of this surface (scaled by `scale`), inside it [m^3]: Steiner's formula up to
        reach_m, the enclosed volume at most."""
        v = self.volume_m3 * scale**3
        t = min(wall_m, self.reach_m(scale))
        return float(min(max(self._poly(t, scale), 0.0), v))


def _root(f: Callable[[float], float], hi: float) -> float | None:
    """The root of an increasing f on [0, hi] (scipy's brentq; an infinite hi is searched for first by doubling),
    None when f(hi) < 0."""
    if not math.isfinite(hi):
        hi = 1e-6
        while f(hi) < 0 and hi < 1e3:
            hi *= 2.0
    if f(hi) < 0:
        return None
    return float(brentq(f, 0.0, hi, xtol=1e-15, rtol=1e-12))


def fitted_wall_m(surface: Surface, mass_kg: float, size_m: float, density_kg_per_m3: float) -> float | None:
    """The wall whose shell on this surface, scaled so that its longest extent is size_m, holds mass_kg at
    density_kg_per_m3 [m]; None when no wall the formula holds for is that heavy (the mass needs more than the
    shell can hold at that density)."""
    if not (mass_kg > 0 and size_m > 0 and density_kg_per_m3 > 0 and surface.longest_m > 0):
        return None
    scale = size_m / surface.longest_m
    target = mass_kg / density_kg_per_m3
    if target >= surface.volume_m3 * scale**3:  # not even the solid is that heavy
        return None
    wall = _root(lambda t: surface._poly(t, scale) - target, surface.reach_m(scale))
    return wall if wall is not None and wall > 0 else None


def concept_wall_m(concept: ConceptMatch | None, surface: Surface) -> float | None:
    """A hollow concept's wall on its built surface: fitted to its typical mass at its typical size and its wall's
    density (fitted_wall_m) when the lexicon gives all three and a wall; the lexicon's wall as it is for a one-layer
    sheet (weighed by half its area), without a typical mass, or when no wall fits; None for a solid concept or a
    hollow one with no wall."""
    if concept is None or not concept.hollow or concept.wall_thickness_m is None:
        return None
    if concept.sheet or concept.typical_mass_kg is None or concept.typical_size_m is None \
            or concept.density_kg_per_m3 is None:
        return concept.wall_thickness_m
    fitted = fitted_wall_m(surface, concept.typical_mass_kg, concept.typical_size_m, concept.density_kg_per_m3)
    return fitted if fitted is not None else concept.wall_thickness_m


__all__ = ["Surface", "concept_wall_m", "fitted_wall_m"]
