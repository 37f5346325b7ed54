"""`deformsmith export DIR --to mujoco|genesis|usd|drake|sofa|all [--out DIR]`: the asset in other simulators."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from flows.cli.apps import app, emit_json, results


@app.command("export")
def export_cmd(
    asset_dir: Path = typer.Argument(..., help="a published asset directory (L2 passed: material.json)"),
    to: str = typer.Option(..., "--to", help="mujoco, genesis, usd, drake, sofa, a comma list, or all"),
    out: Path = typer.Option(None, "--out", help="export root (default: DIR/export); one folder per target"),
    edge_length_m: float = typer.Option(None, "--edge-length", help="tet edge length [m] (default: 0.12 x the "
                                        "bounding-box diagonal)", min=1e-4),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print the export manifest as JSON"),
) -> None:
    """Write the validated deformable asset for other simulators (tet mesh, material, a README line to load it)."""
    # lazy: pulls trimesh, zarr, skimage (--help imports every command module)
    from flows.export import MANIFEST, export_asset

    if cache_dir is not None:
        use_cache_root(cache_dir)
    manifest = export_asset(asset_dir, to, out, edge_length_m=edge_length_m)
    root = Path(out) if out is not None else Path(asset_dir) / "export"
    if as_json:
        emit_json(manifest.model_dump(mode="json"))
        return
    # one line each, never wrapped (a load command is pasted as it is), no markup or highlighting read into them
    results.print(f"tet mesh: {root / manifest.tet_mesh}", markup=False, highlight=False)
    for name in (to.split(",") if to != "all" else list(manifest.targets)):
        t = manifest.targets.get(name.strip())
        if t is not None:
            results.print(f"{t.target}: {root / t.target}/  load: {t.load_hint}", markup=False, highlight=False)
    results.print(f"manifest: {root / MANIFEST}", markup=False, highlight=False)
