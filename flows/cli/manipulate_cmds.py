"""`deformsmith manipulate ASSET_DIR` (L3 pick-and-place) and `deformsmith replay ASSET_DIR` (no re-simulation)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING, cast

import typer

from cache import use_cache_root
from contracts.errors import RequirementNotMet
from flows.cli.apps import RECORD_HELP, app, check_device, check_record, console, emit_json, fail, results
from tasks.preflight import check_asset_dir, check_outputs
from tasks.report.layers import manipulation_summary, manipulation_table

if TYPE_CHECKING:
    from contracts.asset_dir import KeepTrials
    from contracts.sim import Device


@app.command("manipulate")
def manipulate(
    asset: Path = typer.Argument(..., help="asset directory with L0 geometry and L1 physical.json (L2 optional)"),
    quality: str = typer.Option("draft", "--quality", help="draft (CPU) | standard (finer particles, slower timing)"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda"),
    cpu_threads: int = typer.Option(2, "--cpu-threads", help="CPU: threads sharing each trial's particles"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print manipulation.json's summary as JSON"),
    require_l3: bool = typer.Option(False, "--require-l3", help="exit 7 when L3 does not pass (no grasp, a failed "
                                    "pick); manipulation.json is written either way"),
    record: str = typer.Option("adopted", "--record", help=RECORD_HELP),
) -> None:
    """L3: grasp ranking, plan, pick-and-place in the MPM, revision through the harness, held-out conditions.

    An L3 that does not pass (no grasp, no valid pick) is a result: recorded, printed with its reason, exit 0
    (exit 7 with --require-l3)."""
    from tasks.asset_dir import AssetDir  # lazy: contracts.asset_dir's models (~0.1 s at --help)
    from tasks.publish import staged_update  # lazy: pulls ctypes (--help imports every command module)

    if not AssetDir(asset).has("geometry"):
        fail(f"{asset} is not an asset directory (no geometry.json)")
    if not AssetDir(asset).has("physical"):
        fail(f"{asset} has no physical.json: run `deformsmith physical --asset {asset}` first")
    if quality not in ("draft", "standard"):
        fail(f"--quality must be draft or standard, got '{quality}'")
    check_device(device)
    check_record(record)
    if not 1 <= cpu_threads <= 64:
        fail(f"--cpu-threads must be 1 to 64, got {cpu_threads}")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    check_asset_dir(asset)  # the asset directory, its parent and the cache root usable, before L3 runs
    from flows.generate import refresh_after_l3  # lazy: pulls every layer's flow (--help imports every command module)
    # lazy: pulls prefect, warp, pybullet (--help imports every command module)
    from flows.l3_manipulation import L3Options, run_l3

    options = (L3Options.standard(device, cpu_threads) if quality == "standard"
               else L3Options(device=device, cpu_threads=cpu_threads))
    with console.status("L3: pick-and-place trials in the MPM") as status:
        def progress(message: str) -> None:
            status.update(message)
            console.log(message, markup=False)

        with staged_update(asset) as work:  # L3 writes into a working copy, swapped in whole when it ends
            t0 = time.perf_counter()
            result, outcome = run_l3(work, options, progress=progress, keep=cast("KeepTrials", record))
            wall_time_s = time.perf_counter() - t0
            # a published asset: asset.json, the PhysGaussian config, the card and the video follow the new L3 (its
            # adopted material, L3's line and plan), swapped in with manipulation.json
            status.update("L3: asset.json, card and video refreshed from manipulation.json")
            refresh_after_l3(work, result, cast("Device", device))
    if as_json:
        emit_json(manipulation_summary(result, wall_time_s))
    else:
        results.print(manipulation_table(result))
        results.print(result.message, markup=False)
    if not result.passed:
        console.print(f"L3 did not pass: {result.reason or result.message}; recorded in "
                      f"{asset / 'manipulation.json'}" + ("" if require_l3 else " (--require-l3 makes this exit 7)"),
                      markup=False)
        if require_l3:
            raise RequirementNotMet("L3", result.reason or result.message)


@app.command("replay")
def replay_cmd(
    asset: Path = typer.Argument(..., help="asset directory with interaction/ data"),
    trial: int = typer.Option(None, "--trial", help="the trial to replay, numbered from 1 as the console, "
                              "manipulation.json, evidence and the card number them (default: the trial L3 reports)"),
    attempt: int = typer.Option(None, "--attempt", hidden=True, help="interaction folder index (attempt_NNN)"),
    video: Path = typer.Option(None, "--video", help="write an .mp4 or .gif"),
    frames: Path = typer.Option(None, "--frames", help="write PNG frames into this folder"),
    rrd: Path = typer.Option(None, "--rrd", help="write a Rerun recording (robot links, pads, particles, forces)"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda: where the frames are drawn"),
    as_json: bool = typer.Option(False, "--json", help="print what was written as JSON"),
) -> None:
    """Replay a recorded trial from its particle states (no re-simulation): frames, video, .rrd."""
    # lazy: pulls pybullet, trimesh, zarr (--help imports every command module)
    from tasks.manipulation.replay import replay

    if not (asset / "interaction").is_dir():
        fail(f"{asset} has no interaction/ data: run `deformsmith manipulate {asset}` first")
    check_device(device)
    check_outputs(files=(video, rrd), folders=(frames,))  # where the replay is written, before rendering
    with console.status("rendering the recorded attempt"):
        out = replay(asset, attempt, frames_dir=frames, video=video, rrd=rrd, trial=trial, device=device)
    data = {"trial": out.trial, "frames": len(out.frames), "rendered": out.n_frames, "video": str(out.video) if out.video else None,
            "recording": str(out.recording) if out.recording else None, "first_frame_sha256": out.digests[0]}
    if as_json:
        emit_json(data)
    else:
        results.print(data)
