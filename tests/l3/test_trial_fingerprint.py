"""Cache fingerprints of the L3 trial task: the content keys a fixed small context gets for its first candidate,
under the nominal, robustness and held-out conditions.

The values were recorded before L3's context and record building moved from flows/ into tasks/manipulation/ (#37):
a change of the trial task's name, version, input names or input values (the body, the plan, the settings, the
tolerances) would change them, and with them every cached trial of every user's assets. Nothing is simulated.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import flows.l3_manipulation as l3
from contracts.stage import load_contract
from flows.harness import probe_cache_key
from tests.l3.conftest import FIRM, Cube

KEYS = {
    "nominal": "be3279cbc0fb6959445611bd3fd18fa71e5661ec899ce86521779acbff6279ae",
    "robustness_0": "bdbb0dd4002d4de971a5d1a194606468089dd56d40c2b1abd71c6e7e93f5dc93",
    "robustness_1": "d9fff78860f6cdc610dbaf2e2e0b395ceeb1f041468ca24c8acd266f2c3a58fb",
    "held_out_0": "5d45e77918783adbeb5e2a99c5fa7795c44810bc7395e55ca109d09ca980814d",
}


def test_the_l3_trial_keys_of_a_fixed_context_are_unchanged(cube: Cube) -> None:
    from tasks.robot import select_grasps

    grasps = select_grasps(cube.body.surface_points_m, cube.body.surface_normals,
                           np.asarray(cube.physical.center_of_mass_m), cube.physical.gripper_friction).candidates[:3]
    options = l3.L3Options()
    ctx = l3.L3Context(asset_dir=Path("/nonexistent"), body=cube.body, physical=cube.physical,
                       material=FIRM, material_source="given", grasps=grasps, options=options,
                       contract=load_contract("L3"))
    values = l3.initial_values(ctx)
    conditions = {"nominal": (None, 0.0)} | {
        f"robustness_{i}": ((x, y), yaw) for i, (x, y, yaw) in enumerate(options.robustness)} | {
        f"held_out_{i}": ((x, y), yaw) for i, (x, y, yaw) in enumerate(options.held_out)}
    keys = {}
    for name, (target, yaw) in conditions.items():
        _, inputs = ctx._trial_inputs(values, None, target, yaw)
        keys[name] = probe_cache_key(l3.trial_task, inputs)
    assert keys == KEYS
