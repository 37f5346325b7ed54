"""Tables and lines of the maintenance and fleet commands' results: the cache's figures (`cache stats`, `cache gc`),
a batch report (`batch`), the analytic MPM suite (`verify physics`), a cross-simulator check (`crosscheck`) and an
evaluation's figures (`eval`). The types are read for annotations only: building a table imports no engine."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.table import Table

from tasks.report.units import human_bytes, local_time

if TYPE_CHECKING:
    from tasks.batch_requests import BatchReport
    from tasks.export.crosscheck import CrosscheckReport
    from tasks.mpm.verify import CaseResult


def empty_cache_stats(root: Path) -> dict[str, Any]:
    """`cache stats` of a default cache root that does not exist yet: a fresh cache is simply empty."""
    return {"root": str(root), "entries": 0, "bytes": 0, "oldest_use": None, "newest_use": None, "tmp_dirs": 0,
            "events": 0, "hits": 0, "misses": 0}


def cache_stats_table(data: dict[str, Any]) -> Table:
    """The cache's figures (cache.store.CacheStore.stats) as a two-column table."""
    table = Table(title=f"cache {data['root']}", show_header=False)
    table.add_row("entries", str(data["entries"]))
    table.add_row("size", human_bytes(data["bytes"]))
    table.add_row("oldest use", local_time(data["oldest_use"]))
    table.add_row("newest use", local_time(data["newest_use"]))
    table.add_row("runs logged", f"{data['events']} ({data['hits']} hits, {data['misses']} executed)")
    table.add_row("temp dirs", str(data["tmp_dirs"]))
    return table


def gc_line(result: dict[str, Any], dead: dict[str, Any]) -> str:
    """What `cache gc` removed: entries (CacheStore.gc) and the temporaries of dead processes."""
    return (f"removed {len(result['removed'])} entries ({human_bytes(result['freed_bytes'])}); "
            f"{result['remaining_entries']} remain ({human_bytes(result['remaining_bytes'])}); "
            f"{len(dead['removed'])} temporaries of dead processes removed ({human_bytes(dead['freed_bytes'])})")


def batch_table(report: BatchReport) -> Table:
    """One row per request of a batch report, its totals and throughput in the title."""
    table = Table(title=f"batch: {report.ok} ok, {report.failed} failed, {report.wall_s:.1f} s, "
                        f"{report.assets_per_hour:.1f} assets/hour")
    for col in ("line", "name", "status", "wall [s]", "executed/cached", "reason"):
        table.add_column(col)
    for r in report.results:
        counts = "-" if r.tasks_executed is None else f"{r.tasks_executed}/{r.tasks_cached}"
        table.add_row(str(r.line), r.name, "ok" if r.status == "ok" else "[red]failed[/red]", f"{r.wall_s:.1f}",
                      counts, (r.reason or "")[:100])
    return table


def verify_table(cases: list[CaseResult], quick: bool, device: str) -> Table:
    """The analytic MPM suite: measured / expected / error / tolerance / pass per case."""
    table = Table(title=f"MPM analytic suite ({'quick' if quick else 'full'}, {device})")
    for col in ("case", "measured", "expected", "error", "tolerance", "units", "pass", "s"):
        table.add_column(col)
    for r in cases:
        err = f"{r.error:.3g}" + (" (rel)" if r.error_kind == "relative" else " (abs)")
        table.add_row(r.name, f"{r.measured:.5g}", f"{r.expected:.5g}", err, f"{r.tolerance:g}", r.units,
                      "[green]PASS[/green]" if r.passed else "[red]FAIL[/red]", f"{r.seconds:.1f}")
    return table


def _fmt(v: float | None) -> str:
    return "-" if v is None else f"{v:.4g}"


def _pct(v: float | None) -> str:
    return "-" if v is None else f"{100 * v:.1f}%"


def crosscheck_lines(report: CrosscheckReport) -> list[str]:
    """A crosscheck report as aligned text: each metric, ours beside the simulator's before and after calibration."""
    lines = [f"{report.sim} crosscheck of {report.asset} (strain {report.probes['strain']}, drop height "
             f"fraction {report.probes['height_fraction']})",
             f"{'metric':24s} {'DeformSmith':>12s} {report.sim:>12s} {'err':>7s} {'calibrated':>12s} {'err':>7s}"]
    for name, row in report.metrics.items():
        lines.append(f"{name:24s} {_fmt(row.ours):>12s} {_fmt(row.theirs):>12s} {_pct(row.rel_error):>7s} "
                     f"{_fmt(row.theirs_calibrated):>12s} {_pct(row.rel_error_calibrated):>7s}")
    if report.calibration:
        lines.append(f"calibrated parameters: {report.calibration['parameters']}")
        lines.append(f"modulus and rebound within {100 * report.agree_within:.0f} %: {report.agrees}")
    lines.append(f"{report.sim_calls} simulations, {report.wall_time_s:.1f} s")
    return lines


def eval_figure_lines(figures: dict[str, dict[str, dict[str, dict[str, Any]]]]) -> list[str]:
    """'<ablation> / <arm>: metric=value (N=n), ...' per arm of an evaluation's figures (rates in per cent)."""
    lines = []
    for abl, arms in figures.items():
        for arm, figs in arms.items():
            parts = []
            for m, f in figs.items():
                if f["value"] is None:
                    continue
                parts.append(f"{m}={100 * f['value']:.0f}% (N={f['n']})" if f["unit"] == "rate"
                             else f"{m}={f['value']:.1f} (N={f['n']})")
            lines.append(f"{abl} / {arm}: " + ", ".join(parts))
    return lines
