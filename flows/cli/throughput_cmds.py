"""`deformsmith bench throughput REQUESTS.jsonl`: distinct requests end to end, assets per hour and where the time,
memory and bytes go (flows.throughput; the report is tasks.throughput.report's)."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from contracts.errors import DeformSmithError
from flows.cli.apps import bench_app, check_device, console, emit_report, fail
from tasks.batch_requests import REQUESTS_PER_WORKER
from tasks.preflight import check_locations
from tasks.throughput.ledger import DIR, benchmark_items
from tasks.throughput.report import REPORT_JSON, summary_lines
from tasks.throughput.samplers import list_gpus


def pick_gpus(gpus: int) -> list[str]:
    """The first `gpus` GPUs this process may use (CUDA_VISIBLE_DEVICES, else nvidia-smi's indices, else 0..N-1);
    exit 2 when fewer are there."""
    known = list_gpus()
    if known is None:
        return [str(i) for i in range(gpus)]
    if gpus > len(known):
        fail(f"--gpus {gpus}: only {len(known)} GPU(s) here ({', '.join(known) or 'none'})")
    return known[:gpus]


@bench_app.command("throughput")
def throughput(
    requests: Path = typer.Argument(..., help="JSONL file: one AssetRequest per line (+ optional \"name\"), each "
                                    "distinct (benchmarks/throughput_requests.jsonl: 120 over the lexicon)"),
    gpus: int = typer.Option(None, "--gpus", help="run on this many GPUs (--device cuda), --workers-per-gpu workers "
                             "pinned to each (CUDA_VISIBLE_DEVICES, round robin); default: the CPU"),
    workers_per_gpu: int = typer.Option(None, "--workers-per-gpu", help="request processes at once on each GPU "
                                        "(default 1)"),
    concurrency: int = typer.Option(1, "--concurrency", "-j", help="on the CPU (no --gpus): requests at once"),
    requests_per_worker: int = typer.Option(REQUESTS_PER_WORKER, "--requests-per-worker", help="requests "
                                            "each worker process serves one after another before a fresh one "
                                            "replaces it (1: a new process for each request)"),
    out: Path = typer.Option(Path("out/throughput"), "--out", help="root of the assets, the logs, the run's records "
                             f"({DIR}/) and the report ({REPORT_JSON}); a rerun with the same --out resumes"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default OUT/_cache: a new --out runs cold, "
                                   "a resumed one reuses what the killed run finished)"),
    l3: bool = typer.Option(True, "--l3/--no-l3", help="run L3 (robot pick-and-place) in every request"),
    limit: int = typer.Option(None, "--limit", help="run only the file's first N requests"),
    timeout_s: float = typer.Option(None, "--timeout-s", help="kill a request that runs longer than this many seconds"),
    as_json: bool = typer.Option(False, "--json", help="print the report as JSON"),
) -> None:
    """Throughput of the real job: distinct draft requests end to end (L0-L3, renders, card), reported as distinct
    assets per hour, per-stage time shares, GPU utilisation and memory, workers' peak memory, bytes per asset and
    failures by reason. Exit 0 when the run finished (failed requests are in the report)."""
    # lazy: pulls flows.batch and its process handling; --help imports every command module
    from flows.throughput import run_throughput

    if gpus is not None and gpus < 1:
        fail(f"--gpus must be >= 1, got {gpus} (leave it out to run on the CPU)")
    if workers_per_gpu is not None and gpus is None:
        fail("--workers-per-gpu needs --gpus (on the CPU, --concurrency sets the workers)")
    if workers_per_gpu is not None and workers_per_gpu < 1:
        fail(f"--workers-per-gpu must be >= 1, got {workers_per_gpu}")
    if gpus is not None and concurrency != 1:
        fail("--concurrency is for the CPU: with --gpus, the workers are --gpus x --workers-per-gpu")
    if concurrency < 1:
        fail(f"--concurrency must be >= 1, got {concurrency}")
    if requests_per_worker < 1:
        fail(f"--requests-per-worker must be >= 1, got {requests_per_worker}")
    if limit is not None and limit < 1:
        fail(f"--limit must be >= 1, got {limit}")
    if not requests.is_file():
        fail(f"requests file not found: {requests}")
    try:
        n = len(benchmark_items(requests, limit))
    except DeformSmithError as exc:
        fail(str(exc), exc.exit_code)
    gpu_ids = None
    if gpus is not None:
        gpu_ids = pick_gpus(gpus)
        check_device("cuda")
    use_cache_root(cache_dir or out / "_cache")
    check_locations(out_root=out)

    def on_result(r) -> None:
        mark = "[green]ok[/green]" if r.status == "ok" else f"[red]failed[/red]: {r.reason}"
        console.log(f"{r.name} (line {r.line}) {mark} {r.wall_s:.1f} s")

    where = f"{len(gpu_ids)} GPU(s), {workers_per_gpu or 1} per GPU" if gpu_ids else f"the CPU, {concurrency} at a time"
    try:
        with console.status(f"{n} requests from {requests} on {where}"):
            report = run_throughput(requests, out, gpus=gpu_ids, workers_per_gpu=workers_per_gpu or 1,
                                    concurrency=concurrency, l3=l3, limit=limit, timeout_s=timeout_s,
                                    on_result=on_result, requests_per_worker=requests_per_worker)
    except KeyboardInterrupt:  # what finished is recorded: the same command resumes
        console.print(f"interrupted; rerun the same command to resume ({out / DIR})")
        raise
    except DeformSmithError as exc:  # a run of another configuration in --out
        fail(str(exc), exc.exit_code)
    emit_report(report.model_dump(mode="json"), summary_lines(report), Path(report.out_root) / REPORT_JSON, as_json)
