"""Small bodies and a stand-in L0 asset for fast L2 tests (SI units)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from contracts.physical import PhysicalModel
from tasks.mpm.scene import box_particles
from tasks.physical import build_physical_model
from tasks.probes.rollout import DeformableBody


def box_body(size_m: tuple[float, float, float], n_long: int, density: float = 100.0, ground_friction: float = 0.5,
             gripper_friction: float = 0.8) -> DeformableBody:
    """A box resting on z = 0, centred in x, y, with n_long particles along its longest side."""
    s = max(size_m) / n_long
    lo = (-size_m[0] / 2, -size_m[1] / 2, 0.0)
    hi = (size_m[0] / 2, size_m[1] / 2, size_m[2])
    pos, vol = box_particles(lo, hi, s)
    return DeformableBody(pos, vol, s, density, ground_friction, gripper_friction)


def box_asset(size_m: tuple[float, float, float], n_long: int, density: float = 100.0) -> tuple[SimpleNamespace, PhysicalModel]:
    """What flows.l2_material reads of an L0 asset (particles, volumes, spacing, record) and an L1 model."""
    b = box_body(size_m, n_long, density)
    asset = SimpleNamespace(particles_m=b.positions_m, volumes_m3=b.volumes_m3, spacing_m=b.spacing_m,
                            record={"info": {"name": "box", "category": "box"}})
    phys = build_physical_model(b.positions_m, b.volumes_m3, b.spacing_m, density, 0.5, 0.8, "box")
    return asset, phys


__all__ = ["box_asset", "box_body", "np"]
