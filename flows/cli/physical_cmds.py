"""`deformsmith physical --asset DIR`: run L1 (physical model + rigid probes) on an L0 output."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from flows.cli.apps import app, console, emit_json, fail


@app.command("physical")
def physical(
    asset: Path = typer.Option(..., "--asset", help="asset directory written by `deformsmith geometry`"),
    intent: str = typer.Option(None, "--intent", help="material words, e.g. 'soft plush'; default: the request's text"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print the physical model and metrics as JSON"),
) -> None:
    """L1: density and friction from the intent, mass model, rigid placement / drop / slide probes in pybullet."""
    from cache import use_cache_root

    if not (asset / "geometry.json").is_file():
        fail(f"{asset} is not an L0 asset directory (no geometry.json); run `deformsmith geometry ... --out {asset}`")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    from flows.l1_physical import run_l1

    with console.status("L1: rigid probes in pybullet"):
        phys, outcome = run_l1(asset, intent)
    if as_json:
        emit_json({"passed": outcome.passed, "status": outcome.status, "message": outcome.message,
                   "physical_model": phys.model_dump(mode="json") if phys else None, "metrics": outcome.metrics,
                   "sim_calls": outcome.sim_calls, "attempts": outcome.attempts_used})
    else:
        table = Table(title=f"L1 physical model: {outcome.status}")
        table.add_column("metric")
        table.add_column("value", justify="right")
        if phys:
            table.add_row("density [kg/m^3]", f"{phys.density_kg_per_m3:.4g}")
            table.add_row("mass [kg]", f"{phys.mass_kg:.4g}")
            table.add_row("ground / gripper friction [-]", f"{phys.ground_friction:.3g} / {phys.gripper_friction:.3g}")
        for k, v in sorted(outcome.metrics.items()):
            table.add_row(k, f"{v:.4g}")
        console.print(table)
        console.print(outcome.message)
    if not outcome.passed:
        raise typer.Exit(1)
