"""L1 physical model: particle masses from volumes and a density prior, friction, plausibility."""

from tasks.physical.model import MASS_RANGE_KG, build_physical_model, mass_plausible, particle_masses

__all__ = ["MASS_RANGE_KG", "build_physical_model", "mass_plausible", "particle_masses"]
