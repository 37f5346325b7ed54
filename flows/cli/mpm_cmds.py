"""`deformsmith verify physics` (analytic MPM suite) and `deformsmith bench mpm` (standard-scene benchmark)."""

from __future__ import annotations

import contextlib
import sys

import typer

from flows.cli.apps import bench_app, console, emit_json, fail, results, verify_app


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

    from tasks.mpm.verify import CASES, run_case

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
        from rich.table import Table

        table = Table(title=f"MPM analytic suite ({'quick' if quick else 'full'}, {device})")
        for col in ("case", "measured", "expected", "error", "tolerance", "units", "pass", "s"):
            table.add_column(col)
        for r in cases:
            err = f"{r.error:.3g}" + (" (rel)" if r.error_kind == "relative" else " (abs)")
            table.add_row(r.name, f"{r.measured:.5g}", f"{r.expected:.5g}", err, f"{r.tolerance:g}", r.units,
                          "[green]PASS[/green]" if r.passed else "[red]FAIL[/red]", f"{r.seconds:.1f}")
        results.print(table)
    if not all_pass:
        raise typer.Exit(1)


@bench_app.command("mpm")
def bench_mpm(
    device: str = typer.Option("cpu", "--device", help="Warp device: cpu or cuda"),
    particles: int = typer.Option(64000, "--particles", help="particles per scene (rounded to n^3)"),
    steps: int = typer.Option(200, "--steps", help="timed steps"),
    batch: int = typer.Option(1, "--batch", help="independent scenes advanced together"),
    workers: int = typer.Option(0, "--workers", help="CPU threads sharing the batch (0 = one per core)"),
    cpu_threads: int = typer.Option(1, "--cpu-threads", help="CPU: threads sharing each rollout's particles"),
    compare_sequential: bool = typer.Option(
        False, "--compare-sequential",
        help="also run the batch's scenes one after another in this process and print both ratios"),
    json_out: bool = typer.Option(False, "--json", help="print the figures as JSON on stdout"),
    kernel: list[str] = typer.Option(
        None, "--kernel", help="engine kernel option name=value (contracts.sim.KernelOptions; repeatable)"),
) -> None:
    """Benchmark the MPM step on the standard cube scene (warm-up/compile excluded from the timing)."""
    if device not in ("cpu", "cuda"):
        fail("--device must be cpu or cuda")
    if particles < 8 or steps < 1 or batch < 1 or workers < 0 or not 1 <= cpu_threads <= 64:
        fail("need --particles >= 8, --steps >= 1, --batch >= 1, --workers >= 0, 1 <= --cpu-threads <= 64")
    if compare_sequential and batch < 2:
        fail("--compare-sequential needs --batch >= 2")
    from contracts.sim import KernelOptions

    try:
        options = KernelOptions.from_assignments(kernel or [])
    except ValueError as exc:
        fail(f"--kernel: {exc}")
    from tasks.mpm.bench import run_bench

    with contextlib.redirect_stdout(sys.stderr):  # Warp's own messages must not mix with --json output
        res = run_bench(device=device, particles=particles, steps=steps, batch=batch, workers=workers or None,
                        cpu_threads=cpu_threads, compare_sequential=compare_sequential, kernel=options)
    if json_out:
        emit_json(res)
    else:
        for k in ("device_name", "particles", "batch", "workers", "cpu_threads", "steps", "seconds", "us_per_step",
                  "particle_steps_per_s", "peak_memory_bytes", "finite"):
            results.print(f"{k:>22}: {res[k]}")
        cmp = res["sequential_comparison"]
        if cmp:
            results.print(f"{'one after another':>22}: {cmp['sequential_us_per_step']:.2f} us/step "
                          f"(batch {cmp['batch_us_per_step']:.2f}): {cmp['ratio_per_step']:.2f}x per step; "
                          f"whole rollouts {cmp['sequential_rollouts_s']:.3f} s vs {cmp['batch_rollout_s']:.3f} s: "
                          f"{cmp['ratio_end_to_end']:.2f}x end to end")
        results.print(f"[dim]{res['note']}[/dim]")
