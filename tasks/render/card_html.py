"""The asset card as one HTML page next to the renders (renders/card.html): the card's figures as tables, the stills
and drop frames as images and the videos in <video> tags, all by relative paths. No scripts, no time stamps."""

from __future__ import annotations

import html
import os
from pathlib import Path

from tasks.render.card_calibration import CalibrationCard
from tasks.render.card_data import CardData, Figure
from tasks.render.card_text import band_text, outcome_lines, request_line, si, state_text

STYLE = ("body{font-family:system-ui,-apple-system,'Segoe UI',Helvetica,Arial,sans-serif;font-size:18px;"
         "line-height:1.45;max-width:1320px;margin:1em auto;padding:0 1em;color:#1d1d1d}"
         "h1{font-size:32px;margin:.3em 0}h2{font-size:24px;margin-top:1.4em}h3{font-size:20px}"
         ".request{font-size:20px;color:#444}"
         ".verdicts{display:grid;grid-template-columns:repeat(4,1fr);gap:12px;margin:1em 0}"
         ".verdict{border-radius:10px;padding:12px 14px;border:3px solid}"
         ".verdict.pass{border-color:#1a7f37;background:#eaf7ee}.verdict.fail{border-color:#c62828;background:#fdecea}"
         ".verdict.none{border-color:#999;background:#f3f3f3}"
         ".mark{font-size:30px;font-weight:800;letter-spacing:.02em}.pass .mark{color:#1a7f37}"
         ".fail .mark{color:#c62828}.none .mark{color:#666}.layer{font-size:16px;color:#555}"
         ".material{font-size:22px;font-weight:600}"
         "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:4px 8px;font-size:16px}"
         "th{background:#eee;text-align:left}.miss{color:#b00;font-weight:bold}.unmeasured{color:#8a5a00}"
         ".key{font-family:monospace;font-size:14px}.technical{border-top:3px solid #ccc;margin-top:2em}"
         "video,img.still{max-width:640px;width:100%}img.calibration{max-width:100%}img.frame{width:24%}figure{display:inline-block;margin:4px}"
         "figcaption{font-size:16px;color:#444}"
         ".analogy{border:3px solid #c80;background:#fff6e5;padding:8px 12px;margin:.6em 0;font-size:18px}")

PASSED, NOT_PASSED, NOT_RUN = "PASSED", "NOT PASSED", "NOT RUN"


def _rel(asset_rel: str) -> str:
    """A path relative to the asset, as seen from renders/card.html."""
    return Path(os.path.relpath(asset_rel, "renders")).as_posix()


def _table(figures: list[Figure]) -> str:
    rows = ["<table><tr><th>figure</th><th>value</th><th>target band</th><th>state</th><th>from</th>"
            "<th>cache key</th></tr>"]
    for f in figures:
        band = band_text(f)
        cls = {"measured outside": ' class="miss"', "not measured": ' class="unmeasured"'}.get(f.state, "")
        rows.append(f"<tr><td>{html.escape(f.label)}</td><td>{html.escape(si(f.value, f.unit))}</td>"
                    f"<td>{html.escape(band)}</td><td{cls}>{html.escape(state_text(f))}</td>"
                    f"<td>{html.escape(f.source)}</td>"
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

    lines = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-size="14">',
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


def _ratio(v: float | None) -> str:
    """A residual as a signed percentage, '-' when there is none."""
    return "-" if v is None else f"{100 * v:+.1f} %"


def calibration_html(c: CalibrationCard) -> list[str]:
    """The calibration section: the real clip beside the simulated one, the fitted material beside the prior, the
    metrics with the fit's residuals, the checks and the limits."""
    e = html.escape
    parts = ["<h2>Calibrated from a video of the real object</h2>",
             f"<p>Clip <b>{e(c.video)}</b>: Young's modulus {e(si(c.prior[0], 'Pa'))} &rarr; "
             f"<b>{e(si(c.fitted[0], 'Pa'))}</b> (from {e(c.youngs_modulus_source.replace('_', ' '))}); viscosity "
             f"{e(si(c.prior[1], 'Pa s'))} &rarr; <b>{e(si(c.fitted[1], 'Pa s'))}</b> (from "
             f"{e(c.viscosity_source.replace('_', ' '))}); the fit {'converged' if c.converged else 'did not converge'}."
             "</p>"]
    if c.image:
        parts.append(f'<figure><img class="calibration" src="{e(_rel(c.image))}" alt="real clip above, simulated '
                     f'drop below"><figcaption>top: the real clip; bottom: the fitted material simulated from the same '
                     f'release ({e("; ".join(c.frames))})</figcaption></figure>')
    else:
        parts.append("<p>(no side-by-side frames stored)</p>")
    rows = ["<table><tr><th>metric</th><th>video</th><th>simulated</th><th>residual</th><th>note</th></tr>"]
    for r in c.rows:
        rows.append(f"<tr><td>{e(r.label)}</td><td>{e(si(r.video, r.unit))}</td><td>{e(si(r.simulated, r.unit))}</td>"
                    f"<td>{e(_ratio(r.residual))}</td><td>{e(r.note or '')}</td></tr>")
    parts += [*rows, "</table>", "<h3>Checks before it was published</h3>",
              "<ul>" + "".join(f"<li>{e(s)}</li>" for s in c.checks) + "</ul>",
              "<h3>Limits of the video's evidence</h3>",
              "<ul>" + "".join(f"<li>{e(s)}</li>" for s in c.limits) + "</ul>",
              f"<p>record: {e(c.record)}</p>"]
    return parts


def verdict_mark(passed: bool | None) -> str:
    """PASSED / NOT PASSED / NOT RUN."""
    return NOT_RUN if passed is None else (PASSED if passed else NOT_PASSED)


def _verdicts(card: CardData) -> str:
    e = html.escape
    boxes = []
    for v in card.layers:
        cls = "none" if v.passed is None else ("pass" if v.passed else "fail")
        boxes.append(f'<div class="verdict {cls}"><div class="layer">{e(v.stage)} · {e(v.title)}</div>'
                     f'<div class="mark">{verdict_mark(v.passed)}</div><div>{e(v.sentence)}</div></div>')
    return '<div class="verdicts">' + "".join(boxes) + "</div>"


def card_html(card: CardData) -> str:
    """The page: first what a reader needs (the request, what was built, PASSED / NOT PASSED per layer, the material
    in plain words, the views, the drop and the grasp), then the technical details (probes, cache keys, records)."""
    e = html.escape
    parts = ["<!DOCTYPE html>", "<html><head><meta charset=\"utf-8\">",
             f"<title>DeformSmith asset card: {e(card.name)}</title><style>{STYLE}</style></head><body>",
             f"<h1>Asset card: {e(card.name)}</h1>", f'<p class="request">{e(request_line(card.request))}</p>',
             *([f"<p><b>{e(card.built)}</b></p>"] if card.built and not card.analogy else []),
             *([f'<div class="analogy"><b>{e(card.analogy[0])}</b><ul>'
                + "".join(f"<li>{e(s)}</li>" for s in card.analogy[1:]) + "</ul></div>"] if card.analogy else []),
             _verdicts(card)]
    if card.material_words:
        parts.append(f'<p class="material">Material: {e(card.material_words)}</p>')
    parts.append("<h2>What it looks like</h2>")
    parts += [f'<figure><img class="still" style="max-width:400px" src="{e(_rel(rel))}" alt="{e(view)}">'
              f"<figcaption>{e(view)}</figcaption></figure>" for view, rel in card.views.items()]
    parts.append("<h2>Dropped on a table (5 s)</h2>")
    for view in dict.fromkeys(f.view for f in card.drop_frames):
        frames = [f for f in card.drop_frames if f.view == view and f.still]
        if frames:
            parts.append(f"<p>{e(view)} view: " + "".join(
                f'<img class="frame" src="{e(_rel(f.still or ""))}" alt="t = {f.t_s:.1f} s" '
                f'title="t = {f.t_s:.1f} s">' for f in frames) + "</p>")
        else:
            parts.append(f"<p>{e(view)} view: no drop frames stored (older asset): see the video below.</p>")
    parts += [f'<figure><video controls muted loop playsinline preload="metadata" src="{e(_rel(rel))}"></video>'
              f"<figcaption>{e(label)}</figcaption></figure>" for label, rel in card.videos.items()]
    if card.calibration is not None:
        parts += calibration_html(card.calibration)
    parts.append("<h2>The grasp</h2>")
    l3 = card.l3
    if not l3.ran:
        parts.append(f"<p>{e(l3.note)}</p>")
    else:
        trial = f"trial {l3.trial} of {l3.trials}" if l3.trial is not None else f"{l3.trials} trial(s)"
        parts += [f"<p>Gripper <b>{e(str(l3.gripper))}</b>; {e(trial)}: "
                  f"{'picked, carried and placed' if l3.passed else 'not passed: ' + e(l3.note)}.</p>",
                  force_svg(card)]
    parts += ['<section class="technical"><h2>Technical details</h2>',
              "<h3>Stages (harness)</h3>", "<ul>" + "".join(f"<li>{e(s)}</li>" for s in card.stages) + "</ul>",
              '<p><a href="card.png">card.png</a> (the same card as one picture)</p>',
              "<h3>L2 material</h3>", _table(card.material), "<h3>Target bands and measured values</h3>",
              _table(card.bands), "<h3>L1 mass and contact</h3>", _table(card.l1),
              "<h3>Drop protocol (5 s at 30 fps from a clearance of a quarter of the height)</h3>",
              _table(card.protocol), "<h3>L3 pick and place</h3>"]
    if not l3.ran:
        parts.append(f"<p>{e(l3.note)}</p>")
    else:
        parts += [f"<p>gripper <b>{e(str(l3.gripper))}</b>: {e(l3.gripper_reason or '')}</p>",
                  *([f"<p>grasp: {e(l3.grasp_reason)}</p>"] if l3.grasp_reason else []),
                  f"<p>{'passed' if l3.passed else 'did not pass'} ({e(str(l3.status))}), trial {l3.trial} "
                  f"({e(l3.data or 'no states stored')}): {e(l3.note)}</p>",
                  *([f"<p>{e(l3.others)}</p>"] if l3.others else []),
                  "<p>" + e("; ".join(outcome_lines(l3.outcome))) + "</p>",
                  f"<p>force budget {e(si(l3.force_budget_n, 'N'))} per finger</p>", _table(l3.figures)]
    parts += ["<h3>Where the numbers came from</h3>",
              "<p>Cache keys (<code>CacheStore(root).get(key)</code>); records: asset.json, physical.json, "
              "material.json, manipulation.json, evidence/attempts.jsonl.</p>",
              "<ul class=\"key\">" + "".join(f"<li>{e(s)}</li>" for s in card.sources) + "</ul>",
              "</section></body></html>", ""]
    return "\n".join(parts)
