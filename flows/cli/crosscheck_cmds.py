"""`deformsmith crosscheck DIR --sim mujoco|genesis|drake`: the asset in other simulators, measured by L2's probes
beside DeformSmith's MPM values, before and after per-simulator calibration (over several assets and simulators:
`python -m benchmarks.crosscheck_bench`)."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from contracts.errors import DeformSmithError
from flows.cli.apps import app, console, emit_json, fail, results
from tasks.report.tables import crosscheck_lines


@app.command("crosscheck")
def crosscheck_cmd(
    asset_dir: Path = typer.Argument(..., help="a published asset directory (L2 passed: material.json)"),
    sim: str = typer.Option("mujoco", "--sim", help="mujoco, genesis or drake"),
    calibrate: bool = typer.Option(True, "--calibrate/--no-calibrate", help="fit the simulator's E and damping"),
    out: Path = typer.Option(None, "--out", help="export root (default: DIR/export); exported first if missing"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print the report as JSON"),
) -> None:
    """Run L2's drop and compression probes in another simulator on the exported asset and report each metric
    (effective modulus, rebound, impact strain, settle time, recovery) beside DeformSmith's MPM value."""
    # lazy: pulls warp, trimesh, zarr (--help imports every command module)
    from flows.crosscheck import crosscheck_asset

    if not asset_dir.is_dir():
        fail(f"{asset_dir} is not an asset directory")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    try:
        with console.status(f"probing the asset in {sim} ..."):
            report = crosscheck_asset(asset_dir, sim, calibrate=calibrate, export_root=out)
    except DeformSmithError as e:
        fail(str(e))
    if as_json:
        emit_json(report.model_dump(mode="json"))
        return
    for line in crosscheck_lines(report):
        results.print(line)
