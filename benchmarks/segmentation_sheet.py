"""Photos -> segmentation sheets: each photo with its mask outlined beside the mask alone, and a contact sheet.

    python benchmarks/segmentation_sheet.py [--photos DIR] --out DIR [--only NAME ...] [--labels]

For each row of DIR/manifest.json (tests/geometry/photos/ by default) the photo is read as the photo path reads it
(tasks.geometry.image.load_image) and segmented (image.segment); OUT/<stem>.png (--out, required) shows the photo
with the mask's outline in green (and, with --labels, the rough hand label of DIR/masks.json in magenta) beside the
mask alone, captioned with the method, the mask's area fraction, the seconds and, where a label exists, the IoU with
it. OUT/contact_sheet.png puts every photo's panel in a grid. One JSON line per photo on stdout.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import cv2
import numpy as np

from tasks.geometry import image

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

PANEL_H = 320  # height of one photo's half panel in the sheets [px]


def label_mask(shapes: list[dict], shape: tuple[int, int]) -> np.ndarray:
    """Rasterise a rough hand label (ellipses and polygons in coordinates relative to the width and height)."""
    h, w = shape
    m = np.zeros((h, w), np.uint8)
    for s in shapes:
        if s["type"] == "ellipse":
            cx, cy, rx, ry = s["cx"] * w, s["cy"] * h, s["rx"] * w, s["ry"] * h
            cv2.ellipse(m, (round(cx), round(cy)), (max(1, round(rx)), max(1, round(ry))), float(s.get("angle", 0.0)),
                        0, 360, 1, -1)
        elif s["type"] == "polygon":
            pts = np.array([[x * w, y * h] for x, y in s["points"]], np.float64).round().astype(np.int32)
            cv2.fillPoly(m, [pts], 1)
        else:
            raise ValueError(f"unknown label shape {s['type']!r}")
    return m.astype(bool)


def _caption(img: np.ndarray, lines: list[str]) -> np.ndarray:
    bar = np.full((18 * len(lines) + 6, img.shape[1], 3), 255, np.uint8)
    for i, line in enumerate(lines):
        cv2.putText(bar, line, (4, 16 + 18 * i), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    return np.vstack([img, bar])


def panel(rgb: np.ndarray, mask: np.ndarray, label: np.ndarray | None, lines: list[str]) -> np.ndarray:
    """The photo with the outlines beside the mask alone (RGB uint8), at PANEL_H pixels high, captioned."""
    rgb = np.ascontiguousarray(rgb[:, :, :3])
    k = PANEL_H / rgb.shape[0]
    size = (max(1, round(rgb.shape[1] * k)), PANEL_H)
    left = cv2.resize(rgb, size, interpolation=cv2.INTER_AREA)
    m = cv2.resize(mask.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST)
    if label is not None:
        lm = cv2.resize(label.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST)
        contours, _ = cv2.findContours(lm, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        cv2.drawContours(left, contours, -1, (255, 0, 255), 1, cv2.LINE_AA)
    contours, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(left, contours, -1, (0, 255, 0), 2, cv2.LINE_AA)
    right = np.repeat((m * 255)[:, :, None], 3, axis=2)
    gap = np.full((PANEL_H, 6, 3), 255, np.uint8)
    return _caption(np.hstack([left, gap, right]), lines)


def contact_sheet(panels: list[np.ndarray], cols: int = 3) -> np.ndarray:
    """The panels in a grid on white (RGB uint8)."""
    cw = max(p.shape[1] for p in panels)
    ch = max(p.shape[0] for p in panels)
    rows = (len(panels) + cols - 1) // cols
    sheet = np.full((rows * (ch + 8), cols * (cw + 8), 3), 255, np.uint8)
    for i, p in enumerate(panels):
        r, c = divmod(i, cols)
        sheet[r * (ch + 8) : r * (ch + 8) + p.shape[0], c * (cw + 8) : c * (cw + 8) + p.shape[1]] = p
    return sheet


def main() -> None:
    """Segment every photo of the manifest and write the per-photo panels and the contact sheet."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--photos", type=Path, default=ROOT / "tests" / "geometry" / "photos")
    ap.add_argument("--out", type=Path, required=True, help="folder for the PNGs (created)")
    ap.add_argument("--only", nargs="*", default=None, help="file names to run")
    ap.add_argument("--labels", action="store_true", help="outline the rough hand labels of masks.json too")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = json.loads((args.photos / "manifest.json").read_text(encoding="utf-8"))
    labels_path = args.photos / "masks.json"
    labels = json.loads(labels_path.read_text(encoding="utf-8")) if labels_path.is_file() else {}
    panels = []
    for row in rows:
        if args.only and row["file"] not in args.only:
            continue
        path = args.photos / row["file"]
        rgb = image.load_image(path)
        t0 = time.perf_counter()
        mask, method = image.segment(rgb)
        seconds = time.perf_counter() - t0
        shapes = labels.get(row["file"])
        label = label_mask(shapes, mask.shape) if shapes else None
        out = {"file": row["file"], "soft": row["soft"], "method": method, "area": round(float(mask.mean()), 3),
               "seconds": round(seconds, 2)}
        if label is not None:
            out["label_iou"] = round(float((mask & label).sum() / max(1, (mask | label).sum())), 3)
        lines = [f"{row['file']} ({'soft' if row['soft'] else 'rigid'})",
                 f"{method}  area {out['area']:.3f}  {seconds:.2f} s"
                 + (f"  label IoU {out['label_iou']:.3f}" if "label_iou" in out else "")]
        p = panel(rgb, mask, label if args.labels else None, lines)
        cv2.imwrite(str(args.out / f"{path.stem}.png"), cv2.cvtColor(p, cv2.COLOR_RGB2BGR))
        panels.append(p)
        print(json.dumps(out), flush=True)
    if panels:
        sheet = contact_sheet(panels)
        cv2.imwrite(str(args.out / "contact_sheet.png"), cv2.cvtColor(sheet, cv2.COLOR_RGB2BGR))


if __name__ == "__main__":
    main()
