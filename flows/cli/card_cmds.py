"""`deformsmith card DIR`: (re)build an asset's card, renders/card.png and renders/card.html, from its directory."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from flows.cli.apps import app, results


@app.command("card")
def card(
    asset_dir: Path = typer.Argument(..., help="a published asset directory (with asset.json)"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (the card's picture is cached by what it shows)"),
) -> None:
    """Rebuild the asset card: request, views, drop frames, material and bands, L1, L3 and where each number came
    from (renders/card.png and renders/card.html, the videos embedded)."""
    from tasks.render.card import build_card  # lazy: pulls trimesh, zarr, scipy (--help imports every command module)

    if cache_dir is not None:
        use_cache_root(cache_dir)
    png, page = build_card(asset_dir.expanduser())  # InputError on a bad directory: one `error:` line, exit 2
    results.print(f"card: {png}\ncard: {page}", markup=False, highlight=False)
