"""The quasi-static probes of an asset with and without mass scaling, side by side in one process.

    python -m benchmarks.quasi_static_scaling --asset DIR [--E PA --nu NU --damping RATE] [--probe compress ...]
                                              [--device cpu|cuda] [--json]

L2's compression (the object's and the specimen cube's) and its 3 s rest run a body whose fundamental period is below
their bound (tasks.probes.deformable: compress_qs_period_s(), STABILITY_QS_PERIOD_S) mass-scaled (density x k,
gravity / k; tasks.probes.rollout.quasi_static_mass_scale). This runs each probe both ways on the asset at one
material (default: L2's start values for the asset's intent, as the flow begins) and prints, per probe: the mass
scale, wall time [s], MPM steps, the speed-up, and every metric both ways with its relative difference. Uncached; no
recordings.
"""

from __future__ import annotations

import contextlib
import math
import os
import platform
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import typer
from rich.table import Table

from contracts.material import Material
from contracts.sim import SimConfig
from contracts.stage import load_contract
from flows.cli.apps import emit_json, fail, results
from flows.l2_material import l2_targets, probe_parameters
from tasks.agents.orchestrator import initial_values
from tasks.geometry.outputs import load_l0
from tasks.mpm import simulator as mpm_simulator
from tasks.physical.plan import physical_for
from tasks.probes import deformable
from tasks.probes.rollout import DeformableBody
from tasks.probes.specimen import specimen_particles
from benchmarks.l2_schedule import physical_intent

PROBES = ("compress", "specimen_compress", "stability")


@contextlib.contextmanager
def unscaled() -> Iterator[None]:
    """Mass scaling off (every body runs at its own density and gravity) inside the block."""
    saved = deformable.COMPRESS_QS_PERIOD_S, deformable.STABILITY_QS_PERIOD_S
    deformable.COMPRESS_QS_PERIOD_S = deformable.STABILITY_QS_PERIOD_S = 0.0
    try:
        yield
    finally:
        deformable.COMPRESS_QS_PERIOD_S, deformable.STABILITY_QS_PERIOD_S = saved


def row_k(result: Any) -> float:
    """The mass scale a probe result ran at (1 when its params name none)."""
    return float(result.spec.params.get("mass_scale", 1.0))


@contextlib.contextmanager
def step_counter() -> Iterator[list[int]]:
    """Counts the MPM steps every Simulator.advance takes inside the block."""
    count = [0]
    original = mpm_simulator.Simulator.advance

    def advance(self: Any, *args: Any, **kwargs: Any) -> Any:
        rep = original(self, *args, **kwargs)
        count[0] += rep.steps
        return rep

    mpm_simulator.Simulator.advance = advance  # type: ignore[method-assign]
    try:
        yield count
    finally:
        mpm_simulator.Simulator.advance = original  # type: ignore[method-assign]


def _rel(a: float | None, b: float | None) -> float | None:
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return None
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0 else round(abs(a - b) / scale, 5)


def run_scaling_bench(asset_dir: Path, material: Material | None = None, probes: tuple[str, ...] = PROBES,
                      device: str = "cpu") -> dict[str, Any]:
    """Each probe with mass scaling and without, on the asset at `material` (default: L2's start values)."""
    import warp as wp

    asset = load_l0(Path(asset_dir))
    physical = physical_for(Path(asset_dir), asset)
    contract = load_contract("L2")
    p = probe_parameters(contract)
    if material is None:
        values = initial_values(contract, l2_targets(asset, physical_intent(Path(asset_dir))), None)
        material = Material(youngs_modulus_pa=values["youngs_modulus_pa"], poisson_ratio=values["poisson_ratio"],
                            damping_rate_per_s=values["damping_rate_per_s"])
    sim = SimConfig(device=device)
    obj = DeformableBody.from_physical(asset.particles_m, asset.volumes_m3, physical)
    spos, svol = specimen_particles(physical.particle_spacing_m, int(p["specimen_particles_per_axis"]), "cube")
    cube = DeformableBody.from_physical(spos, svol, physical)
    runs = {"compress": (obj, "compress", {"strain": p["strain"]}),
            "specimen_compress": (cube, "compress", {"strain": p["strain"]}),
            "stability": (obj, "stability", {"duration_s": p["stability_duration_s"]})}
    wp.init()
    deformable.drop(obj, [material], duration_s=0.01, sim=sim)  # warm-up: kernel load, not timed
    out: dict[str, Any] = {
        "asset": str(asset_dir), "device": device, "material": material.model_dump(mode="json"),
        "particles": int(len(obj.positions_m)), "density_kg_per_m3": obj.density_kg_per_m3,
        "host": {"cpus": os.cpu_count(), "load_average": list(os.getloadavg()), "machine": platform.machine(),
                 "python": platform.python_version(), "warp": wp.__version__},
        "probes": {},
    }
    for name in probes:
        body, kind, params = runs[name]
        row: dict[str, Any] = {"particles": int(len(body.positions_m))}
        for label, ctx in (("unscaled", unscaled()), ("scaled", contextlib.nullcontext())):
            with ctx, step_counter() as steps:
                t = time.perf_counter()
                r = deformable.PROBES[kind](body, [material], sim=sim, **params)[0]
                wall = time.perf_counter() - t
            row[label] = {"wall_s": round(wall, 3), "steps": steps[0], "health_ok": r.health.ok,
                          "metrics": r.metrics}
        row["mass_scale"] = round(float(row_k(r)), 4)
        row["speedup"] = round(row["unscaled"]["wall_s"] / row["scaled"]["wall_s"], 3)
        row["step_ratio"] = round(row["unscaled"]["steps"] / max(1, row["scaled"]["steps"]), 3)
        keys = sorted(set(row["unscaled"]["metrics"]) | set(row["scaled"]["metrics"]))
        row["relative_difference"] = {k: _rel(row["unscaled"]["metrics"].get(k), row["scaled"]["metrics"].get(k))
                                      for k in keys}
        out["probes"][name] = row
    return out


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
def bench_scaling(
    asset: Path = typer.Option(..., "--asset", help="asset directory holding L0 (and L1 physical.json)"),
    youngs: float = typer.Option(None, "--E", help="Young's modulus [Pa] (default: L2's start value)"),
    nu: float = typer.Option(None, "--nu", help="Poisson's ratio [-] (with --E)"),
    damping: float = typer.Option(None, "--damping", help="damping rate [1/s] (with --E)"),
    device: str = typer.Option("cpu", "--device", help="Warp device: cpu or cuda"),
    probe: list[str] = typer.Option(None, "--probe", help="compress | specimen_compress | stability (repeatable)"),
    json_out: bool = typer.Option(False, "--json", help="print the figures as JSON on stdout"),
) -> None:
    """Quasi-static probes with and without mass scaling: wall time, steps and metrics side by side."""
    chosen = tuple(probe or PROBES)
    bad = [x for x in chosen if x not in PROBES]
    if bad:
        fail(f"unknown probe {bad[0]!r}; choose from {', '.join(PROBES)}", 2)
    material = None
    if youngs is not None:
        material = Material(youngs_modulus_pa=youngs, poisson_ratio=0.3 if nu is None else nu,
                            damping_rate_per_s=0.0 if damping is None else damping)
    out = run_scaling_bench(asset, material, chosen, device)
    if json_out:
        emit_json(out)
        return
    table = Table(title=f"mass scaling: {asset} ({out['particles']} particles)")
    for col in ("probe", "k", "unscaled s", "scaled s", "speed-up", "largest metric difference"):
        table.add_column(col)
    for name, row in out["probes"].items():
        diffs = {k: v for k, v in row["relative_difference"].items() if v is not None}
        worst = max(diffs.items(), key=lambda kv: kv[1]) if diffs else ("-", 0.0)
        table.add_row(name, f"{row['mass_scale']:.3g}", f"{row['unscaled']['wall_s']:.1f}",
                      f"{row['scaled']['wall_s']:.1f}", f"{row['speedup']:.2f}x", f"{worst[0]} {worst[1]:.2%}")
    results.print(table)


if __name__ == "__main__":
    app()
