"""Cache fingerprints of the L3 trial task: the content keys a fixed small context gets for its first candidate,
under the nominal, robustness and held-out conditions.

The values were recorded before L3's context and record building moved from flows/ into tasks/manipulation/ (#37),
and recorded again when the trial task's version went to 13 (the `settled` label's turn rate, a longer settle, #36):
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
    "nominal": "259a1e39ac13eb5087ad52bf5e0eaa8b756e0159e5d2aad3a87334c28820e668",
    "robustness_0": "546549fc6db80c61a64d81b95474a184d2254c6b834332a026dc365e150feba2",
    "robustness_1": "89db566645a3bad7d53ad86db2d7c4a7fc825ba0bc85b0274848cea89b4e60e9",
    "held_out_0": "6b92a8385dee60d1cb827a80d4c0222e481417455aae186377ef00537239a253",
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
