"""The screening task's cache key on a fixed input, recorded before it moved from flows/l2_material.py to
tasks/probes/screening.py (#37): its name, version and inputs are unchanged, so every cached screening still hits.
Re-recorded at TASK_VERSION 3 (session 55: the screened compression mass-scales a stiff specimen)."""

from __future__ import annotations

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from flows.harness import probe_cache_key
from tasks.probes.screening import screen_task

KEY = "cbfee423b00e0ea7ee72a69cc4e3fbc1949db2a49ec4aa1acd1f300a65ad51f0"


def test_the_screening_task_key_is_unchanged() -> None:
    phys = PhysicalModel(density_kg_per_m3=300.0, volume_m3=2.7e-5, mass_kg=8.1e-3, particle_count=8,
                         particle_spacing_m=0.003, ground_friction=0.5, gripper_friction=0.8,
                         center_of_mass_m=(0.0, 0.0, 0.015), extents_m=(0.03, 0.03, 0.03), category="foam")
    kw = dict(positions_m=np.arange(24, dtype=float).reshape(8, 3), volumes_m3=np.ones(8), physical=phys,
              kind="specimen_compress",
              materials=[Material(youngs_modulus_pa=1e4, poisson_ratio=0.3, damping_rate_per_s=1.0)],
              params={"strain": 0.1}, sim=SimConfig(), schedule="batch")
    assert probe_cache_key(screen_task, kw) == KEY
