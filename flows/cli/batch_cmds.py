"""`deformsmith batch REQUESTS.jsonl`: the requests in worker processes, a concurrency limit, one report."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from flows.cli.apps import app, check_device, console, emit_json, fail, results
from tasks.preflight import check_locations
from tasks.batch_requests import REPORT_JSON, REQUESTS_PER_WORKER
from tasks.report.tables import batch_table


@app.command("batch")
def batch(
    requests: Path = typer.Argument(..., help="JSONL file: one AssetRequest per line (+ optional \"name\")"),
    out: Path = typer.Option(Path("out/batch"), "--out", help="batch root: one asset directory per request"),
    concurrency: int = typer.Option(1, "--concurrency", "-j", help="requests running at once (one worker process "
                                    "each)"),
    requests_per_worker: int = typer.Option(REQUESTS_PER_WORKER, "--requests-per-worker", help="requests "
                                            "each worker process serves one after another before a fresh one "
                                            "replaces it (1: a new process for each request)"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda (the MPM's Warp device)"),
    timeout_s: float = typer.Option(None, "--timeout-s", help="kill a request that runs longer than this [s]"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (shared by every request)"),
    as_json: bool = typer.Option(False, "--json", help="print the report as JSON"),
    l3: bool = typer.Option(True, "--l3/--no-l3", help="run L3 (robot pick-and-place validation) in every request"),
    require_l3: bool = typer.Option(False, "--require-l3", help="a request whose L3 does not pass fails (its asset is "
                                    "published all the same)"),
) -> None:
    """Generate many assets; a bad request fails alone; exit 1 if any failed (the report is written anyway)."""
    # lazy: pulls concurrent.futures, ctypes (probe workers); --help imports every command module
    from flows.batch import DEFAULT_JOB, NO_L3_JOB, REQUIRE_L3_JOB, run_batch

    if require_l3 and not l3:
        fail("--require-l3 needs L3: drop --no-l3")
    if concurrency < 1:
        fail(f"--concurrency must be >= 1, got {concurrency}")
    if requests_per_worker < 1:
        fail(f"--requests-per-worker must be >= 1, got {requests_per_worker}")
    check_device(device)
    if not requests.is_file():
        fail(f"requests file not found: {requests}")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    check_locations(out_root=out)  # the batch root and the cache root are usable, before any request runs

    def on_result(r) -> None:
        mark = "[green]ok[/green]" if r.status == "ok" else f"[red]failed[/red]: {r.reason}"
        console.log(f"{r.name} (line {r.line}) {mark} {r.wall_s:.1f} s")

    try:
        with console.status(f"running requests from {requests} ({concurrency} at a time)"):
            report = run_batch(requests, out, concurrency=concurrency, device=device, timeout_s=timeout_s,
                               on_result=on_result, requests_per_worker=requests_per_worker,
                               job=REQUIRE_L3_JOB if require_l3 else DEFAULT_JOB if l3 else NO_L3_JOB)
    except KeyboardInterrupt:  # run_batch stopped the children and wrote the report first
        console.print(f"report (interrupted): {out / REPORT_JSON}")
        raise
    if as_json:
        emit_json(report.model_dump(mode="json"))
    else:
        results.print(batch_table(report))
        results.print(f"report: {Path(report.out_root) / REPORT_JSON}", markup=False, highlight=False)
    if report.failed:
        raise typer.Exit(1)
