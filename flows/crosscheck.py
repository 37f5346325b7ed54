"""Cross-simulator check of an exported asset: L2's object probes re-run in MuJoCo, Genesis or Drake, then calibration.

MuJoCo runs the compression and the drop and is calibrated (young, then its timestep where its integrator's numerical
dissipation leaves less rebound than L2's, then the flex damping; alternated until both hold). Genesis runs both on
the exported scene.py (tasks.export.genesis_probes) and is calibrated (young, then the velocity damping rate its
scene.py applies); the calibrated scene is scene_calibrated.py. Drake runs both on the exported SDFormat body
(tasks.export.drake_probes) and is calibrated like MuJoCo (young, its timestep, then its Rayleigh mass damping); the
calibrated body is <slug>_calibrated.sdf, the timestep to simulate it with in its comment and calibration.json.

    crosscheck_asset(asset_dir, "mujoco")  # -> CrosscheckReport; DIR/export/mujoco/{<slug>_calibrated.xml,
                                           #    calibration.json, crosscheck.json}, manifest.json's calibrated entry

The export is made first when DIR/export has none for the simulator (flows.export.export_asset). Before calibration
the simulator runs the exported parameters; calibration (tasks.export.calibrate) fits its Young's modulus to L2's
effective modulus, then its damping to L2's rebound, and the probes run once more with the fitted values ("after").
No Prefect flow: a handful of simulations in-process, like `deformsmith export`.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from flows.export import export_asset
from tasks.export.calibrate import Calibration
from tasks.export.crosscheck import (
    AGREEMENT_TOLERANCE, CALIBRATED_METRICS, CrosscheckReport, metric_rows, probe_targets, slice_area_m2,
)
from tasks.export.inputs import load_export_inputs
from tasks.export.manifest import record_calibration
from tasks.export.sim_runners import (
    SIMULATORS, calibrate as calibrate_runner, probe_metrics, require_simulator, sim_runner,
)
from tasks.publish import write_text_atomic

REPORT = "crosscheck.json"
CALIBRATION = "calibration.json"


def _export_folder(asset_dir: Path, sim: str, export_root: Path | None) -> tuple[Path, Path]:
    """(export root, the simulator's folder), exporting first when it is missing."""
    root = Path(export_root) if export_root is not None else asset_dir / "export"
    if not (root / sim).is_dir():
        export_asset(asset_dir, [sim], root)
    return root, root / sim


def crosscheck_asset(asset_dir: Path, sim: str = "mujoco", calibrate: bool = True, export_root: Path | None = None,
                     write: bool = True) -> CrosscheckReport:
    """Run L2's object compression and drop in `sim` on the exported asset, calibrate, and report beside L2's."""
    t_wall = time.perf_counter()
    asset_dir = Path(asset_dir)
    require_simulator(sim)
    targets = probe_targets(asset_dir)
    inputs = load_export_inputs(asset_dir)
    notes: list[str] = []
    area = targets.area_m2
    if area is None:
        z = inputs.tet.nodes_m[:, 2]
        area = slice_area_m2(inputs.tet.nodes_m, inputs.tet.tets, 0.5 * (z.min() + z.max()))
        notes.append("cross-section from the tet mesh (material.json records none)")
    root, folder = _export_folder(asset_dir, sim, export_root)
    runner = sim_runner(sim, inputs, targets, area, folder)
    values = dict(runner.initial)
    before = probe_metrics(runner.compress(values) if runner.compress else {}, runner.drop(values))
    calls = 2 if runner.compress else 1
    after: dict[str, float] | None = None
    calibration: Calibration | None = None
    if calibrate and (runner.compress is None or runner.knobs is None):
        notes.append("no calibration: not supported")
    elif calibrate:
        after, calibration = calibrate_runner(sim, runner, targets, before)
        calls += calibration.sim_calls
    rows = metric_rows(targets.ours, before, after)
    agrees = None
    if after is not None:
        errors = [rows[m].rel_error_calibrated for m in CALIBRATED_METRICS]
        agrees = all(e is not None and e <= AGREEMENT_TOLERANCE for e in errors)
    report = CrosscheckReport(asset=str(asset_dir), sim=sim,
                              probes={"strain": targets.strain, "height_fraction": targets.height_fraction,
                                      "area_m2": area},
                              metrics=rows, parameters=runner.initial,
                              calibration=calibration.model_dump() if calibration else None, agrees=agrees,
                              sim_calls=calls, wall_time_s=time.perf_counter() - t_wall, notes=notes)
    if write:
        write_text_atomic(folder / REPORT, report.model_dump_json(indent=2) + "\n")
        if calibration is not None and runner.write_calibrated is not None:
            files = runner.write_calibrated(calibration.parameters, folder)
            write_text_atomic(folder / CALIBRATION, calibration.model_dump_json(indent=2) + "\n")
            entry = {**json.loads(calibration.model_dump_json(exclude={"history"})),
                     "files": [f"{sim}/{f}" for f in (*files, CALIBRATION, REPORT)]}
            record_calibration(root, sim, entry)
    return report


__all__ = ["SIMULATORS", "crosscheck_asset"]
