"""The evaluation report: Markdown tables next to the paper's numbers, PNG plots, links to videos and recordings.

Every figure is traceable: `figures.json` lists, per figure, the case ids it aggregates and the record files; each
record (`records/<ablation>/<arm>/<case>.json`) names the cache keys of the probes and the evidence files behind it.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from contracts.evaluation import ARMS, ArmResult, Suite
from tasks.evaluation.metrics import METRICS, Figure, aggregate, direction_ok, meets_target
from tasks.evaluation.paper import PAPER, TARGETS
from tasks.evaluation.vision import RATINGS

TITLES = {"hierarchy": "A. Flat vs Hierarchical", "harness": "B. One-shot vs Harness",
          "manipulation": "C. No feedback vs Full manipulation-guided refinement"}
LABELS = {"delivery": "asset delivery", "physics_pass": "physics-test pass", "sim_calls": "sim calls / asset",
          "target_satisfaction": "target satisfaction (held-out)", "hard_failure": "hard-failure rate",
          "task_success": "task success", "material_pass": "material pass", "joint_success": "joint success"}


def _fmt(metric: str, f: Figure | None) -> str:
    if f is None or f.value is None:
        return "n/a"
    if f.unit == "rate":
        return f"{100 * f.value:.0f} % ({f.k:.0f}/{f.n})"
    return f"{f.value:.1f} (N={f.n})"


def _paper(metric: str, v: float | None) -> str:
    if v is None:
        return "-"
    return f"{v:.0f}" if metric == "sim_calls" else f"{100 * v:.0f} %"


def _target(metric: str) -> str:
    if metric not in TARGETS:
        return "-"
    op, t = TARGETS[metric]
    return f"{op} {t:.0f}" if metric == "sim_calls" else f"{op} {100 * t:.0f} %"


def _table(ablation: str, figs: dict[str, dict[str, Figure]]) -> list[str]:
    base, ours = ARMS[ablation]
    lines = [f"| metric | paper {base} | paper {ours} | ours: {base} | ours: {ours} | target | gap in paper's direction | target met |",
             "|---|---|---|---|---|---|---|---|"]
    for m in METRICS[ablation]:
        fb, fo = figs[base].get(m), figs[ours].get(m)
        pb, po = PAPER[ablation].get(m, (None, None))
        d = None if m == "sim_calls" else direction_ok(m, fb.value if fb else None, fo.value if fo else None)
        t = meets_target(m, fo.value if fo else None)
        lines.append(f"| {LABELS[m]} | {_paper(m, pb)} | {_paper(m, po)} | {_fmt(m, fb)} | {_fmt(m, fo)} | "
                     f"{_target(m)} | {_gap(d, fb, fo)} | "
                     f"{'-' if t is None else ('yes' if t else 'NO')} |")
    return lines


def _gap(ok: bool | None, fb: Figure | None, fo: Figure | None) -> str:
    """'yes' (ours better, as in the paper), 'equal', 'NO' (worse) or '-'."""
    if ok is None:
        return "-"
    if fb is not None and fo is not None and fb.value == fo.value:
        return "equal"
    return "yes" if ok else "NO"


def _plot(ablation: str, figs: dict[str, dict[str, Figure]], path: Path) -> None:
    """Grouped bars: paper baseline / ours, our baseline / ours, per rate metric (95 % Wilson intervals)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    base, ours = ARMS[ablation]
    metrics = [m for m in METRICS[ablation] if m != "sim_calls"]
    fig, ax = plt.subplots(figsize=(7, 4.2))
    w = 0.2
    for i, m in enumerate(metrics):
        pb, po = PAPER[ablation].get(m, (None, None))
        vals: list[tuple[float | None, Figure | None, str, str]] = [
            (pb, None, f"paper {base}", "#bbbbbb"), (po, None, f"paper {ours}", "#777777")]
        for arm, col in ((base, "#e69f00"), (ours, "#0072b2")):
            fig_arm = figs[arm][m]
            vals.append((fig_arm.value, fig_arm, f"ours: {arm}", col))
        for j, (v, f, label, col) in enumerate(vals):
            if v is None:
                continue
            x = i + (j - 1.5) * w
            err = None
            if f is not None and f.low is not None and f.high is not None:
                # a rate of 0 or 1 sits on its Wilson bound up to round-off: clip the arms at 0 (matplotlib refuses < 0)
                err = [[max(0.0, 100 * (v - f.low))], [max(0.0, 100 * (f.high - v))]]
            ax.bar(x, 100 * v, w, color=col, label=label if i == 0 else None, yerr=err, capsize=3)
            if f is not None:
                ax.text(x, 100 * v + 2, f"N={f.n}", ha="center", fontsize=6)
    ax.set_xticks(range(len(metrics)), [LABELS[m] for m in metrics], fontsize=8)
    ax.set_ylabel("%")
    ax.set_ylim(0, 115)
    ax.set_title(TITLES[ablation], fontsize=10)
    ax.legend(fontsize=7, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _sim_plot(records: list[ArmResult], path: Path) -> bool:
    """Construction simulation calls per delivered asset, per arm (A and B)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = [(f"{r.ablation}:{r.arm}", r.sim_calls) for r in records if r.ablation != "manipulation" and r.delivered]
    if not groups:
        return False
    names = sorted({g for g, _ in groups})
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.boxplot([[v for g, v in groups if g == n] for n in names], showmeans=True)
    ax.set_xticks(range(1, len(names) + 1), names)
    ax.axhline(14, color="grey", ls="--", lw=1, label="paper: 14 calls")
    ax.set_ylabel("simulation calls / asset")
    ax.tick_params(axis="x", labelsize=7)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True


def _rel(path: str | None, start: Path) -> str | None:
    return None if not path else os.path.relpath(path, start)


def _case_rows(records: list[ArmResult], report_dir: Path, out: Path) -> list[str]:
    """One line per case and arm: outcome, failures, evidence links (videos, recordings, record)."""
    lines = ["| case | ablation | arm | delivered | physics | targets | hard fail | sim calls | failures | evidence |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(records, key=lambda r: (r.case_id, r.ablation, r.arm)):
        links = [f"[record]({_rel(str(Path(out) / 'records' / r.ablation / r.arm / (r.case_id + '.json')), report_dir)})"]
        if r.asset_dir:
            root = Path(r.asset_dir)
            for f in r.evidence.get("files", []):
                if f.endswith(".mp4"):
                    links.append(f"[{Path(f).stem}]({_rel(str(root / f), report_dir)})")
            for f in r.evidence.get("recordings", [])[:6]:
                links.append(f"[{Path(f).stem}]({_rel(str(root / f), report_dir)})")
        yn = {True: "yes", False: "NO", None: "-"}
        if r.ablation == "manipulation":
            ok = sum(c.task_success for c in r.conditions)
            phys, tgt = f"task {ok}/{len(r.conditions)}", f"material {sum(c.material_pass for c in r.conditions)}/{len(r.conditions)}"
        else:
            phys, tgt = yn[r.physics_pass], yn[r.target_satisfied]
        fails = "; ".join(r.failure_kinds)[:120] or "-"
        lines.append(f"| {r.case_id} | {r.ablation} | {r.arm} | {yn[r.delivered]} | {phys} | {tgt} | "
                     f"{yn[r.hard_failure]} | {r.sim_calls} | {fails} | {' '.join(links)} |")
    return lines


def _shown_path(path: Path) -> str:
    """A suite file as the report names it: relative to the repository when it is one of ours, else as given."""
    root = Path(__file__).resolve().parents[2]
    try:
        return str(Path(path).resolve().relative_to(root))
    except ValueError:
        return str(path)


def write_report(report_dir: Path, records: list[ArmResult], suite: Suite, suite_file: Path, opts: Any,
                 wall_s: float, jobs: list[dict[str, Any]]) -> dict[str, Any]:
    """report.md, plots and figures.json; returns the summary (also the CLI's --json)."""
    report_dir = Path(report_dir)
    report_dir.mkdir(parents=True, exist_ok=True)
    out = report_dir.parent
    figs = aggregate(records)
    md = [f"# DeformSmith evaluation: suite '{suite.name}'", "",
          f"Suite file `{_shown_path(suite_file)}` ({len(suite.cases)} cases); this run: ablations {', '.join(opts.ablations)}, "
          f"quality {opts.quality}, device {opts.device}, {opts.workers} worker(s), "
          f"limit {opts.limit if opts.limit is not None else 'none'}, agents {opts.llm or 'offline rule backend'}. "
          f"Wall time of this invocation: {wall_s:.0f} s (cached work is not re-run).", "",
          "Rates count missing outputs as failures; N is the number of cases (C: asset x condition trials) both arms "
          "ran. Intervals in the plots are Wilson 95 %. Definitions: `tasks/evaluation/` and the README.", ""]
    summary: dict[str, Any] = {"suite": suite.name, "records": len(records), "wall_time_s": wall_s,
                               "figures": {}, "failed_cases": [j for j in jobs if not j.get("ok")]}
    traced: dict[str, Any] = {}
    for ablation in opts.ablations:
        if ablation not in figs:
            md += [f"## {TITLES[ablation]}", "", "No case has records of both arms yet.", ""]
            continue
        md += [f"## {TITLES[ablation]}", "", *_table(ablation, figs[ablation]), ""]
        png = report_dir / f"{ablation}.png"
        _plot(ablation, figs[ablation], png)
        md += [f"![{ablation}]({png.name})", ""]
        summary["figures"][ablation] = {arm: {m: f.as_dict() for m, f in fs.items()} for arm, fs in figs[ablation].items()}
        traced[ablation] = {arm: {m: {"value": f.value, "n": f.n, "cases": f.sources,
                                      "records": sorted({f"records/{ablation}/{arm}/{s.split('#')[0]}.json"
                                                         for s in f.sources})}
                                  for m, f in fs.items()} for arm, fs in figs[ablation].items()}
    if _sim_plot(records, report_dir / "sim_calls.png"):
        md += ["## Simulation calls per delivered asset", "", "![sim calls](sim_calls.png)", ""]
    md += ["## Asset quality: the paper's drop protocol", "",
           "5 s gravity drop from a quarter of the object's height at 30 fps, two views (front / side MP4 links "
           "below). Automated plausibility: shape retention >= 0.8, |volume ratio - 1| <= 0.1, no collapse "
           "(height ratio >= 0.5), no explosion (extent growth <= 2).", ""]
    md += _quality_rows(records)
    md += ["", *_rating_rows(records, opts)]
    md += ["", "## Wall time", "", "Wall time per case and arm as recorded (cache hits make reruns cheaper; the "
           "hierarchical arm includes L0):", "", "| ablation | arm | cases | total [s] | mean per case [s] |",
           "|---|---|---|---|---|"]
    for ablation, arms in ARMS.items():
        for arm in arms:
            ws = [r.wall_s for r in records if r.ablation == ablation and r.arm == arm]
            if ws:
                md.append(f"| {ablation} | {arm} | {len(ws)} | {sum(ws):.0f} | {sum(ws) / len(ws):.0f} |")
    md += ["", "## Per case", "", *_case_rows(records, report_dir, out), ""]
    failed = summary["failed_cases"]
    if failed:
        md += ["## Cases that crashed", ""] + [f"- {j['case']}: {j['error']}" for j in failed] + [""]
    md += ["## Traceability", "", "`figures.json` lists every figure's cases and record files; each record names the "
           "cache keys (`evidence.cache_keys`, `CacheStore(root).get(key)`) and files behind it.", ""]
    (report_dir / "figures.json").write_text(json.dumps(traced, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    (report_dir / "report.md").write_text("\n".join(md) + "\n", encoding="utf-8")
    summary["report"] = str(report_dir / "report.md")
    summary["figures_json"] = str(report_dir / "figures.json")
    return summary


def _rating_rows(records: list[ArmResult], opts: Any) -> list[str]:
    """The vision LLM's 0-1 ratings of our assets' drop videos: the mean per rating, then one row per asset."""
    rated = [r for r in records if r.ablation == "hierarchy" and r.arm == "hierarchical"
             and all(f"rating_{k}" in r.metrics for k in RATINGS)]
    failed = [r for r in records if r.ablation == "hierarchy" and "vision_rating_error" in r.evidence]
    rater = getattr(opts, "vision_llm", None) or getattr(opts, "llm", None)
    lines = ["### Vision-LLM ratings (0-1)", ""]
    if not rated:
        why = (f"{len(failed)} asset(s) could not be rated by {rater}: {failed[0].evidence['vision_rating_error']}"
               if failed else "no vision LLM was configured (`--vision-llm` or `--llm`), or the videos were off")
        return lines + [f"None in this run: {why}.", ""]
    means = {k: sum(r.metrics[f"rating_{k}"] for r in rated) / len(rated) for k in RATINGS}
    lines += [f"Rated by `{rated[0].evidence.get('vision_rating', {}).get('model', rater)}` from "
              f"{rated[0].evidence.get('vision_rating', {}).get('frames_per_view', '?')} frames per view of the front "
              f"and side videos; {len(rated)} asset(s) rated, {len(failed)} not.", "",
              "| rating | mean | N |", "|---|---|---|"]
    lines += [f"| {k.replace('_', ' ')} | {means[k]:.2f} | {len(rated)} |" for k in RATINGS]
    lines += ["", "| case | " + " | ".join(RATINGS) + " | reason |", "|---|" + "---|" * (len(RATINGS) + 1)]
    for r in sorted(rated, key=lambda r: r.case_id):
        why = str(r.evidence.get("vision_rating", {}).get("rationale", "")).replace("|", "/")
        lines.append(f"| {r.case_id} | " + " | ".join(f"{r.metrics[f'rating_{k}']:.2f}" for k in RATINGS)
                     + f" | {why} |")
    return lines + [""]


def _quality_rows(records: list[ArmResult]) -> list[str]:
    """Drop-protocol metrics per delivered asset of A's arms."""
    keys = ("shape_retention", "volume_ratio_end", "body_height_ratio_end", "tilt_deg_end", "max_extent_growth",
            "plausible")
    lines = ["| case | arm | " + " | ".join(keys) + " |", "|---|---|" + "---|" * len(keys)]
    for r in sorted(records, key=lambda r: (r.case_id, r.arm)):
        if r.ablation != "hierarchy" or not r.delivered:
            continue
        vals = [r.metrics.get(f"protocol.{k}") for k in keys]
        lines.append(f"| {r.case_id} | {r.arm} | " + " | ".join("-" if v is None else f"{v:.3g}" for v in vals) + " |")
    return lines
