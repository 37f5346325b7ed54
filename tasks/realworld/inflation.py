"""A pressurised hollow ball as a homogenised wall (issue #39, session 33): the inflation gas's contact stiffness
against a flat, expressed as a modulus added to the wall's rubber, so that the MPM shell (one neo-Hookean material, no
gas) is as stiff against the floor as the rubber shell and its gas together. Not a gas simulation.

The gas: a membrane at gauge pressure p pressed by a flat over a depth d has a contact disc of radius a, a^2 ~ 2 R d,
on which p pushes back: F = p pi a^2 = 2 pi R p d, a contact stiffness k_gas = 2 pi R p. The wall: a thin spherical
shell under a point load (Reissner) has k_shell = 4 E t^2 / (R sqrt(3 (1 - nu^2))). The wall modulus that gives the
shell both is E_wall = E_rubber + dE_gas, dE_gas = k_gas R sqrt(3 (1 - nu^2)) / (4 t^2).

Left out, and why: the gas's adiabatic volume stiffness (the contact cap's volume pi R d^2 raises the pressure by
gamma p_abs dV / V, a force cubic in d). It is nothing at the small deflections of L2's compression and L3's grasps
and ~20 % of k_gas at a rule drop's deepest deflection (adiabatic_secant_stiffness_n_per_m gives its size); a linear
material cannot carry a deflection-dependent term, so the linear one alone is adopted.
"""

from __future__ import annotations

import math

from contracts.asset_dir import ParticleBody

AMBIENT_PA = 101_325.0  # standard atmosphere: a gauge pressure is over this
GAS_GAMMA = 1.4  # air / nitrogen, adiabatic (an impact's few milliseconds leave no time to exchange heat)
MODEL = ("homogenised equivalent, not a gas simulation: the inflation's contact stiffness against a flat (2 pi R p) "
         "added to the wall's rubber as a modulus through the Reissner point-load stiffness of a thin shell, "
         "4 E t^2 / (R sqrt(3 (1 - nu^2))); the gas's adiabatic volume stiffness is left out")


def gas_contact_stiffness_n_per_m(radius_m: float, gauge_pa: float) -> float:
    """Contact stiffness of a membrane at gauge pressure pressed by a flat, 2 pi R p [N/m]."""
    return 2.0 * math.pi * radius_m * gauge_pa


def shell_point_stiffness_n_per_m(youngs_modulus_pa: float, wall_m: float, radius_m: float,
                                  poisson_ratio: float) -> float:
    """Reissner's point-load stiffness of a thin spherical shell, 4 E t^2 / (R sqrt(3 (1 - nu^2))) [N/m]."""
    return 4.0 * youngs_modulus_pa * wall_m ** 2 / (radius_m * math.sqrt(3.0 * (1.0 - poisson_ratio ** 2)))


def gas_wall_modulus_pa(radius_m: float, wall_m: float, gauge_pa: float, poisson_ratio: float) -> float:
    """The modulus the inflation adds to a shell's wall: the E whose Reissner stiffness is k_gas,
    2 pi R p R sqrt(3 (1 - nu^2)) / (4 t^2) [Pa]."""
    k_gas = gas_contact_stiffness_n_per_m(radius_m, gauge_pa)
    return k_gas * radius_m * math.sqrt(3.0 * (1.0 - poisson_ratio ** 2)) / (4.0 * wall_m ** 2)


def adiabatic_secant_stiffness_n_per_m(radius_m: float, wall_m: float, gauge_pa: float, deflection_m: float) -> float:
    """The secant stiffness the gas's adiabatic compression adds at a flat's deflection d (the same work as its force
    2 pi^2 R^2 gamma p_abs d^3 / V): pi^2 R^2 gamma p_abs d^2 / V, V the gas's volume (inner radius R - t) [N/m]."""
    volume = 4.0 / 3.0 * math.pi * (radius_m - wall_m) ** 3
    return math.pi ** 2 * radius_m ** 2 * GAS_GAMMA * (AMBIENT_PA + gauge_pa) * deflection_m ** 2 / volume


def sphere_radius_m(volume_m3: float) -> float:
    """Radius of the sphere of this volume [m]."""
    return (3.0 * volume_m3 / (4.0 * math.pi)) ** (1.0 / 3.0)


def shell_inflation(body: ParticleBody | None, poisson_ratio: float) -> dict[str, float | str] | None:
    """The inflation record of an asset whose particles are a pressurised ball's shell (geometry.json `particles`
    with a gauge pressure): the pressure and its source, the radius (of the enclosed volume's sphere) and wall, the
    gas's contact stiffness and the wall modulus it adds at this Poisson ratio; None for anything else (a solid, an
    unpressurised shell)."""
    if body is None or not body.shell or body.gauge_pressure_pa is None or body.wall_m is None:
        return None
    radius = sphere_radius_m(body.enclosed_volume_m3)
    return {"gauge_pressure_pa": body.gauge_pressure_pa, "source": str(body.gauge_pressure_source),
            "radius_m": radius, "wall_m": body.wall_m, "poisson_ratio": poisson_ratio,
            "gas_contact_stiffness_n_per_m": gas_contact_stiffness_n_per_m(radius, body.gauge_pressure_pa),
            "gas_modulus_pa": gas_wall_modulus_pa(radius, body.wall_m, body.gauge_pressure_pa, poisson_ratio),
            "model": MODEL}
