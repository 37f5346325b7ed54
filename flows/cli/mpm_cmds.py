"""`deformsmith verify physics`: the analytic MPM suite (the standard-scene benchmark is
`python -m benchmarks.mpm_bench`)."""

from __future__ import annotations

import contextlib
import sys

import typer

from flows.cli.apps import console, emit_json, fail, results, verify_app
from tasks.report.tables import verify_table


@verify_app.command("physics")
def verify_physics(
    json_out: bool = typer.Option(False, "--json", help="print the results as JSON on stdout"),
    quick: bool = typer.Option(False, "--quick", help="reduced-resolution versions of the cases (CI)"),
    device: str = typer.Option("cpu", "--device", help="Warp device: cpu or cuda"),
    case: list[str] = typer.Option(None, "--case", help="run only these cases (repeatable)"),
) -> None:
    """Run the analytic MPM suite: measured / expected / error / tolerance / pass per case (exit 1 on a failure)."""
    if device not in ("cpu", "cuda"):
        fail("--device must be cpu or cuda")
    import warp as wp

    from tasks.mpm.verify import CASES, run_case  # lazy: pulls warp (--help imports every command module)

    names = list(case) if case else list(CASES)
    unknown = [n for n in names if n not in CASES]
    if unknown:
        fail(f"unknown case(s) {', '.join(unknown)}; known: {', '.join(CASES)}")
    cases = []
    with contextlib.redirect_stdout(sys.stderr):  # Warp's own messages must not mix with --json output
        wp.init()
        for name in names:
            console.print(f"[dim]running {name} ({'quick' if quick else 'full'}, {device})...[/dim]")
            cases.extend(run_case(name, quick=quick, device=device))
    all_pass = all(r.passed for r in cases)
    if json_out:
        emit_json({"quick": quick, "device": device, "passed": all_pass, "cases": [r.as_dict() for r in cases]})
    else:
        results.print(verify_table(cases, quick, device))
    if not all_pass:
        raise typer.Exit(1)
