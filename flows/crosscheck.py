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

from pydantic import ValidationError

from contracts.export import ExportManifest
from flows.export import MANIFEST, export_asset
from tasks.export.calibrate import Calibration, fit_both, rel
from tasks.export.crosscheck import (
    AGREEMENT_TOLERANCE, CALIBRATED_METRICS, CrosscheckReport, metric_rows, probe_targets, slice_area_m2,
)
from tasks.export.inputs import load_export_inputs
from tasks.export.sim_runners import SIMULATORS, require_simulator, sim_runner
from tasks.publish import write_text_atomic

REPORT = "crosscheck.json"
CALIBRATION = "calibration.json"


def _probe_metrics(c: dict[str, float], d: dict[str, float]) -> dict[str, float]:
    return {**{k: float(v) for k, v in d.items()}, **{k: float(v) for k, v in c.items()}}


def _export_folder(asset_dir: Path, sim: str, export_root: Path | None) -> tuple[Path, Path]:
    """(export root, the simulator's folder), exporting first when it is missing."""
    root = Path(export_root) if export_root is not None else asset_dir / "export"
    if not (root / sim).is_dir():
        export_asset(asset_dir, [sim], root)
    return root, root / sim


def _record_calibration(root: Path, sim: str, calibrated: dict) -> None:
    """manifest.json: the simulator's TargetManifest.calibrated (left alone when there is no manifest)."""
    path = root / MANIFEST
    try:
        manifest = ExportManifest.model_validate_json(path.read_text(encoding="utf-8"))
    except (OSError, ValidationError):
        return
    if sim in manifest.targets:
        t = manifest.targets[sim]
        files = list(dict.fromkeys([*t.files, *calibrated.get("files", [])]))
        manifest.targets[sim] = t.model_copy(update={"calibrated": calibrated, "files": files})
        write_text_atomic(path, manifest.model_dump_json(indent=2) + "\n")


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
    calls = 0
    values = dict(runner.initial)
    before = _probe_metrics(runner.compress(values) if runner.compress else {}, runner.drop(values))
    calls += 2 if runner.compress else 1
    ours = targets.ours
    after: dict[str, float] | None = None
    calibration: Calibration | None = None
    if calibrate and (runner.compress is None or runner.knobs is None):
        notes.append("no calibration: not supported")
    elif calibrate and runner.compress is not None and runner.knobs is not None:
        # every probe run once per parameter set: the fits re-read what they measured (fit_both's rounds)
        probes = {"compress": runner.compress, "drop": runner.drop}
        runs: dict[tuple, dict[str, float]] = {(kind, *sorted(values.items())): before for kind in probes}

        def probe(kind: str, v: dict[str, float]) -> dict[str, float]:
            key = (kind, *sorted(v.items()))
            if key not in runs:
                runs[key] = probes[kind](v)
            return runs[key]

        values, steps = fit_both(lambda v: float(probe("compress", v)["effective_modulus_pa"]),
                                 lambda v: float(probe("drop", v).get("rebound_ratio", 0.0)), runner.knobs, values,
                                 ours["effective_modulus_pa"], ours["rebound_ratio"])
        after = _probe_metrics(probe("compress", values), probe("drop", values))
        calls += len(runs) - len(probes)
        residuals = {m: rel(after[m], ours[m]) for m in CALIBRATED_METRICS if m in after}
        calibration = Calibration(
            sim=sim, parameters=values, initial=runner.initial, residuals=residuals,
            residuals_before={m: rel(before[m], ours[m]) for m in CALIBRATED_METRICS if m in before},
            probes=[f"compress (object, strain {targets.strain})",
                    f"drop (object, height fraction {targets.height_fraction})"],
            history=steps, sim_calls=len(runs) - len(probes),
            converged=all(abs(r) <= AGREEMENT_TOLERANCE for r in residuals.values()))
    rows = metric_rows(ours, before, after)
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
            _record_calibration(root, sim, entry)
    return report


__all__ = ["SIMULATORS", "crosscheck_asset"]
