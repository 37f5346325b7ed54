"""Wall time of one pick-and-place trial (issue #7 figures): particles, steps, simulated and wall seconds, labels.

Cases:
  turtle  an L0/L1/L2 asset directory (default: the eval case t01_plush_turtle, copied first: never written into),
          the first L3 candidate (``initial_values`` of ``load_context``) at draft (``L3Options()``) or standard
          (``L3Options.standard()``) quality
  cube    the 3 cm firm foam cube of tests/l3/conftest.py (box_body(0.03, 0.0025), E 100 kPa, rho 300, plan(0.004))

The trajectory is planned (pybullet IK, on the CPU) before the timed part; its time is reported apart
(``plan_wall_s``). ``trial_wall_s`` is the whole ``run_trial`` call with the trajectory given (MPM set-up, control
loop, recorded arrays, labels); ``wall_s`` is ``run_trial``'s own ``info['wall_time_s']``, which stops before the
arrays are assembled and the labels computed: at standard quality the labels (max_strain: an SVD of every particle's
F in every recorded frame, numpy on the CPU) take longer than the simulation on a GPU. A machine without pybullet
(the GPU machine) runs a bundle prepared here::

    python -m benchmarks.l3_trial cube --device cpu --json      # prepare + run here
    python -m benchmarks.l3_trial turtle --quality standard --export .benchtrial/turtle_std.pkl
    python -m benchmarks.l3_trial --bundle .benchtrial/turtle_std.pkl --device cuda --json

A bundle is a pickle of the trial inputs (body, physical model, material, plan, settings, tolerances and the planned
Trajectory); the trajectory's motion pieces (closures of tasks.robot.trajectory's factories) are stored as the
factory's name and arguments and rebuilt by calling it, so the bundle holds no bytecode and loads under another
Python version. Loading one where pybullet is missing (or with ``--no-pybullet``) puts a stand-in module in its place
that raises on any use, so a run that completes proves the trial touched no pybullet. ``--repeat N`` runs the trial
N times in one process: the first run includes Warp's kernel loading (and compilation when its kernel cache is cold).
``--full`` simulates the whole plan even after a failed lift. The 1-minute load average around each run is recorded
(a shared CPU makes CPU timings noisy).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib.util
import io
import json
import os
import pickle
import platform
import shutil
import subprocess
import sys
import tempfile
import time
import types
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan
from contracts.stage import load_contract
from flows.l3_manipulation import L3Options, initial_values, load_context
from tasks.manipulation.body import box_body
from tasks.manipulation.context import tolerances_from
from tasks.manipulation.outcome import TrialTolerances
from tasks.manipulation.trial import TrialSettings, plan_or_error, run_trial
from tasks.robot import select_grasps, trajectory

DEFAULT_TURTLE = Path("out/eval/cases/t01_plush_turtle/hierarchical")
LABELS = ("lifted", "transported", "released_in_target", "settled", "slipped", "force_budget_violated",
          "numerically_healthy", "stopped_after_failed_lift", "max_finger_force_n", "max_strain",
          "hold_friction_ratio")


class _NoPybullet(types.ModuleType):
    """Stand-in for pybullet / pybullet_data on a machine without them: importing works, any use raises."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise RuntimeError(f"{self.__name__}.{name} used, but pybullet is not installed here: plan on a machine "
                           "with pybullet and pass the trajectory (benchmarks.l3_trial --export / --bundle)")


def _stub_pybullet(force: bool = False) -> bool:
    """Install the stand-ins when pybullet is missing (or ``force``); True when they were installed."""
    if not force and importlib.util.find_spec("pybullet") is not None:
        return False
    for name in ("pybullet", "pybullet_data"):
        sys.modules.setdefault(name, _NoPybullet(name))
    return True


def _rebuild_piece(factory: str, args: tuple[Any, ...]) -> Any:
    """A trajectory motion piece, made again by its factory in tasks.robot.trajectory."""
    return getattr(trajectory, factory)(*args)


def _rebuild_ppoly(c: Any, x: Any, extrapolate: Any, axis: int) -> Any:
    """A piecewise polynomial (the trajectory's joint-path splines) from its breakpoints and coefficients."""
    from scipy.interpolate import PPoly

    return PPoly.construct_fast(c, x, extrapolate, axis)


class _BundlePickler(pickle.Pickler):
    """Pickles the trajectory's closures as (factory, arguments) and scipy splines as their coefficients (scipy's
    own pickles hold private, version-bound state); everything else as usual."""

    def reducer_override(self, obj: Any) -> Any:
        # the importable copies (this module may run as __main__)
        from benchmarks.l3_trial import _rebuild_piece, _rebuild_ppoly

        if type(obj).__module__.startswith("scipy.interpolate"):
            from scipy.interpolate import PPoly

            if isinstance(obj, PPoly):
                return _rebuild_ppoly, (np.asarray(obj.c), np.asarray(obj.x), obj.extrapolate, int(obj.axis))
        if isinstance(obj, types.FunctionType) and obj.__module__ == "tasks.robot.trajectory" \
                and ".<locals>." in obj.__qualname__:
            import inspect

            factory = obj.__qualname__.split(".<locals>.")[0]
            cells = dict(zip(obj.__code__.co_freevars, (c.cell_contents for c in obj.__closure__ or ())))
            params = list(inspect.signature(getattr(trajectory, factory)).parameters)
            missing = [p for p in params if p not in cells]
            if missing:
                raise pickle.PicklingError(f"{obj.__qualname__}: {missing} not in its closure")
            return _rebuild_piece, (factory, tuple(cells[p] for p in params))
        return NotImplemented


def dump_bundle(inputs: dict[str, Any]) -> bytes:
    """The prepared inputs as bytes (see the module docstring)."""
    buf = io.BytesIO()
    _BundlePickler(buf, protocol=pickle.HIGHEST_PROTOCOL).dump(inputs)
    return buf.getvalue()


_OLD_HOMES = {"tasks.manipulation.bench_trial": "benchmarks.l3_trial"}  # bundles exported before the move


class _BundleUnpickler(pickle.Unpickler):
    """Reads bundles, also those exported when this module was tasks.manipulation.bench_trial."""

    def find_class(self, module: str, name: str) -> Any:
        return super().find_class(_OLD_HOMES.get(module, module), name)


def load_bundle(data: bytes) -> dict[str, Any]:
    """The prepared inputs from ``dump_bundle``'s bytes."""
    return _BundleUnpickler(io.BytesIO(data)).load()


def cube_inputs(device: str = "cpu") -> dict[str, Any]:
    """The firm cube trial of tests/l3/conftest.py (``firm_trial``): inputs of ``run_trial`` without the trajectory."""
    import numpy as np

    edge, spacing, rho = 0.03, 0.0025, 300.0
    body = box_body(edge, spacing)
    phys = PhysicalModel(density_kg_per_m3=rho, volume_m3=body.volume_m3, mass_kg=rho * body.volume_m3,
                         particle_count=len(body.particles_m), particle_spacing_m=spacing, ground_friction=0.5,
                         gripper_friction=0.8, center_of_mass_m=(0.0, 0.0, edge / 2), extents_m=(edge,) * 3,
                         category="foam")
    firm = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)
    g = select_grasps(body.surface_points_m, body.surface_normals, np.asarray(phys.center_of_mass_m),
                      phys.gripper_friction).best()
    plan = ActionPlan(grasp=g, squeeze_depth_m=0.004, target_xy_m=(0.08, 0.06), lift_height_m=0.05,
                      closing_speed_m_per_s=0.04, closure_duration_s=0.3, lift_duration_s=0.4,
                      transport_duration_s=0.6, release_duration_s=0.2, retreat_duration_s=0.2, settle_duration_s=0.2)
    return {"case": "cube_3cm_firm", "quality": "tests/l3 firm_trial", "body": body, "physical": phys,
            "material": firm, "plan": plan, "settings": TrialSettings(device=device),
            "tolerances": TrialTolerances(lift_height_m=0.05), "source": "tests/l3/conftest.py firm_trial"}


def turtle_inputs(asset_dir: Path = DEFAULT_TURTLE, quality: str = "draft", device: str = "cpu") -> dict[str, Any]:
    """The first L3 candidate of an asset (a copy of ``asset_dir`` is read; the original is never written)."""
    options = L3Options() if quality == "draft" else L3Options.standard(device=device)
    options = replace(options, device=device, settings=replace(options.settings, device=device))
    contract = load_contract("L3")
    with tempfile.TemporaryDirectory(prefix="bench_trial_") as tmp:
        copy = Path(tmp) / "asset"
        shutil.copytree(asset_dir, copy)
        ctx = load_context(copy, options, contract)
    values = initial_values(ctx)
    plan = ctx.plan(values)
    settings = replace(options.settings, substeps=int(round(values.get("substeps", 1))), device=device)
    return {"case": f"{Path(asset_dir).parent.name or Path(asset_dir).name}", "quality": quality, "body": ctx.body,
            "physical": ctx.physical, "material": ctx.material, "plan": plan, "settings": settings,
            "tolerances": tolerances_from(contract), "values": values, "material_source": ctx.material_source,
            "source": str(asset_dir)}


def with_trajectory(inputs: dict[str, Any]) -> dict[str, Any]:
    """Plan the trajectory (pybullet) and time it."""
    t0 = time.perf_counter()
    traj, why = plan_or_error(inputs["plan"], inputs["body"], inputs["settings"])
    if traj is None:
        raise SystemExit(f"the plan cannot be executed: {why}")
    return {**inputs, "trajectory": traj, "plan_wall_s": time.perf_counter() - t0}


def machine() -> dict[str, Any]:
    """What ran it: CPU model and cores, the GPU's name, Python and Warp versions."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    gpu = ""
    if shutil.which("nvidia-smi"):
        try:
            gpu = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version", "--format=csv,noheader"],
                                 capture_output=True, text=True, timeout=20).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            gpu = ""
    import warp

    return {"host": platform.node(), "cpu": cpu, "cpu_cores": os.cpu_count(), "gpu": gpu,
            "python": platform.python_version(), "warp": warp.__version__}


def _finite_or_none(v: Any) -> float | None:
    """A float for JSON: None where it is nan or infinite (strict JSON has no NaN)."""
    f = float(v)
    return f if f == f and abs(f) != float("inf") else None


def bench(inputs: dict[str, Any], device: str = "cpu", repeat: int = 1, full: bool = False) -> dict[str, Any]:
    """Run the trial ``repeat`` times on ``device``; the figures of the last run and the wall time of each.
    ``full``: the whole plan even when the lift failed (``TrialSettings.stop_when_lift_fails`` off)."""
    settings = replace(inputs["settings"], device=device)
    if full:
        settings = replace(settings, stop_when_lift_fails=False)
    walls, outer, loads = [], [], []
    r = None
    for _ in range(max(1, repeat)):
        load0 = os.getloadavg()[0]
        t0 = time.perf_counter()
        r = run_trial(inputs["body"], inputs["physical"], inputs["material"], inputs["plan"], settings,
                      inputs["tolerances"], inputs["trajectory"])
        outer.append(time.perf_counter() - t0)
        walls.append(float(r.info["wall_time_s"]))  # type: ignore[arg-type]
        loads.append([round(load0, 2), round(os.getloadavg()[0], 2)])
    assert r is not None
    info: dict[str, Any] = r.info
    m = r.metrics
    plan = inputs["plan"]
    return {
        "case": inputs["case"], "quality": inputs["quality"], "device": device,
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"), "machine": machine(),
        "particles": int(info["particles"]), "steps": int(info["steps"]), "sim_time_s": float(info["sim_time_s"]),
        # trial_wall_s: the whole run_trial call (set-up, control loop, recording, labels), the last run;
        # wall_s: run_trial's own info['wall_time_s'], which stops before the arrays and labels are made
        "trial_wall_s": outer[-1], "wall_s": walls[-1], "wall_s_runs": walls, "call_wall_s_runs": outer,
        "labelling_wall_s": outer[-1] - walls[-1], "loadavg_1min_runs": loads,
        "plan_wall_s": float(inputs.get("plan_wall_s", float("nan"))),
        "labels": {k: _finite_or_none(m[k]) for k in LABELS if k in m},
        "stopped": info["stopped"], "health_issue": info["health_issue"], "intervals": int(info["intervals"]),
        "dx_m": float(info["dx_m"]), "particle_spacing_m": float(info["particle_spacing_m"]),
        "trajectory_duration_s": float(inputs["trajectory"].duration_s),
        "squeeze_depth_m": float(plan.squeeze_depth_m), "grasp_width_m": float(plan.grasp.width_m),
        "material": inputs["material"].model_dump(mode="json"), "mass_kg": float(inputs["physical"].mass_kg),
        "settings": asdict(settings), "tolerances": asdict(inputs["tolerances"]), "source": inputs.get("source", ""),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.l3_trial", description=__doc__.split("\n")[0])
    ap.add_argument("case", nargs="?", choices=("turtle", "cube"), help="what to prepare (omit with --bundle)")
    ap.add_argument("--asset", type=Path, default=DEFAULT_TURTLE, help="asset directory of the turtle case")
    ap.add_argument("--quality", choices=("draft", "standard"), default="draft")
    ap.add_argument("--device", default="cpu", help="cpu | cuda (the run's device; a bundle's settings follow it)")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--full", action="store_true", help="simulate the whole plan even after a failed lift")
    ap.add_argument("--export", type=Path, help="write the prepared inputs (with the trajectory) here; no run")
    ap.add_argument("--bundle", type=Path, help="run prepared inputs from --export (no pybullet needed)")
    ap.add_argument("--no-pybullet", action="store_true", help="with --bundle: the stand-in even if pybullet exists")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    a = ap.parse_args(argv)
    if a.bundle:
        stubbed = _stub_pybullet(a.no_pybullet)
        inputs = load_bundle(a.bundle.read_bytes())
    elif a.case:
        stubbed = False
        inputs = cube_inputs(a.device) if a.case == "cube" else turtle_inputs(a.asset, a.quality, a.device)
        inputs = with_trajectory(inputs)
    else:
        ap.error("name a case or a --bundle")
    if a.export:
        a.export.parent.mkdir(parents=True, exist_ok=True)
        a.export.write_bytes(dump_bundle(inputs))
        print(json.dumps({"exported": str(a.export), "case": inputs["case"], "quality": inputs["quality"],
                          "particles": len(inputs["body"].particles_m), "plan_wall_s": inputs["plan_wall_s"]}))
        return 0
    out = bench(inputs, a.device, a.repeat, a.full)
    out["pybullet_stand_in"] = stubbed
    out["command"] = "python -m benchmarks.l3_trial " + " ".join(sys.argv[1:] if argv is None else argv)
    if a.json:
        print(json.dumps(out))
    else:
        for k in ("case", "quality", "device", "particles", "steps", "sim_time_s", "wall_s", "labels"):
            print(f"{k}: {out[k]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
