"""`deformsmith bench realworld`: everyday objects with published measurements, built from their plain names through
L2 (draft), our mass, modulus and rule-drop rebound beside each measurement (flows.realworld)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import cast

import typer

from cache import use_cache_root
from contracts.errors import DeformSmithError
from contracts.sim import Device
from contracts.realworld import REALWORLD_YAML, ObjectReport, RealWorldReport, load_realworld
from flows.cli.apps import bench_app, check_device, console, emit_report, fail
from tasks.preflight import check_locations
from tasks.publish import write_text_atomic
from tasks.realworld.compare import select_objects

REPORT_JSON = "realworld_report.json"


def _line(r: ObjectReport) -> str:
    """One object's comparisons on one line."""
    if r.status != "ok":
        return f"{r.name}: FAILED {r.error}"
    parts = []
    for c in r.comparisons:
        mark = "ok" if c.passed else ("-" if c.passed is None else "MISS")
        ours = "n/a" if c.ours is None else f"{c.ours:.3g}"
        parts.append(f"{c.quantity} {ours} vs [{c.measured.low:.3g}, {c.measured.high:.3g}] {mark}")
    concept = "" if r.ours.concept == r.expected_concept else f" (built {r.ours.concept}, expected {r.expected_concept})"
    return f"{r.name}{concept}: " + "; ".join(parts)


def summary_lines(report: RealWorldReport) -> list[str]:
    """The report as text lines."""
    s = report.summary
    return [_line(r) for r in report.objects] + [
        f"built {s.built}/{s.objects}, lexicon concept as expected {s.concept_matches}/{s.objects}",
        f"Young's modulus within 2x: {s.modulus_within_2x}/{s.modulus_measured}; mass within 2x: "
        f"{s.mass_within_2x}/{s.mass_measured}; rebound in the rule's band: {s.rebound_in_band}/{s.rule_balls}"
        + ("" if report.simulated else " (--priors-only: no MPM, no rebound)")]


@bench_app.command("realworld")
def realworld(
    only: list[str] = typer.Option(None, "--only", help="an object of the set by its name (repeatable)"),
    limit: int = typer.Option(None, "--limit", help="the first N objects (after --only)"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda"),
    priors_only: bool = typer.Option(False, "--priors-only", help="L0, L1 and L2's priors only (no MPM, no rebound): "
                                     "seconds per object"),
    data: Path = typer.Option(REALWORLD_YAML, "--data", help="the validation set (YAML, contracts/realworld.py)"),
    out: Path = typer.Option(Path("out/realworld"), "--out", help="the objects' asset directories and the report "
                             f"({REPORT_JSON})"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default OUT/_cache)"),
    as_json: bool = typer.Option(False, "--json", help="print the report as JSON"),
    hollow_shell: bool = typer.Option(False, "--hollow-shell", help="a hollow ball's particles as its wall, its gas "
                                      "as an added wall modulus where the lexicon records a pressure (default solid)"),
) -> None:
    """Everyday soft objects with published measurements (Young's modulus, mass, regulation-ball rebound) built from
    their plain names through L2 at draft; our mass, E, effective modulus and rule-drop rebound beside each. Exit 0
    when the run finished (objects that failed to build are in the report)."""
    # lazy: pulls the layers' flows, Warp and pybullet; --help imports every command module
    from flows.realworld import run_realworld

    check_device(device)
    if limit is not None and limit < 1:
        fail(f"--limit must be >= 1, got {limit}")
    if not data.is_file():
        fail(f"validation set not found: {data}")
    try:
        objects = select_objects(load_realworld(data).objects, only, limit)
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    except ValueError as exc:  # pydantic's ValidationError: a malformed set
        fail(f"{data}: {exc}")
    use_cache_root(cache_dir or out / "_cache")
    check_locations(out_root=out)

    def on_result(r: ObjectReport) -> None:
        console.log(_line(r) + f" ({r.wall_s:.1f} s)")

    with console.status(f"{len(objects)} objects on {device}"):
        report = run_realworld(objects, out, cast("Device", device), priors_only, on_result, hollow_shell)
    write_text_atomic(out / REPORT_JSON, json.dumps(report.model_dump(mode="json"), indent=2) + "\n")
    emit_report(report.model_dump(mode="json"), summary_lines(report), out / REPORT_JSON, as_json)
