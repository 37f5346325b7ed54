"""The asset card as one HTML page next to the renders (renders/card.html): the card's figures as tables, the stills
and drop frames as images and the videos in <video> tags, all by relative paths. No scripts, no time stamps."""

from __future__ import annotations

import html
import os
from pathlib import Path

from tasks.render.card_data import CardData, Figure
from tasks.render.card_text import band_text, outcome_lines, request_line, si

STYLE = ("body{font-family:sans-serif;max-width:1320px;margin:1em auto;color:#222}"
         "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;font-size:90%}"
         "th{background:#eee;text-align:left}.miss{color:#b00;font-weight:bold}.key{font-family:monospace}"
         "video,img.still{max-width:640px;width:100%}img.frame{width:24%}figure{display:inline-block;margin:4px}"
         ".analogy{border:2px solid #c80;background:#fff6e5;padding:6px 10px;margin:.5em 0}")


def _rel(asset_rel: str) -> str:
    """A path relative to the asset, as seen from renders/card.html."""
    return Path(os.path.relpath(asset_rel, "renders")).as_posix()


def _table(figures: list[Figure]) -> str:
    rows = ["<table><tr><th>figure</th><th>value</th><th>target band</th><th>from</th><th>cache key</th></tr>"]
    for f in figures:
        band = band_text(f)
        cls = ' class="miss"' if f.band is not None and not f.met else ""
        rows.append(f"<tr><td>{html.escape(f.label)}</td><td>{html.escape(si(f.value, f.unit))}</td>"
                    f"<td{cls}>{html.escape(band)}</td><td>{html.escape(f.source)}</td>"
                    f"<td class=\"key\" title=\"{html.escape(f.key or '')}\">{html.escape((f.key or '-')[:12])}</td>"
                    "</tr>")
    return "\n".join([*rows, "</table>"])


def force_svg(card: CardData, width: int = 640, height: int = 220) -> str:
    """The finger-force curve as an inline SVG (|force| on each finger against time, the budget dashed)."""
    t, f = card.l3.force_t_s, card.l3.finger_force_n
    if not t or not f:
        return "<p>(no finger-force record)</p>"
    pad = 40
    top = max([*(max(a, b) for a, b in f), card.l3.force_budget_n or 0.0, 1e-9]) * 1.05
    t0, t1 = t[0], max(t[-1], t[0] + 1e-9)

    def xy(ti: float, fi: float) -> str:
        return f"{pad + (ti - t0) / (t1 - t0) * (width - 2 * pad):.1f},{height - pad - fi / top * (height - 2 * pad):.1f}"

    lines = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-size="11">',
             f'<rect x="{pad}" y="{pad}" width="{width - 2 * pad}" height="{height - 2 * pad}" fill="none" '
             'stroke="#999"/>']
    for finger, colour in ((0, "#1f77b4"), (1, "#ff7f0e")):
        pts = " ".join(xy(ti, fi[finger]) for ti, fi in zip(t, f))
        lines.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.2" points="{pts}"/>')
    if card.l3.force_budget_n:
        y = xy(t0, card.l3.force_budget_n).split(",")[1]
        lines.append(f'<line x1="{pad}" x2="{width - pad}" y1="{y}" y2="{y}" stroke="#666" stroke-dasharray="4"/>')
    budget = f", dashed: budget {card.l3.force_budget_n:.3g} N" if card.l3.force_budget_n else ""
    lines += [f'<text x="{pad}" y="{pad - 6}">finger force [N] (blue: finger 1, orange: finger 2{budget}); '
              f'axis top {top:.3g} N</text>',
              f'<text x="{pad}" y="{height - pad + 16}">{t0:.2f} s</text>',
              f'<text x="{width - pad}" y="{height - pad + 16}" text-anchor="end">{t1:.2f} s (time)</text>', "</svg>"]
    return "\n".join(lines)


def card_html(card: CardData) -> str:
    """The page."""
    e = html.escape
    parts = ["<!DOCTYPE html>", "<html><head><meta charset=\"utf-8\">",
             f"<title>DeformSmith asset card: {e(card.name)}</title><style>{STYLE}</style></head><body>",
             f"<h1>Asset card: {e(card.name)}</h1>", f"<p>{e(request_line(card.request))}</p>",
             *([f"<p>{e(card.built)}</p>"] if card.built else []),
             *([f'<div class="analogy"><b>{e(card.analogy[0])}</b><ul>'
                + "".join(f"<li>{e(s)}</li>" for s in card.analogy[1:]) + "</ul></div>"] if card.analogy else []),
             "<ul>" + "".join(f"<li>{e(s)}</li>" for s in card.stages) + "</ul>",
             '<p><a href="card.png">card.png</a> (the same card as one picture)</p>', "<h2>Views (L0)</h2>"]
    parts += [f'<figure><img class="still" style="max-width:400px" src="{e(_rel(rel))}" alt="{e(view)}">'
              f"<figcaption>{e(view)}</figcaption></figure>" for view, rel in card.views.items()]
    parts.append("<h2>Videos</h2>")
    parts += [f'<figure><video controls muted loop playsinline preload="metadata" src="{e(_rel(rel))}"></video>'
              f"<figcaption>{e(label)}</figcaption></figure>" for label, rel in card.videos.items()]
    parts.append("<h2>Drop protocol frames (5 s at 30 fps from a clearance of a quarter of the height)</h2>")
    for view in dict.fromkeys(f.view for f in card.drop_frames):
        frames = [f for f in card.drop_frames if f.view == view and f.still]
        if frames:
            parts.append(f"<p>{e(view)} view: " + "".join(
                f'<img class="frame" src="{e(_rel(f.still or ""))}" alt="t = {f.t_s:.1f} s" '
                f'title="t = {f.t_s:.1f} s">' for f in frames) + "</p>")
        else:
            parts.append(f"<p>{e(view)} view: no drop frames stored (older asset): see the video above.</p>")
    parts += ["<h2>L2 material</h2>", _table(card.material), "<h3>Target bands and measured values</h3>",
              _table(card.bands), "<h2>L1 mass and contact</h2>", _table(card.l1),
              "<h2>Drop protocol</h2>", _table(card.protocol), "<h2>L3 pick and place</h2>"]
    l3 = card.l3
    if not l3.ran:
        parts.append(f"<p>{e(l3.note)}</p>")
    else:
        parts += [f"<p>gripper <b>{e(str(l3.gripper))}</b>: {e(l3.gripper_reason or '')}</p>",
                  f"<p>{'passed' if l3.passed else 'did not pass'} ({e(str(l3.status))}), trial {l3.attempt}: "
                  f"{e(l3.note)}</p>", "<p>" + e("; ".join(outcome_lines(l3.outcome))) + "</p>",
                  f"<p>force budget {e(si(l3.force_budget_n, 'N'))} per finger</p>", force_svg(card),
                  _table(l3.figures)]
    parts += ["<h2>Where the numbers came from</h2>",
              "<p>Cache keys (<code>CacheStore(root).get(key)</code>); records: asset.json, physical.json, "
              "material.json, manipulation.json, evidence/attempts.jsonl.</p>",
              "<ul class=\"key\">" + "".join(f"<li>{e(s)}</li>" for s in card.sources) + "</ul>",
              "</body></html>", ""]
    return "\n".join(parts)
