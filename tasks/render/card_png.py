"""The asset card as one PNG (matplotlib, Agg): request, three views, drop frames, material and bands, L1, L3 and
where each number came from. Deterministic: no time stamps in the file."""

from __future__ import annotations

import textwrap

from pathlib import Path
from typing import Any

import numpy as np

from tasks.render.card_data import STILL_VIEWS, CardData, DropFrame, Figure
from tasks.render.card_html import verdict_mark
from tasks.render.card_text import band_text, outcome_lines, request_line, si, wrap

FONT_PT = 12.0  # the main text (sans-serif); the technical block is smaller (TECH_PT)
TECH_PT = 8.5
TECH_WRAP = 66  # characters a line of a technical column holds at TECH_PT
CARD_VIEW = "front"  # the drop frames shown on the PNG (the HTML shows both views)
COLOURS = {True: ("#1a7f37", "#eaf7ee"), False: ("#c62828", "#fdecea"), None: ("#666666", "#f3f3f3")}


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
    """A block of the technical section (smaller, sans-serif)."""
    ax.axis("off")
    ax.set_title(title, loc="left", fontsize=TECH_PT + 2, fontweight="bold")
    ax.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", fontsize=TECH_PT, transform=ax.transAxes,
            linespacing=1.25)


def _image(ax: Any, img: np.ndarray | None, title: str) -> None:
    ax.axis("off")
    ax.set_title(title, fontsize=FONT_PT)
    if img is None:
        ax.text(0.5, 0.5, "(no picture)", ha="center", va="center", fontsize=FONT_PT, transform=ax.transAxes)
    else:
        ax.imshow(img, interpolation="antialiased")


def _verdict(ax: Any, stage: str, title: str, passed: bool | None, sentence: str) -> None:
    """One layer's box: its name, a large PASSED / NOT PASSED and one plain sentence."""
    from matplotlib.patches import FancyBboxPatch

    ax.axis("off")
    edge, face = COLOURS[passed]
    ax.add_patch(FancyBboxPatch((0.01, 0.02), 0.98, 0.96, boxstyle="round,pad=0,rounding_size=0.04",
                                transform=ax.transAxes, facecolor=face, edgecolor=edge, linewidth=3))
    ax.text(0.05, 0.9, f"{stage} · {title}", fontsize=FONT_PT, color="#444", va="top", transform=ax.transAxes)
    ax.text(0.05, 0.72, verdict_mark(passed), fontsize=26, fontweight="bold", color=edge, va="top",
            transform=ax.transAxes)
    ax.text(0.05, 0.44, "\n".join(textwrap.wrap(sentence, 45)[:4]), fontsize=FONT_PT - 0.5, va="top",
            transform=ax.transAxes, linespacing=1.2)


def _figure_line(fig: Figure) -> str:
    """'effective modulus  10.4 kPa  in [5 kPa, 19.9 kPa]', or '... not measured: why' (no NaN)."""
    if fig.state == "not measured":
        return f"{fig.label}: not measured" + (f" ({fig.note})" if fig.note else "")
    return f"{fig.label}: {si(fig.value, fig.unit)}" + (f"  {band_text(fig)}" if fig.band else "")


def _material_lines(card: CardData) -> list[str]:
    lines = [line for f in card.material for line in wrap(_figure_line(f), TECH_WRAP, indent="    ")]
    c = card.calibration
    if c is not None:
        lines += wrap(f"calibrated from video {c.video}: E {si(c.prior[0], 'Pa')} -> {si(c.fitted[0], 'Pa')}, "
                      f"viscosity {si(c.prior[1], 'Pa s')} -> {si(c.fitted[1], 'Pa s')} (real beside simulated: "
                      "card.html)", TECH_WRAP, indent="    ")
    lines += ["", "targets (measured on a specimen of the material):"]
    for fig in card.bands:
        lines += wrap(_figure_line(fig), TECH_WRAP, indent="    ")
    return lines


def _l1_lines(card: CardData) -> list[str]:
    lines = [line for f in card.l1 for line in wrap(_figure_line(f), TECH_WRAP, indent="    ")]
    lines += ["", "drop protocol (5 s, 30 fps, clearance H/4):"]
    lines += [line for f in card.protocol for line in wrap(_figure_line(f), TECH_WRAP, indent="    ")]
    return lines


def _l3_lines(card: CardData) -> list[str]:
    l3 = card.l3
    if not l3.ran:
        return wrap(l3.note, TECH_WRAP)
    lines = wrap(f"gripper {l3.gripper}; {l3.status}; trial {l3.trial} of {l3.trials} "
                 "(simulated pick-and-places, numbered from 1)", TECH_WRAP, indent="    ")
    lines += [w for line in outcome_lines(l3.outcome) for w in wrap(line, TECH_WRAP, indent="    ")]
    lines += [f"force budget {si(l3.force_budget_n, 'N')} per finger"]
    lines += [line for f in l3.figures for line in wrap(_figure_line(f), TECH_WRAP, indent="    ")]
    return lines


def _stage_lines(card: CardData) -> list[str]:
    lines = []
    for s in card.stages:
        lines += wrap(s, TECH_WRAP, indent="    ")
    lines += ["", "probes and cache keys: renders/card.html, evidence/attempts.jsonl"]
    return lines


def _force_plot(ax: Any, card: CardData) -> None:
    l3 = card.l3
    if not l3.ran or not l3.force_t_s:
        ax.axis("off")
        ax.text(0.5, 0.5, "\n".join(wrap(l3.note if not l3.ran else "no finger-force record", 40)),
                ha="center", va="center", fontsize=FONT_PT, transform=ax.transAxes)
        ax.set_title("The grasp", fontsize=FONT_PT + 1)
        return
    t = np.asarray(l3.force_t_s)
    f = np.asarray(l3.finger_force_n)
    ax.plot(t, f[:, 0], lw=1.5, label="finger 1")
    ax.plot(t, f[:, 1], lw=1.5, label="finger 2")
    if l3.force_budget_n:
        ax.axhline(l3.force_budget_n, color="0.4", ls="--", lw=1.0, label=f"limit {l3.force_budget_n:.3g} N")
    ax.set_xlabel("time [s]", fontsize=FONT_PT - 1)
    ax.set_ylabel("finger force [N]", fontsize=FONT_PT - 1)
    ax.tick_params(labelsize=FONT_PT - 2)
    ax.legend(fontsize=FONT_PT - 2, loc="upper right")
    ax.set_title(f"The grasp: {l3.gripper}, trial {l3.trial} of {l3.trials}", fontsize=FONT_PT + 1)
    ax.grid(alpha=0.3)


def write_card_png(card: CardData, asset_dir: Path, path: Path) -> Path:
    """Draw the card into path (PNG, 1800 x 1300 px): the request and what was built, PASSED / NOT PASSED per layer,
    the material in plain words, three views and the grasp, the drop frames; then a smaller technical block."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.gridspec import GridSpec

    fig = plt.figure(figsize=(18, 13), dpi=100)
    try:
        gs = GridSpec(5, 12, figure=fig, height_ratios=[0.8, 1.45, 1.95, 1.7, 2.1], hspace=0.36, wspace=0.35,
                      left=0.025, right=0.985, top=0.975, bottom=0.015)
        head = fig.add_subplot(gs[0, :])
        head.axis("off")
        head.text(0.0, 1.0, card.name, fontsize=24, fontweight="bold", va="top", transform=head.transAxes)
        head.text(0.0, 0.55, request_line(card.request), fontsize=FONT_PT + 1, color="#444", va="top",
                  transform=head.transAxes)
        if card.material_words:
            head.text(0.0, 0.22, f"Material: {card.material_words}", fontsize=FONT_PT + 3, fontweight="bold",
                      va="top", transform=head.transAxes)
        if card.analogy:  # built by analogy: said in a box a reader cannot miss
            head.text(0.6, 1.0, "\n".join(textwrap.wrap(card.analogy[0], 62)[:4]), fontsize=FONT_PT, va="top",
                      transform=head.transAxes, bbox={"boxstyle": "round", "facecolor": "#fff6e5", "edgecolor": "#c80",
                                                      "linewidth": 2})
        elif card.built:
            head.text(0.6, 1.0, "\n".join(textwrap.wrap(card.built[:1].upper() + card.built[1:], 50)[:2]),
                      fontsize=FONT_PT + 3, va="top", transform=head.transAxes)
        for i, v in enumerate(card.layers[:4]):
            _verdict(fig.add_subplot(gs[1, 3 * i:3 * i + 3]), v.stage, v.title, v.passed, v.sentence)
        import imageio.v2 as imageio

        for i, view in enumerate([v for v in STILL_VIEWS if v in card.views][:3] or ["front", "side", "top"]):
            rel = card.views.get(view)
            img = np.asarray(imageio.imread(asset_dir / rel))[..., :3] if rel else None
            _image(fig.add_subplot(gs[2, 2 * i:2 * i + 2]), img, view)
        _force_plot(fig.add_subplot(gs[2, 7:12]), card)
        frames = [f for f in card.drop_frames if f.view == CARD_VIEW]
        for i, frame in enumerate(frames[:4]):
            img, t = drop_frame_image(asset_dir, frame)
            _image(fig.add_subplot(gs[3, 3 * i:3 * i + 3]), img, f"dropped on a table: t = {t:.1f} s")
        _text(fig.add_subplot(gs[4, 0:3]), _material_lines(card), "Technical: material (L2)")
        _text(fig.add_subplot(gs[4, 3:6]), _l1_lines(card), "mass and contact (L1)")
        _text(fig.add_subplot(gs[4, 6:9]), _l3_lines(card), "pick and place (L3)")
        _text(fig.add_subplot(gs[4, 9:12]), _stage_lines(card), "stages (harness)")
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=100, metadata={"Software": None})
    finally:
        plt.close(fig)
    return path
