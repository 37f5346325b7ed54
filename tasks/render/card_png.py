"""The asset card as one PNG (matplotlib, Agg): request, three views, drop frames, material and bands, L1, L3 and
where each number came from. Deterministic: no time stamps in the file."""

from __future__ import annotations

import textwrap

from pathlib import Path
from typing import Any

import numpy as np

from tasks.render.card_data import CardData, DropFrame
from tasks.render.card_text import figure_lines, outcome_lines, request_line, si, wrap

FONT_PT = 8.0
CARD_VIEW = "front"  # the drop frames shown on the PNG (the HTML shows both views)


def drop_frame_image(asset_dir: Path, frame: DropFrame) -> tuple[np.ndarray | None, float]:
    """The drop frame's picture and the time it shows [s]: the still, else the video's nearest frame, else None."""
    import imageio.v2 as imageio

    if frame.still:
        return np.asarray(imageio.imread(asset_dir / frame.still))[..., :3], frame.t_s
    if frame.video:
        reader = imageio.get_reader(asset_dir / frame.video)
        try:
            n = reader.count_frames()  # type: ignore[attr-defined]  # the ffmpeg plugin's reader
            k = min(frame.video_frame, n - 1)
            return np.asarray(reader.get_data(k))[..., :3], k / 30.0
        finally:
            reader.close()
    return None, frame.t_s


def _text(ax: Any, lines: list[str], title: str) -> None:
    ax.axis("off")
    ax.set_title(title, loc="left", fontsize=FONT_PT + 2, fontweight="bold")
    ax.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", family="monospace", fontsize=FONT_PT,
            transform=ax.transAxes)


def _image(ax: Any, img: np.ndarray | None, title: str) -> None:
    ax.axis("off")
    ax.set_title(title, fontsize=FONT_PT + 1)
    if img is None:
        ax.text(0.5, 0.5, "(no picture)", ha="center", va="center", fontsize=FONT_PT, transform=ax.transAxes)
    else:
        ax.imshow(img, interpolation="antialiased")


def _material_lines(card: CardData) -> list[str]:
    lines = []
    for fig in card.material:
        lines += figure_lines(fig)[:1]
    lines += ["", "target bands (measured on a specimen of the material):"]
    for fig in card.bands:
        lines += figure_lines(fig)
    return lines


def _l1_lines(card: CardData) -> list[str]:
    lines = []
    for fig in card.l1:
        lines += figure_lines(fig, 22)
    lines += ["", "drop protocol (5 s, 30 fps, clearance H/4):"]
    for fig in card.protocol:
        lines += figure_lines(fig, 22)[:1]
    return lines


def _l3_lines(card: CardData) -> list[str]:
    l3 = card.l3
    if not l3.ran:
        return wrap(l3.note)
    verdict = "passed" if l3.passed else "did not pass"
    lines = [f"gripper: {l3.gripper}", f"L3 {verdict} ({l3.status}); trial {l3.attempt}"]
    lines += wrap(l3.note, indent="  ")
    lines += outcome_lines(l3.outcome) + [f"force budget {si(l3.force_budget_n, 'N')} per finger", ""]
    for fig in l3.figures:
        lines += figure_lines(fig, 22)[:1]
    if l3.key:
        lines.append(f"  from manipulation.json, trial cache key {l3.key[:12]}")
    return lines


def _force_plot(ax: Any, card: CardData) -> None:
    l3 = card.l3
    if not l3.ran or not l3.force_t_s:
        ax.axis("off")
        ax.text(0.5, 0.5, "\n".join(wrap(l3.note if not l3.ran else "no finger-force record", 40)),
                ha="center", va="center", fontsize=FONT_PT + 1, transform=ax.transAxes)
        ax.set_title("L3 finger forces", fontsize=FONT_PT + 1)
        return
    t = np.asarray(l3.force_t_s)
    f = np.asarray(l3.finger_force_n)
    ax.plot(t, f[:, 0], lw=1.0, label="finger 1")
    ax.plot(t, f[:, 1], lw=1.0, label="finger 2")
    if l3.force_budget_n:
        ax.axhline(l3.force_budget_n, color="0.4", ls="--", lw=0.8, label=f"budget {l3.force_budget_n:.3g} N")
    ax.set_xlabel("time [s]", fontsize=FONT_PT)
    ax.set_ylabel("finger force [N]", fontsize=FONT_PT)
    ax.tick_params(labelsize=FONT_PT)
    ax.legend(fontsize=FONT_PT, loc="upper right")
    ax.set_title(f"L3 finger forces ({l3.gripper}, trial {l3.attempt})", fontsize=FONT_PT + 1)
    ax.grid(alpha=0.3)


def write_card_png(card: CardData, asset_dir: Path, path: Path) -> Path:
    """Draw the card into path (PNG, 1800 x 1300 px: three text columns of 80 characters)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.gridspec import GridSpec

    fig = plt.figure(figsize=(18, 13), dpi=100)
    try:
        gs = GridSpec(5, 12, figure=fig, height_ratios=[0.6, 2.2, 1.9, 3.6, 0.8], hspace=0.35, wspace=0.4,
                      left=0.03, right=0.98, top=0.97, bottom=0.02)
        head = fig.add_subplot(gs[0, :])
        head.axis("off")
        head.text(0.0, 1.0, f"DeformSmith asset card: {card.name}", fontsize=14, fontweight="bold", va="top",
                  transform=head.transAxes)
        stages = ["   ".join(card.stages[i:i + 2]) for i in range(0, len(card.stages), 2)]
        head.text(0.0, 0.45, "\n".join([request_line(card.request), *stages]), fontsize=FONT_PT + 1,
                  family="monospace", va="top", transform=head.transAxes)
        if card.analogy:  # built by analogy: said in a box a reader cannot miss
            head.text(0.62, 1.0, "\n".join(textwrap.wrap(card.analogy[0], 70)[:3]), fontsize=FONT_PT + 1, va="top",
                      transform=head.transAxes, bbox={"boxstyle": "round", "facecolor": "#fff6e5", "edgecolor": "#c80"})
        elif card.built:
            head.text(0.62, 1.0, card.built, fontsize=FONT_PT + 1, va="top", transform=head.transAxes)
        import imageio.v2 as imageio

        for i, view in enumerate(("front", "side", "top")):
            rel = card.views.get(view)
            img = np.asarray(imageio.imread(asset_dir / rel))[..., :3] if rel else None
            _image(fig.add_subplot(gs[1, 2 * i:2 * i + 2]), img, f"{view} (L0 mesh)")
        _force_plot(fig.add_subplot(gs[1, 7:12]), card)
        frames = [f for f in card.drop_frames if f.view == CARD_VIEW]
        for i, frame in enumerate(frames[:4]):
            img, t = drop_frame_image(asset_dir, frame)
            _image(fig.add_subplot(gs[2, 3 * i:3 * i + 3]), img, f"drop, {frame.view} view, t = {t:.2f} s")
        _text(fig.add_subplot(gs[3, 0:4]), _material_lines(card), "L2 material")
        _text(fig.add_subplot(gs[3, 4:8]), _l1_lines(card), "L1 mass and contact")
        _text(fig.add_subplot(gs[3, 8:12]), _l3_lines(card), "L3 pick and place")
        src = fig.add_subplot(gs[4, :])
        lines = ["cache keys (CacheStore(root).get(key)); records: asset.json, physical.json, material.json, "
                 "manipulation.json, evidence/attempts.jsonl"]
        lines += ["   ".join(card.sources[i:i + 4]) for i in range(0, len(card.sources), 4)]
        _text(src, lines, "where the numbers came from")
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=100, metadata={"Software": None})
    finally:
        plt.close(fig)
    return path
