"""The L2 screening candidates under each schedule, side by side in one process.

    python -m benchmarks.l2_schedule --asset DIR [--intent WORDS] [--schedule S ...] [--probe compress|drop ...]
                                     [--repeat N] [--device cpu|cuda] [--json]

The candidates are those of flows.l2_material.screen() for the asset and intent: compress at E = 1/3, 1, 3 x the start
value, drop at three damping rates. Each (probe, schedule) runs once here, uncached, with recordings written to a
temporary folder (as the flow writes them). Figures: wall time [s], simulation calls (rollouts), per-candidate wall
time and metrics, and whether the metrics equal those of the same candidate run alone (the sequential schedule).
"""

from __future__ import annotations

import contextlib
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import typer
from rich.table import Table

from contracts.material import Material
from contracts.sim import SimConfig
from contracts.stage import load_contract
from flows.cli.apps import console, emit_json, fail, results
from flows.l2_material import l2_targets, probe_parameters, screen_dampings, screen_moduli
from tasks.physical.plan import physical_for
from tasks.agents.orchestrator import initial_values
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import load_l0
from tasks.probes import deformable
from tasks.probes.rollout import SCHEDULES, DeformableBody, plan_batches, rollouts

KEY_METRICS = {"compress": ("effective_modulus_pa", "recovery_ratio", "compression_strain"),
               "drop": ("rebound_ratio", "settle_time_s", "max_impact_strain")}


def run_l2_bench(asset_dir: Path, intent: str | None = None, schedules: tuple[str, ...] = ("batch", "sequential"),
                 probes: tuple[str, ...] = ("compress", "drop"), device: str = "cpu",
                 repeat: int = 1) -> dict[str, Any]:
    """Run the screening candidates of each probe under each schedule (`repeat` times); return the figures."""
    import warp as wp

    asset_dir = Path(asset_dir)
    asset = load_l0(asset_dir)
    physical = physical_for(asset_dir, asset)
    contract = load_contract("L2")
    targets = l2_targets(asset, intent or physical_intent(asset_dir))
    values = initial_values(contract, targets, None)
    fields = {f.name: f for f in contract.editable_fields}
    p = probe_parameters(contract)
    sim = SimConfig(device=device)
    body = DeformableBody.from_physical(asset.particles_m, asset.volumes_m3, physical)
    candidates = {
        "compress": ([Material(youngs_modulus_pa=e, poisson_ratio=values["poisson_ratio"],
                               damping_rate_per_s=values["damping_rate_per_s"])
                      for e in screen_moduli(values, fields["youngs_modulus_pa"])], {"strain": p["strain"]}),
        "drop": ([Material(youngs_modulus_pa=values["youngs_modulus_pa"], poisson_ratio=values["poisson_ratio"],
                           damping_rate_per_s=d) for d in screen_dampings(values, fields["damping_rate_per_s"])],
                 {"height_fraction": p["height_fraction"]}),
    }
    wp.init()
    t = time.perf_counter()
    deformable.drop(body, candidates["drop"][0][:1], duration_s=0.02, sim=sim)  # warm-up: kernel load, not timed
    warm_s = time.perf_counter() - t
    out: dict[str, Any] = {
        "asset": str(asset_dir), "intent": targets.intent, "device": device, "particles": int(len(asset.particles_m)),
        "particle_spacing_m": float(asset.spacing_m), "density_kg_per_m3": float(physical.density_kg_per_m3),
        "start_values": values, "warm_up_s": round(warm_s, 3), "repeat": repeat,
        "host": {"cpus": os.cpu_count(), "load_average": list(os.getloadavg()), "machine": platform.machine(),
                 "python": platform.python_version(), "warp": wp.__version__},
        "probes": {},
    }
    with tempfile.TemporaryDirectory(prefix="ds-bench-l2-") as tmp:
        for kind in probes:
            mats, params = candidates[kind]
            rows: dict[str, Any] = {}
            for sched in schedules:
                for rep in range(repeat):
                    paths = [Path(tmp) / f"{kind}-{sched}-{rep}-{i}.rrd" for i in range(len(mats))]
                    probe: Any = deformable.PROBES[kind]
                    t = time.perf_counter()
                    rs = probe(body, mats, sim=sim, record_paths=paths, schedule=sched, **params)
                    wall = time.perf_counter() - t
                    groups = plan_batches(body, mats, sim, sched)
                    row: dict[str, Any] = {
                        "wall_s": round(wall, 3), "sim_calls": rollouts(groups, rs), "groups": groups,
                        "healthy": all(r.health.ok for r in rs),
                        "candidates": [{"material": m.model_dump(mode="json"),
                                        "rollout_wall_s": round(r.wall_time_s, 3),
                                        "metrics": {k: r.metrics.get(k) for k in KEY_METRICS[kind]}}
                                       for m, r in zip(mats, rs)]}
                    if rep == 0:
                        rows[sched] = row
                    else:
                        rows[sched].setdefault("repeats_wall_s", []).append(row["wall_s"])
                        rows[sched]["deterministic"] = rows[sched].get("deterministic", True) and all(
                            a["metrics"] == b["metrics"] for a, b in zip(rows[sched]["candidates"], row["candidates"]))
            ref = rows.get("sequential")
            for row in rows.values():
                if ref is not None:
                    row["same_metrics_as_alone"] = all(a["metrics"] == b["metrics"]
                                                       for a, b in zip(row["candidates"], ref["candidates"]))
                    row["x_sequential"] = round(row["wall_s"] / ref["wall_s"], 3) if ref["wall_s"] > 0 else None
                    one = ref["candidates"][len(mats) // 2]["rollout_wall_s"]
                    row["x_one_probe"] = round(row["wall_s"] / one, 3) if one > 0 else None
            out["probes"][kind] = rows
    out["total_wall_s"] = {s: round(sum(out["probes"][k][s]["wall_s"] for k in probes), 3) for s in schedules}
    out["total_sim_calls"] = {s: sum(out["probes"][k][s]["sim_calls"] for k in probes) for s in schedules}
    return out


def physical_intent(asset_dir: Path) -> str | None:
    """The intent L1 ran with (physical.json), if any."""
    import json

    path = Path(asset_dir) / "physical.json"
    if not path.is_file():
        return None
    return json.loads(path.read_text(encoding="utf-8")).get("intent")


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
def bench_l2(
    asset: Path = typer.Option(..., "--asset", help="asset directory holding L0 (and L1 physical.json)"),
    intent: str = typer.Option(None, "--intent", help="material words (default: the intent L1 ran with)"),
    schedule: list[str] = typer.Option(None, "--schedule",
                                       help="batch | grouped | sequential | auto (repeatable; default batch, grouped, "
                                            "sequential)"),
    probe: list[str] = typer.Option(None, "--probe", help="compress | drop (repeatable; default both)"),
    repeat: int = typer.Option(1, "--repeat", help="runs per schedule (>1 also checks the metrics repeat exactly)"),
    device: str = typer.Option("cpu", "--device", help="Warp device: cpu or cuda"),
    json_out: bool = typer.Option(False, "--json", help="print the figures as JSON on stdout"),
) -> None:
    """Time the L2 screening candidates (compress at 1/3, 1, 3 x E; drop at three damping rates) under each schedule,
    side by side in one process (warm-up excluded, no cache, recordings to a temporary folder)."""
    if not AssetDir(asset).has("geometry"):
        fail(f"{asset} is not an asset directory (no geometry.json); run `deformsmith geometry ... --out {asset}`")
    schedules = tuple(schedule or ("batch", "grouped", "sequential"))
    probes = tuple(probe or ("compress", "drop"))
    if bad := [s for s in schedules if s not in SCHEDULES]:
        fail(f"unknown schedule(s) {', '.join(bad)}; choose from {', '.join(SCHEDULES)}")
    if bad := [p for p in probes if p not in ("compress", "drop")]:
        fail(f"unknown probe(s) {', '.join(bad)}; choose compress and/or drop")
    if device not in ("cpu", "cuda") or repeat < 1:
        fail("need --device cpu|cuda and --repeat >= 1")
    if intent is not None and not intent.strip():
        fail("--intent is empty")
    with contextlib.redirect_stdout(sys.stderr), console.status("benchmarking the L2 screening ..."):
        data = run_l2_bench(asset, intent, schedules, probes, device, repeat)
    if json_out:
        emit_json(data)
        return
    table = Table(title=f"L2 screening on {asset} ({data['particles']} particles, {data['intent']}, {device})")
    for col in ("probe", "schedule", "sim calls", "wall [s]", "x sequential", "x one probe", "same as alone"):
        table.add_column(col)
    for kind, rows in data["probes"].items():
        for sched, row in rows.items():
            table.add_row(kind, sched, str(row["sim_calls"]), f"{row['wall_s']:.2f}", str(row.get("x_sequential")),
                          str(row.get("x_one_probe")), str(row.get("same_metrics_as_alone")))
    results.print(table)


__all__ = ["physical_intent", "run_l2_bench"]

if __name__ == "__main__":
    app()
