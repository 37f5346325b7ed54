"""Blind-judging sheets: renders tiled ten to a PNG in a seeded random order, each labelled 'NNN-k', and the label ->
name map written aside (the judges see the sheets only).

    python -m benchmarks.tile_sheets VIEWS_DIR --out SHEETS_DIR [--seed 38] [--per-sheet 10] [--only IDS.txt]
"""

from __future__ import annotations

import argparse
import json
import random
import sys
from pathlib import Path

from PIL import Image, ImageDraw

LABEL_H = 22  # pixels of the label strip above each render


def tile(views: list[Path], out: Path, seed: int, per_sheet: int) -> dict[str, str]:
    """Write sheet_NNN.png files under `out`; return label -> view stem."""
    order = sorted(views)
    random.Random(seed).shuffle(order)
    out.mkdir(parents=True, exist_ok=True)
    labels: dict[str, str] = {}
    for s in range(0, len(order), per_sheet):
        chunk = order[s:s + per_sheet]
        ims = [Image.open(p).convert("RGB") for p in chunk]
        w, h = max(i.width for i in ims), max(i.height for i in ims)
        cols = 2
        rows = (len(ims) + cols - 1) // cols
        sheet = Image.new("RGB", (cols * w, rows * (h + LABEL_H)), "white")
        draw = ImageDraw.Draw(sheet)
        n = s // per_sheet + 1
        for k, (im, path) in enumerate(zip(ims, chunk), start=1):
            x, y = ((k - 1) % cols) * w, ((k - 1) // cols) * (h + LABEL_H)
            label = f"{n:03d}-{k}"
            labels[label] = path.stem
            draw.text((x + 6, y + 4), label, fill="black")
            sheet.paste(im, (x, y + LABEL_H))
        sheet.save(out / f"sheet_{n:03d}.png")
    return labels


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("views", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--labels", type=Path, required=True, help="where the label -> name map goes (kept from judges)")
    ap.add_argument("--seed", type=int, default=38)
    ap.add_argument("--per-sheet", type=int, default=10)
    ap.add_argument("--only", type=Path, help="a file of view stems, one a line: tile only these")
    args = ap.parse_args(argv)
    views = sorted(args.views.glob("*.jpg")) + sorted(args.views.glob("*.png"))
    if args.only is not None:
        keep = set(args.only.read_text(encoding="utf-8").split())
        views = [v for v in views if v.stem in keep]
    labels = tile(views, args.out, args.seed, args.per_sheet)
    args.labels.write_text(json.dumps(labels, indent=1), encoding="utf-8")
    print(f"{len(labels)} renders on {len(list(args.out.glob('sheet_*.png')))} sheets in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
