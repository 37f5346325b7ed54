"""`deformsmith physical DIR` (or --asset DIR): run L1 (physical model + rigid probes) on an L0 output."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, cast

import typer

from cache import use_cache_root
from flows.cli.apps import RECORD_HELP, app, check_record, console, emit_json, fail, results
from tasks.preflight import check_asset_dir
from tasks.report.layers import mass_check_lines, physical_table

if TYPE_CHECKING:
    from contracts.asset_dir import KeepTrials


def asset_path(positional: Path | None, option: Path | None) -> Path:
    """The asset directory given as the argument or with --asset (one of them, not two different ones)."""
    if positional is None and option is None:
        fail("give the asset directory, as the argument or with --asset DIR")
    if positional is not None and option is not None and positional != option:
        fail(f"two asset directories given ({positional} and --asset {option}); give one")
    return positional if positional is not None else option  # type: ignore[return-value]


@app.command("physical")
def physical(
    asset_dir: Path = typer.Argument(None, help="asset directory written by `deformsmith geometry` (or --asset)"),
    asset: Path = typer.Option(None, "--asset", help="asset directory written by `deformsmith geometry`"),
    intent: str = typer.Option(None, "--intent", help="material words, e.g. 'soft plush'; default: the request "
                               "`geometry` stored (its --intent, else its text), as `generate` does"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print the physical model and metrics as JSON"),
    record: str = typer.Option("adopted", "--record", help=RECORD_HELP),
) -> None:
    """L1: density and friction from the intent, mass model, rigid placement / drop / slide probes in pybullet."""
    from tasks.asset_dir import AssetDir  # lazy: contracts.asset_dir's models (~0.1 s at --help)
    from tasks.publish import staged_update  # lazy: pulls ctypes (--help imports every command module)

    asset = asset_path(asset_dir, asset)
    if intent is not None and not intent.strip():
        fail("--intent is empty")
    check_record(record)

    if not AssetDir(asset).has("geometry"):
        fail(f"{asset} is not an L0 asset directory (no geometry.json); run `deformsmith geometry ... --out {asset}`")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    check_asset_dir(asset)  # the asset directory, its parent and the cache root usable, before L1 runs
    from flows.l1_physical import run_l1  # lazy: pulls prefect, trimesh, zarr (--help imports every command module)

    # L1 writes into a working copy, swapped in whole when it ends: files and evidence together, or nothing
    with console.status("L1: rigid probes in pybullet"), staged_update(asset) as work:
        phys, outcome = run_l1(work, intent, keep=cast("KeepTrials", record))  # (checked by check_record)
    mass = AssetDir(asset).physical().mass_check  # tasks.physical.mass.MassCheck as written
    if as_json:
        emit_json({"passed": outcome.passed, "status": outcome.status, "message": outcome.message,
                   "physical_model": phys.model_dump(mode="json") if phys else None, "metrics": outcome.metrics,
                   "sim_calls": outcome.sim_calls, "attempts": outcome.attempts_used, "mass_check": mass})
    else:
        results.print(physical_table(outcome, phys))
        if mass:
            head, *notes = mass_check_lines(mass)
            results.print(head)
            for note in notes:
                results.print(note, markup=False)
        results.print(outcome.message, markup=False)
    if not outcome.passed:
        raise typer.Exit(1)
