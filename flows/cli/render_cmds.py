"""`deformsmith bench render`: seconds per 1280 x 720 frame of the Gaussian splatting renderer, CPU and GPU."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from flows.cli.apps import bench_app, console, emit_json, fail, results


@bench_app.command("render")
def bench_render(
    asset: Path | None = typer.Argument(None, help="asset directory (its gaussians.ply) or a .ply; default: a "
                                        "synthetic ball of --gaussians Gaussians"),
    gaussians: int = typer.Option(20_000, "--gaussians", min=1, help="Gaussians of the synthetic ball"),
    width: int = typer.Option(1280, "--width", min=16, max=8192, help="image width [px]"),
    height: int = typer.Option(720, "--height", min=16, max=8192, help="image height [px]"),
    repeats: int = typer.Option(5, "--repeats", min=1, help="steady-state frames timed (median reported)"),
    png: Path | None = typer.Option(None, "--png", help="also write the frame to this PNG"),
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
) -> None:
    """Seconds per frame on the CPU and (where Warp sees one) a CUDA GPU: first call and steady state; Gaussians
    per frame; the asset used."""
    from contracts.errors import InputError
    from tasks.render.bench import run

    if asset is not None and not asset.exists():
        fail(f"{asset} does not exist")
    try:
        with console.status("timing the splat renderer ..."):
            data = run(asset.absolute() if asset else None, gaussians, width, height, repeats, png=png)
    except InputError as e:
        fail(str(e))
    if as_json:
        emit_json(data)
        return
    table = Table(title=f"splat render {width} x {height}, {data['gaussians_per_frame']} Gaussians ({data['asset']})")
    table.add_column("device")
    table.add_column("first call", justify="right")
    table.add_column("steady", justify="right")
    for dev in ("cpu", "cuda"):
        res = data.get(dev, {})
        if "steady_s" in res:
            table.add_row(dev, f"{res['first_call_s']:.3f} s", f"{res['steady_s']:.3f} s")
        elif res:
            table.add_row(dev, res.get("skipped", "-"), "")
    results.print(table)
