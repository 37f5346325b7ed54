"""`deformsmith bench throughput`: distinct requests end to end through the batch runner (flows.batch), on the CPU or
on GPUs with each worker pinned to one, sampled in the background, resumed where a killed run left off. The report's
model, the samplers and the resume records are tasks.throughput's."""

from __future__ import annotations

import os
from pathlib import Path

import cache
from flows.batch import DEFAULT_JOB, LOG_DIR, NO_L3_JOB, run_batch
from tasks.batch_requests import REQUESTS_PER_WORKER, ItemCallback, RequestResult
from tasks.throughput.ledger import Ledger, SamplerStats, benchmark_items, gpu_slots
from tasks.throughput.report import RunConfig, ThroughputReport, build_report
from tasks.throughput.samplers import GpuSampler, HostMemorySampler, nvidia_smi_available

SAMPLE_S = 1.0  # how often the GPUs and the workers' memory are sampled [s]
BEAT_S = 5.0  # how often the session's entry in the ledger says it runs, with the samples so far [s]


def run_throughput(requests_jsonl: Path, out_root: Path, gpus: list[str] | None = None, workers_per_gpu: int = 1,
                   concurrency: int = 1, l3: bool = True, limit: int | None = None, timeout_s: float | None = None,
                   job: str | None = None, on_result: ItemCallback | None = None,
                   requests_per_worker: int = REQUESTS_PER_WORKER) -> ThroughputReport:
    """Run the benchmark's requests not yet done in out_root (gpus: pin workers_per_gpu workers to each, on CUDA;
    None: `concurrency` workers on the CPU), then write and return the report of every session in out_root. An
    interrupted run records what finished and re-raises; the same command resumes it."""
    given = str(requests_jsonl)  # the report names the file as the command was given it, not this machine's path
    requests_jsonl, out_root = Path(requests_jsonl).absolute(), Path(out_root).absolute()
    items = benchmark_items(requests_jsonl, limit)
    workers = len(gpus) * workers_per_gpu if gpus else concurrency
    config = RunConfig(device="cuda" if gpus else "cpu", gpus=gpus, workers_per_gpu=workers_per_gpu if gpus else None,
                       workers=workers, l3=l3, requests_per_worker=requests_per_worker)
    ledger = Ledger(out_root)
    session = ledger.start_session(config)
    todo, _ = ledger.plan(items, session.index)
    by_name = {item.name: item for item in todo}

    def record(result: RequestResult) -> None:
        ledger.record(result, by_name[result.name], session.index, out_root / LOG_DIR)
        if on_result is not None:
            on_result(result)

    gpu_sampler = GpuSampler(gpus, SAMPLE_S) if nvidia_smi_available() else None
    host_sampler = HostMemorySampler(os.getpid(), SAMPLE_S)
    for sampler in (gpu_sampler, host_sampler):
        if sampler is not None:
            sampler.start()

    def stats() -> SamplerStats:
        return gpu_sampler.stats() if gpu_sampler is not None else None, host_sampler.stats()

    def end() -> None:
        ledger.end_session(session, *stats())

    def write_report():  # noqa: ANN202
        report = build_report(ledger.current(items), ledger.sessions(), len(items), requests_file=given,
                              out_root=str(out_root), cache_root=str(cache.cache_root()))
        report.write(out_root)
        return report

    def interrupted() -> None:  # at once on a stop, before the children are: the command line's backstop ends the
        end()  # process ~1.3 s after the signal, sooner than many workers stop (24 workers: no report was written)
        write_report()

    # a killed run's wall time ends at its last beat, and its samples are those of that beat
    stop_heartbeat = ledger.heartbeat(session, BEAT_S, stats)
    try:
        if todo:  # (stopped: the session's end is recorded at once, as the command line may end the process
            # before its children have stopped and this `finally` has run)
            run_batch(ledger.write_requests(todo, session.index), out_root, concurrency=workers,
                      device=config.device, job=job or (DEFAULT_JOB if l3 else NO_L3_JOB), timeout_s=timeout_s,
                      on_result=record, worker_envs=gpu_slots(gpus, workers_per_gpu) if gpus else None,
                      on_interrupt=interrupted, requests_per_worker=requests_per_worker)
    finally:  # also when interrupted: the session's end and samples are recorded, and the report written (again,
        stop_heartbeat()  # with the stopped requests' records, when the process lives that long)
        for sampler in (gpu_sampler, host_sampler):
            if sampler is not None:
                sampler.stop()
        end()
        report = write_report()
    return report
