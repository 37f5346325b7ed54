"""What an export records of a pressurised shell's modulus (issue #39): the wall's homogenised modulus, the rubber's E
plus the modulus its inflation gas adds (Material.gas_modulus_pa, fixed by L2 from tasks.realworld.inflation), with
the pressure and its source from material.json's `inflation` record."""

from __future__ import annotations

from contracts.export import HomogenisedWall
from contracts.material import Material

EXPORT_NOTE = ("youngs_modulus_pa is a pressurised shell's homogenised wall modulus: the rubber's E plus the modulus "
               "its inflation gas adds (2 pi R p through Reissner's point-load stiffness of a thin shell), what "
               "DeformSmith simulates the shell's wall at; a homogenised equivalent of the gas, not a gas simulation")


def homogenised_wall(material: Material, inflation: dict[str, float | str] | None) -> HomogenisedWall | None:
    """What an export records of a pressurised shell's modulus (contracts.export.HomogenisedWall: the rubber's E, the
    gas's modulus, their sum, the pressure and its source from material.json's `inflation`); None when the material
    has no gas (a solid, an unpressurised shell: exported as before)."""
    if material.gas_modulus_pa == 0.0:
        return None
    infl = inflation or {}
    pressure, source = infl.get("gauge_pressure_pa"), infl.get("source")
    return HomogenisedWall(rubber_youngs_modulus_pa=material.youngs_modulus_pa, gas_modulus_pa=material.gas_modulus_pa,
                           wall_modulus_pa=material.wall_modulus_pa,
                           gauge_pressure_pa=float(pressure) if pressure is not None else None,
                           gauge_pressure_source=str(source) if source is not None else None, note=EXPORT_NOTE)


__all__ = ["EXPORT_NOTE", "homogenised_wall"]
