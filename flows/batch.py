"""`deformsmith batch`: many requests from a JSONL file, at most N at a time in processes of their own, one report.

Each of the N workers is a process that serves up to `requests_per_worker` requests one after another (imports,
Warp's kernels and the Prefect client load once for them) and is then replaced; 1 runs each request in a new process.

A line is an AssetRequest as JSON plus an optional "name" (the output directory under the batch root). A malformed
line, an invalid request, a StageFailure or a hard crash fails that request alone; the report says why. Reruns are
cheap: every expensive unit is content-cached, so an unchanged request republishes from cache hits.
The Prefect flows that deployments run (one request per run, a batch fanned out over a work pool) live in
`flows.batch_flows`; they share the parsing and the report model defined here.
"""

from __future__ import annotations

import json
import os
import queue
import select
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor, as_completed
from contextlib import contextmanager
from pathlib import Path
from typing import Any


import cache
from cache import runtime
from cache.config import ENV_VAR
from contracts.errors import InputError
from tasks.batch_requests import (
    REQUESTS_PER_WORKER, BatchItem, BatchReport, ItemCallback, RequestResult, cache_counts, failed_result, not_started,
    parse_requests, process_result,
)
from tasks.probes.workers import child_probe_workers
from tasks.processes import Children, sigterm_as_interrupt, signal_group

LOG_DIR = "_logs"
DEFAULT_JOB = "flows.batch_job:generate_job"
NO_L3_JOB = "flows.batch_job:generate_job_without_l3"
REQUIRE_L3_JOB = "flows.batch_job:generate_job_requiring_l3"


# ---- the local runner: one process per request ------------------------------------------------------


def _request_files(item: BatchItem, out_root: Path, cache_dir: Path) -> tuple[Path, Path, Path, Path, int]:
    """A request's log, result file (removed) and request file (written) under OUT/_logs, the cache's execution log
    and its size now (the request's cache counts are read from there)."""
    assert item.request is not None
    logs = out_root / LOG_DIR
    logs.mkdir(parents=True, exist_ok=True)
    log, result_file = logs / f"{item.name}.log", logs / f"{item.name}.result.json"
    result_file.unlink(missing_ok=True)
    request_file = logs / f"{item.name}.request.json"
    request_file.write_text(item.request.model_dump_json(), encoding="utf-8")
    events = cache_dir / "events.jsonl"
    return log, result_file, request_file, events, events.stat().st_size if events.is_file() else 0


def run_one(item: BatchItem, out_root: Path, device: str, job: str, env: dict[str, str], cache_dir: Path,
            timeout_s: float | None = None, children: Children | None = None) -> RequestResult:
    """Run one request in a child process (`python -m flows.batch_job`) and read back its result."""
    assert item.request is not None
    children = children or Children()
    if children.stopping.is_set():
        return not_started(item)
    log, result_file, request_file, events, since = _request_files(item, out_root, cache_dir)
    # -P: the working directory is not put on sys.path, so a folder there named like one of our packages (a user's
    # `cache/` or `tasks/`) cannot shadow it in the child (it would, under an editable install)
    cmd = [sys.executable, "-P", "-m", "flows.batch_job", "--request", str(request_file), "--out", str(out_root / item.name),
           "--device", device, "--job", job, "--result", str(result_file), "--parent-pid", str(os.getpid())]
    t0 = time.perf_counter()
    with log.open("w", encoding="utf-8") as fh:
        proc = children.start(cmd, stdout=fh, stderr=subprocess.STDOUT, env=env)
        if proc is None:
            return not_started(item)
        try:
            rc = proc.wait(timeout=timeout_s)
            timed_out = None
        except subprocess.TimeoutExpired:
            signal_group(proc, signal.SIGKILL)
            rc = proc.wait()
            timed_out = f"timed out after {timeout_s:g} s"
        finally:
            children.finished(proc)
    return process_result(item, rc, time.perf_counter() - t0, result_file, log, cache_counts(events, proc.pid, since),
                          timed_out, children.stopping.is_set())


class ServedWorker:
    """One worker process (`python -m flows.batch_job --serve`) of a batch slot, started on its first request and
    again after a crash, a timeout or `requests_per_worker` requests. A request's wall time counts the worker's start
    when the worker started for it."""

    def __init__(self, slot: int, out_root: Path, device: str, env: dict[str, str], children: Children,
                 requests_per_worker: int) -> None:
        self.slot, self.out_root, self.device, self.env = slot, out_root, device, env
        self.children, self.requests_per_worker = children, requests_per_worker
        self.proc: subprocess.Popen[bytes] | None = None
        self.served = 0

    def _start(self) -> bool:
        logs = self.out_root / LOG_DIR
        logs.mkdir(parents=True, exist_ok=True)
        log = logs / f"_worker-{self.slot}.log"  # (its stderr from the start, so that a failed start is in it too)
        cmd = [sys.executable, "-P", "-m", "flows.batch_job", "--serve", "--log", str(log), "--device", self.device,
               "--parent-pid", str(os.getpid())]  # (-P: see run_one)
        with log.open("a", encoding="utf-8") as fh:
            self.proc = self.children.start(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=fh,
                                            env=self.env)
        self.served = 0
        return self.proc is not None

    def _ended(self) -> int:
        """Wait for the worker to end; its exit status."""
        assert self.proc is not None
        proc, self.proc = self.proc, None
        rc = proc.wait()
        for stream in (proc.stdin, proc.stdout):
            if stream is not None:
                stream.close()
        self.children.finished(proc)
        return rc

    def close(self, grace_s: float = 30.0) -> None:
        """End the worker: the end of its orders, then SIGKILL after grace_s."""
        if self.proc is None:
            return
        try:
            assert self.proc.stdin is not None
            self.proc.stdin.close()
            self.proc.wait(timeout=grace_s)
        except (OSError, subprocess.TimeoutExpired):
            signal_group(self.proc, signal.SIGKILL)
        self._ended()

    def run(self, item: BatchItem, job: str, cache_dir: Path, timeout_s: float | None = None) -> RequestResult:
        """Serve one request (as run_one, in this slot's worker)."""
        assert item.request is not None
        if self.children.stopping.is_set():
            return not_started(item)
        log, result_file, request_file, events, since = _request_files(item, self.out_root, cache_dir)
        order = json.dumps({"name": item.name, "request": str(request_file), "out": str(self.out_root / item.name),
                            "result": str(result_file), "log": str(log), "job": job}) + "\n"
        t0 = time.perf_counter()
        if self.proc is not None and self.proc.poll() is not None:
            self._ended()  # (it ended while idle: a fresh one)
        if self.proc is None and not self._start():
            return not_started(item)
        assert self.proc is not None and self.proc.stdin is not None and self.proc.stdout is not None
        pid, answer, timed_out = self.proc.pid, b"", None
        try:
            self.proc.stdin.write(order.encode())
            self.proc.stdin.flush()
            ready, _, _ = select.select([self.proc.stdout], [], [], timeout_s)
            if ready:
                answer = self.proc.stdout.readline()  # (an answer, or b"" at the end of the worker)
            else:
                timed_out = f"timed out after {timeout_s:g} s"
                signal_group(self.proc, signal.SIGKILL)
        except OSError:  # (it died before reading the order)
            answer = b""
        rc = 0
        if answer:
            self.served += 1
            if json.loads(answer).get("retire") or self.served >= self.requests_per_worker:
                self.close()  # (a failed request retires its worker: see flows.batch_job.serve)
        else:
            rc = self._ended()
        return process_result(item, rc, time.perf_counter() - t0, result_file, log,
                              cache_counts(events, pid, since), timed_out, self.children.stopping.is_set())


@contextmanager
def prefect_api_for_children() -> Iterator[dict[str, str]]:
    """The Prefect environment the child processes share: the user's server, else one local server for the whole
    batch (marked local, so that the children's flows run without heartbeats, as against their own). The local one is
    DeformSmith's (`cache.runtime.prestart_local_server`, already started by the CLI): it exits by itself if the
    batch is killed, where Prefect's own temporary server, the fallback, would be left running."""
    if runtime.uses_remote_server():
        from prefect.settings import PREFECT_API_URL

        yield {"PREFECT_API_URL": str(PREFECT_API_URL.value())}
        return
    runtime.prestart_local_server()
    shared = runtime.shared_server_env()
    if shared:
        yield shared
        return
    from prefect.server.api.server import SubprocessASGIServer

    server = SubprocessASGIServer()
    server.start(timeout=120)
    try:
        yield runtime.local_api_env(server.api_url)
    finally:
        server.stop()


def run_batch(requests_jsonl: Path, out_root: Path, concurrency: int = 1, device: str = "cpu",
              job: str = DEFAULT_JOB, timeout_s: float | None = None,
              on_result: ItemCallback | None = None, worker_envs: list[dict[str, str]] | None = None,
              on_interrupt: Callable[[], None] | None = None,
              requests_per_worker: int = REQUESTS_PER_WORKER) -> BatchReport:
    """Run every request of a JSONL file in `concurrency` worker processes, each serving up to requests_per_worker
    of them one after another (1: a new process for each); write and return the report.
    worker_envs: one environment overlay per worker (`concurrency` of them), a request process running under a free
    one (the throughput benchmark pins each worker to a GPU this way: CUDA_VISIBLE_DEVICES). on_interrupt: called at
    once on Ctrl-C or SIGTERM, before the children are stopped (which may outlast the command line's ~1.3 s backstop;
    the throughput benchmark records its session's end there)."""
    if concurrency < 1:
        raise InputError(f"concurrency must be >= 1, got {concurrency}")
    if requests_per_worker < 1:
        raise InputError(f"requests per worker must be >= 1, got {requests_per_worker}")
    if worker_envs is not None and len(worker_envs) != concurrency:
        raise InputError(f"{len(worker_envs)} worker environments for {concurrency} workers")
    free: queue.SimpleQueue[tuple[int, dict[str, str]]] = queue.SimpleQueue()
    for slot, overlay in enumerate(worker_envs or [{}] * concurrency):
        free.put((slot, overlay))
    if device not in ("cpu", "cuda"):
        raise InputError(f"device must be cpu or cuda, got '{device}'")
    requests_jsonl, out_root = Path(requests_jsonl).absolute(), Path(out_root).absolute()
    items = parse_requests(requests_jsonl)
    out_root.mkdir(parents=True, exist_ok=True)
    cache_dir = cache.cache_root()
    lock = threading.Lock()
    results: dict[int, RequestResult] = {}  # by line: a result handed in twice (see the interrupt below) counts once

    def done(result: RequestResult) -> None:
        with lock:
            results[result.line] = result
        if on_result:
            on_result(result)

    for item in items:
        if item.request is None:
            done(failed_result(item))
    t0 = time.perf_counter()
    runnable = [item for item in items if item.request is not None]
    interrupted = False
    if runnable:
        children = Children()
        with prefect_api_for_children() as prefect_env, sigterm_as_interrupt():
            env = {**os.environ, **prefect_env, ENV_VAR: str(cache_dir),
                   **child_probe_workers(concurrency)}  # the requests' probe threads share the cores
            workers: dict[int, ServedWorker] = {}
            with ThreadPoolExecutor(max_workers=concurrency) as pool:
                def run_in_slot(item: BatchItem) -> RequestResult:  # (at most `concurrency` run: one is free)
                    slot, overlay = free.get()
                    try:
                        if requests_per_worker == 1:
                            return run_one(item, out_root, device, job, {**env, **overlay}, cache_dir, timeout_s,
                                           children)
                        if slot not in workers:
                            workers[slot] = ServedWorker(slot, out_root, device, {**env, **overlay}, children,
                                                         requests_per_worker)
                        return workers[slot].run(item, job, cache_dir, timeout_s)
                    finally:
                        free.put((slot, overlay))

                futures = [pool.submit(run_in_slot, item) for item in runnable]
                handled: set[Any] = set()
                try:
                    for fut in as_completed(futures):
                        done(fut.result())
                        handled.add(fut)
                except KeyboardInterrupt:  # Ctrl-C (or SIGTERM): stop the children, report every request, re-raise
                    interrupted = True
                    if on_interrupt is not None:
                        try:
                            on_interrupt()
                        except Exception:  # (the children are stopped whatever it does)
                            pass
                    children.stop_all()
                    for fut in futures:
                        if fut not in handled:
                            done(fut.result())
                finally:
                    for worker in workers.values():
                        worker.close()
    report = BatchReport.build(list(results.values()), time.perf_counter() - t0, requests_file=str(requests_jsonl),
                               out_root=str(out_root), concurrency=concurrency, device=device)
    report.write(out_root)
    if interrupted:
        raise KeyboardInterrupt
    return report
