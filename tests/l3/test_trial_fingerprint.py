"""Cache fingerprints of the L3 trial task: the content keys a fixed small context gets for its first candidate,
under the nominal, robustness and held-out conditions.

The values were recorded before L3's context and record building moved from flows/ into tasks/manipulation/ (#37),
recorded again when the trial task's version went to 13 (the `settled` label's turn rate, a longer settle, #36), and
again when the trial settings gained the force-guarded place (place_support_fraction, place_guard_*, #36):
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
    "nominal": "cbd2fb4f90c8ca941cd6639c4eac95a048e1ea781cd8467d28b09af3ccf8e2af",
    "robustness_0": "82c63958e657d95a67feea5112bd1f59aabaec4247f33f7dc47bb891d7813d98",
    "robustness_1": "68f9802b6f0412a315c2ff382e1adb58c7cbad93d48ac2943074161e6be5adfd",
    "held_out_0": "c23d653d9d53bad9d349a1809106f5ae8be3be6376ae508c7359f3e1b602a7fa",
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
