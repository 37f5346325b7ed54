"""Does a grasp's outcome depend on the object's yaw? One plan at several yaws, in several simulation frames.

    python -m benchmarks.l3_yaw_sweep ASSET_DIR [--yaws 0,45,-75,30,-45,60,90,-20] [--frames none,0,45]
        [--spacing M] [--youngs PA] [--plan-from manipulation.json] [--conditions SUITE] [--workers 2] [--json]

ASSET_DIR is an L2 (or L3) asset directory; it is copied to a temporary folder first (never written into). The plan is
L3's first candidate, or the accepted values of a manipulation.json (``--plan-from``), placed at (0.08, 0.06) m, or at each held-out condition (target and yaw) of an evaluation suite
(``--conditions manipulation``: contracts/suites/manipulation.yaml). A frame
is ``none`` (the world frame: the grasp meets the grid at an angle set by the yaw) or the closing axis' angle to the
grid's x axis in degrees (``TrialSettings.closing_axis_to_grid_deg``). Prints one line per trial and, per frame, how
many yaws lifted and the hold force per finger; ``--json`` prints the whole result as JSON.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path
from typing import Any

from contracts.stage import load_contract
from flows.l3_manipulation import L3Options, initial_values, load_context
from tasks.evaluation.suite import load_suite
from tasks.manipulation.context import tolerances_from
from tasks.manipulation.trial import plan_or_error, run_trial

TARGET_XY_M = (0.08, 0.06)


def _frame(text: str) -> float | None:
    return None if text.strip().lower() == "none" else float(text)


def one_trial(asset_dir: str, yaw_deg: float, frame: float | None, spacing_m: float | None, youngs_pa: float | None,
              values: dict[str, float] | None, target_xy_m: tuple[float, float] = TARGET_XY_M) -> dict[str, Any]:
    """One trial of the plan at a yaw in a frame: the lift labels and the hold force."""
    ctx = load_context(Path(asset_dir), L3Options(particle_spacing_m=spacing_m), load_contract("L3"))
    material = ctx.material if youngs_pa is None else ctx.material.model_copy(update={"youngs_modulus_pa": youngs_pa})
    plan = ctx.plan(values or initial_values(ctx), target_xy_m, yaw_deg)
    settings = replace(ctx.options.settings, closing_axis_to_grid_deg=frame)
    traj, why = plan_or_error(plan, ctx.body, settings)
    if traj is None:
        return {"yaw_deg": yaw_deg, "frame": frame, "error": why}
    t0 = time.perf_counter()
    r = run_trial(ctx.body, ctx.physical, material, plan, settings, tolerances_from(ctx.contract), traj)
    c = traj.closing_axis_world
    off = math.degrees(math.atan2(c[1], c[0])) % 90.0
    m = r.metrics
    return {"yaw_deg": yaw_deg, "frame": frame, "world_axis_to_grid_deg": round(min(off, 90.0 - off), 2),
            "lifted": bool(m["lifted"]), "success": all(m[k] == 1.0 for k in
                                                         ("lifted", "transported", "released_in_target", "settled")),
            "target_xy_m": list(target_xy_m), "released_in_target": bool(m["released_in_target"]),
            "settled": bool(m["settled"]), "place_error_m": m.get("place_error_m"),
            "release_rotation_deg": m.get("release_rotation_deg"), "object_rotation_deg": m.get("object_rotation_deg"),
            "modes": [k[5:] for k, v in m.items() if k.startswith("mode_") and v],
            "lift_rise_m": m.get("lift_rise_m"), "hold_normal_force_n": m.get("hold_normal_force_n"),
            "max_finger_force_n": m.get("max_finger_force_n"), "particles": len(ctx.body.particles_m),
            "youngs_modulus_pa": material.youngs_modulus_pa, "wall_s": time.perf_counter() - t0}


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Per frame: lifts of trials, and the hold force per finger (mean, min, max over the trials that lifted)."""
    out: dict[str, Any] = {}
    for frame in dict.fromkeys(r["frame"] for r in rows):
        rs = [r for r in rows if r["frame"] == frame and "error" not in r]
        f = [r["hold_normal_force_n"] for r in rs if r["lifted"] and r["hold_normal_force_n"] is not None
             and math.isfinite(r["hold_normal_force_n"])]
        out["none" if frame is None else f"{frame:g}"] = {
            "trials": len(rs), "lifted": sum(r["lifted"] for r in rs), "succeeded": sum(r["success"] for r in rs),
            "hold_normal_force_n": {"mean": sum(f) / len(f), "min": min(f), "max": max(f)} if f else None}
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.l3_yaw_sweep", description=__doc__.split("\n")[0])
    ap.add_argument("asset_dir")
    ap.add_argument("--yaws", default="0,45,-75,30,-45,60,90,-20", help="initial yaws [deg], comma-separated")
    ap.add_argument("--frames", default="none,45", help="'none' or closing-axis-to-grid angles [deg], comma-separated")
    ap.add_argument("--spacing", type=float, default=None, help="trial particle spacing [m] (default: L3's draft)")
    ap.add_argument("--youngs", type=float, default=None, help="Young's modulus [Pa] instead of the asset's")
    ap.add_argument("--plan-from", default=None, help="a manipulation.json whose accepted values make the plan")
    ap.add_argument("--conditions", default=None,
                    help="an evaluation suite whose held-out conditions (target, yaw) replace --yaws")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    src = Path(a.asset_dir)
    if not (src / "material.json").is_file():
        print(f"error: {src} is not an L2 asset directory (no material.json)", file=sys.stderr)
        return 2
    try:
        yaws = [float(y) for y in a.yaws.split(",")]
        frames = [_frame(f) for f in a.frames.split(",")]
    except ValueError as exc:
        print(f"error: --yaws and --frames take comma-separated numbers ('none' for a frame): {exc}", file=sys.stderr)
        return 2
    values = json.loads(Path(a.plan_from).read_text())["values"] if a.plan_from else None
    if a.conditions:
        suite, _ = load_suite(a.conditions, check_vocab=False)
        poses = [((float(c.target_xy_m[0]), float(c.target_xy_m[1])), float(c.initial_yaw_deg))
                 for c in suite.manipulation_conditions]
    else:
        poses = [(TARGET_XY_M, y) for y in yaws]
    with tempfile.TemporaryDirectory(prefix="yaw_sweep_") as tmp:
        work = Path(tmp) / "asset"
        shutil.copytree(src, work, ignore=shutil.ignore_patterns("interaction", "recordings", "renders"))
        jobs = [(str(work), y, f, a.spacing, a.youngs, values, xy) for f in frames for xy, y in poses]
        rows: list[dict[str, Any]] = []
        with ProcessPoolExecutor(max_workers=max(1, a.workers)) as pool:
            for r in pool.map(one_trial, *zip(*jobs)):
                rows.append(r)
                if not a.json:
                    print(json.dumps(r), flush=True)
    result = {"asset_dir": str(src), "target_xy_m": TARGET_XY_M, "spacing_m": a.spacing, "trials": rows,
              "summary": summarise(rows)}
    print(json.dumps(result if a.json else result["summary"], indent=2, default=str))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
