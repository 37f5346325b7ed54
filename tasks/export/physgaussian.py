"""export/physgaussian_config.json: a PhysGaussian-style simulation config next to the Gaussians, with the asset's
adopted material, L1's density and gravity and the particle file (SI)."""

from __future__ import annotations

import json
from pathlib import Path

from tasks.asset_dir import AssetDir
from tasks.export.wall import homogenised_wall

CONFIG = Path("export") / "physgaussian_config.json"  # in the asset directory


def write_physgaussian_export(adir: AssetDir) -> Path:
    """A PhysGaussian-style simulation config next to the Gaussians: the adopted material's E, nu (AssetDir.
    adopted_material), L1's density and the particle file (SI). A pressurised shell's E is its wall's homogenised
    modulus (the rubber's plus its gas's, what its particles are simulated at), recorded as such under
    `homogenised_wall` (absent otherwise)."""
    phys, mat = adir.physical_model(), adir.adopted_material().material
    # a pressurised shell: its particles are the wall, simulated at the wall's modulus (rubber + gas), and say so
    wall = homogenised_wall(mat, adir.material().inflation) if mat.gas_modulus_pa else None
    config = {
        "material": "jelly",  # PhysGaussian's name for its neo-Hookean model
        "E": mat.youngs_modulus_pa if wall is None else wall.wall_modulus_pa, "nu": mat.poisson_ratio,
        "density": phys.density_kg_per_m3,
        "damping_rate_per_s": mat.damping_rate_per_s,
        # Kelvin-Voigt viscosity [Pa s]: recorded, not applied (PhysGaussian's jelly has no viscous stress)
        "viscosity_pa_s": mat.viscosity_pa_s,
        "g": list(phys.gravity_m_per_s2), "friction_ground": phys.ground_friction,
        "gaussians_ply": "../gaussians.ply", "particles_zarr": "../particles.zarr",
        "units": "SI (Pa, kg/m^3, m, s); frame z up, object resting on z = 0",
        "particle_volumes": "particles.zarr/volumes_m3", "n_particles": phys.particle_count,
        **({"homogenised_wall": wall.model_dump(mode="json")} if wall is not None else {}),
    }
    path = adir.path / CONFIG
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(config, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return path
