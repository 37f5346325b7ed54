"""Seconds per MPM step of reading the finger pads from a planned trajectory (tasks.robot.trajectory): the L3 trial
asks ``Trajectory.finger_pads(t)`` (one time) or ``pads_at(times)`` (many) every control step, and both are meant to
be lookups in the dense table ``plan_trajectory`` fills with pybullet's forward kinematics once, not kinematics per
step. (Was a timed unit test, tests/robot/test_robot_trajectory.py; the test now counts the pybullet calls instead.)

    python -m benchmarks.pads_bench [--steps 2000] [--dt 3.1e-3] [--repeats 5] [--json]

With --json it prints the figures (run()): the planning time (pybullet FK filling the table), the table's samples,
per call of finger_pads and of pads_at (one time and a batch of --batch times) the median wall and CPU seconds over
the repeats, the pybullet calls made while reading, and the 1-minute load average before and after (a shared CPU's
timings vary with what else runs); else a table.
"""

from __future__ import annotations

import os
import platform
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import typer
from rich.table import Table

from contracts.robot import ActionPlan, GraspCandidate
from flows.cli.apps import console, emit_json, results
from tasks.quiet_pybullet import pybullet as pb
from tasks.robot.trajectory import plan_trajectory


def standard_plan() -> ActionPlan:
    """The plan of tests/robot/test_robot_trajectory.py: a 5 cm wide grasp at the origin, placed at (0.12, 0.15) m
    after a 30 degree yaw, 4 mm squeeze."""
    grasp = GraspCandidate(center_m=(0.0, 0.0, 0.03), closing_axis=(1.0, 0.0, 0.0), approach_axis=(0.0, 0.0, -1.0),
                           width_m=0.05, friction_cone_ok=True, score=0.0, rank=0)
    return ActionPlan(grasp=grasp, squeeze_depth_m=0.004, target_xy_m=(0.12, 0.15), initial_yaw_deg=30.0)


def _pybullet_calls() -> tuple[list[str], Callable[[], None]]:
    """Count every public pybullet function called from now on: (the calls' names, a function that undoes it)."""
    calls: list[str] = []
    saved: dict[str, Any] = {}
    for name in dir(pb):
        fn = getattr(pb, name)
        if name.startswith("_") or not callable(fn) or isinstance(fn, type):
            continue
        saved[name] = fn

        def counted(*args: Any, _name: str = name, _fn: Any = fn, **kwargs: Any) -> Any:
            calls.append(_name)
            return _fn(*args, **kwargs)

        setattr(pb, name, counted)

    def undo() -> None:
        for name, fn in saved.items():
            setattr(pb, name, fn)

    return calls, undo


def _per_call(fn: Callable[[int], object], calls: int, repeats: int) -> dict[str, float]:
    """Median (and min) wall and CPU seconds per call of fn(k), k = 0 .. calls - 1, over `repeats` loops."""
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        for k in range(calls):
            fn(k)
        wall.append((time.perf_counter() - t0) / calls)
        cpu.append((time.process_time() - c0) / calls)
    return {"wall_s": statistics.median(wall), "wall_min_s": min(wall), "cpu_s": statistics.median(cpu)}


def run(steps: int = 2000, dt_s: float = 3.1e-3, repeats: int = 5, batch: int = 64) -> dict[str, Any]:
    """The figures as a JSON-ready dict."""
    out: dict[str, Any] = {"cpu_model": platform.processor() or platform.machine(), "cpu_count": os.cpu_count(),
                           "loadavg_1min_before": round(os.getloadavg()[0], 2), "steps": steps, "dt_s": dt_s,
                           "repeats": repeats}
    t0 = time.perf_counter()
    traj = plan_trajectory(standard_plan(), object_height_m=0.06)
    out["plan_s"] = round(time.perf_counter() - t0, 4)
    out["table_samples"] = len(traj.joint_table()["t"])
    out["duration_s"] = traj.duration_s
    times = np.arange(steps) * dt_s
    batches = [times[i:i + batch] for i in range(0, steps, batch)]
    calls, undo = _pybullet_calls()
    try:
        out["finger_pads"] = _per_call(lambda k: traj.finger_pads(float(times[k])), steps, repeats)
        out["pads_at_one"] = _per_call(lambda k: traj.pads_at(times[k:k + 1]), steps, repeats)
        per_batch = _per_call(lambda k: traj.pads_at(batches[k]), len(batches), repeats)
        out["pads_at_batch"] = {**per_batch, "batch": batch,
                                "wall_per_time_s": per_batch["wall_s"] * len(batches) / steps,
                                "cpu_per_time_s": per_batch["cpu_s"] * len(batches) / steps}
    finally:
        undo()
    out["pybullet_calls_while_reading"] = len(calls)
    out["loadavg_1min_after"] = round(os.getloadavg()[0], 2)
    return out


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
def bench_pads(
    steps: int = typer.Option(2000, "--steps", min=1, help="control steps read per timed loop"),
    dt: float = typer.Option(3.1e-3, "--dt", min=1e-6, help="time between steps [s]"),
    repeats: int = typer.Option(5, "--repeats", min=1, help="timed loops (median reported)"),
    batch: int = typer.Option(64, "--batch", min=1, help="times per pads_at call in the batched figure"),
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
) -> None:
    """Seconds per step of reading the finger pads from a planned trajectory (finger_pads, pads_at)."""
    with console.status("timing the finger-pad lookups ..."):
        data = run(steps, dt, repeats, batch)
    if as_json:
        emit_json(data)
        return
    table = Table(title=f"finger pads per step ({data['table_samples']} table samples, planned in "
                        f"{data['plan_s']:.2f} s; pybullet calls while reading: {data['pybullet_calls_while_reading']})")
    table.add_column("call")
    table.add_column("wall per step", justify="right")
    table.add_column("CPU per step", justify="right")
    for key in ("finger_pads", "pads_at_one", "pads_at_batch"):
        res = data[key]
        wall, cpu = res.get("wall_per_time_s", res["wall_s"]), res.get("cpu_per_time_s", res["cpu_s"])
        table.add_row(key, f"{wall * 1e6:.1f} us", f"{cpu * 1e6:.1f} us")
    results.print(table)


if __name__ == "__main__":
    app()
