"""Cross-simulator check on a sponge, a rubber ball and a plush toy: per simulator and metric, DeformSmith's MPM
value, the simulator's before calibration and after (flows.crosscheck).

    python -m benchmarks.crosscheck_bench [ASSET_DIR ...] [--sims mujoco,genesis,drake] [--out docs/crosscheck.json]

Without asset directories it uses $DEFORMSMITH_CROSSCHECK_ASSETS (a colon-separated list). Each asset is copied to
a temporary directory first (the export and calibration are written there, never into the asset). Prints JSON: one
row per (asset, simulator, metric), each simulator's calibrated parameters and residuals, whether the calibrated
effective modulus and rebound agree within 15 %, the simulations and wall time, and the load average (a shared CPU's
timings vary). (It was also `deformsmith bench crosscheck --json` before #37.)
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from contracts.errors import InputError, SimulationError
from flows.crosscheck import crosscheck_asset

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

ASSETS_ENV = "DEFORMSMITH_CROSSCHECK_ASSETS"


def run(assets: list[Path] | None, sims: list[str], out: Path | None = None) -> dict[str, Any]:
    """Crosscheck every asset in every simulator (with calibration); the figures as a JSON-ready dict."""
    if not assets:
        env = os.environ.get(ASSETS_ENV, "")
        assets = [Path(p) for p in env.split(":") if p]
    if not assets:
        raise InputError(f"bench crosscheck needs asset directories (arguments or ${ASSETS_ENV})")
    load0 = os.getloadavg()[0]
    rows: list[dict[str, Any]] = []
    reports: dict[str, dict[str, Any]] = {}
    t0 = time.perf_counter()
    for asset in assets:
        if not (Path(asset) / "material.json").is_file():
            raise InputError(f"{asset} is not an asset directory with material.json")
        with tempfile.TemporaryDirectory(prefix="crosscheck-") as tmp:
            work = Path(tmp) / Path(asset).name
            shutil.copytree(asset, work, ignore=shutil.ignore_patterns("export", "recordings", "renders"))
            for sim in sims:
                name = Path(asset).name
                try:
                    report = crosscheck_asset(work, sim, calibrate=True)
                except SimulationError as exc:  # one simulator failing on one asset is a result, not the end
                    reports[f"{name}/{sim}"] = {"agrees": False, "error": str(exc)}
                    continue
                reports[f"{name}/{sim}"] = {
                    "agrees": report.agrees, "sim_calls": report.sim_calls, "wall_time_s": report.wall_time_s,
                    "parameters_before": report.parameters,
                    "parameters_after": (report.calibration or {}).get("parameters"),
                    "residuals_after": (report.calibration or {}).get("residuals"),
                    "probes": report.probes, "notes": report.notes}
                for metric, row in report.metrics.items():
                    rows.append({"asset": name, "sim": sim, "metric": metric, **row.model_dump()})
    data = {"rows": rows, "runs": reports, "agree_within": 0.15, "wall_time_s": time.perf_counter() - t0,
            "load_average_1min": [load0, os.getloadavg()[0]],
            "all_agree": all(r["agrees"] for r in reports.values())}
    if out is not None:
        Path(out).write_text(json.dumps(data, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return data


def main() -> None:
    """Parse the options, run the benchmark, print JSON."""
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("assets", nargs="*", type=Path)
    ap.add_argument("--sims", default="mujoco")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args()
    print(json.dumps(run(a.assets, a.sims.split(","), a.out), indent=2, sort_keys=True))


if __name__ == "__main__":
    main()
