"""Build an asset's card: renders/card.png and renders/card.html, from its directory (tasks.render.card_data). The
PNG (matplotlib, ~1-3 s) is cached by what it shows (cache.files.cached_file); the HTML is written each time."""

from __future__ import annotations

import hashlib
from pathlib import Path

from cache import content_key
from cache.files import cached_file, source_digest
from contracts.errors import InputError
from contracts.manifest import AssetManifest
from tasks.render.card_data import CardData, card_data
from tasks.render.card_html import card_html
from tasks.render.card_png import write_card_png

CARD_PNG = "renders/card.png"
CARD_HTML = "renders/card.html"


def card_png_key(card: CardData, root: Path) -> str:
    """The PNG's cache key: what it shows (the card's data and the pictures it draws) and the code that draws it."""
    here = Path(__file__).resolve().parent
    code = source_digest([here / f"{m}.py" for m in ("card_png", "card_text", "card_data")], ("matplotlib", "numpy"))
    pictures = sorted({*card.views.values(), *(f.still or f.video or "" for f in card.drop_frames)} - {""})
    digests = [[rel, hashlib.sha256((root / rel).read_bytes()).hexdigest()] for rel in pictures]
    return content_key("asset_card_png", code, card.model_dump_json(), digests)


def build_card(asset_dir: Path | str, manifest: AssetManifest | None = None) -> tuple[Path, Path]:
    """Write renders/card.png and renders/card.html (each atomically); their paths. InputError when asset_dir is not
    an asset directory (nothing is written then).

    manifest: the one about to be written, when asset.json is not there yet (generate builds the card in its working
    directory)."""
    root = Path(asset_dir)
    if not root.is_dir():
        raise InputError(f"{root} is not an asset directory (not a directory)")
    card = card_data(root, manifest)
    png, page = root / CARD_PNG, root / CARD_HTML
    png.parent.mkdir(parents=True, exist_ok=True)
    tmp_png = png.with_name(png.name + ".tmp.png")
    tmp_html = page.with_name(page.name + ".tmp")
    try:
        cached_file(card_png_key(card, root), tmp_png, lambda dest: write_card_png(card, root, dest))
        tmp_html.write_text(card_html(card), encoding="utf-8")
        tmp_png.replace(png)
        tmp_html.replace(page)
    finally:
        for tmp in (tmp_png, tmp_html):
            tmp.unlink(missing_ok=True)
    return png, page
