"""A throughput run on disk, so that a killed run resumes: under `<out>/_throughput/`, `records.jsonl` (one line
appended per finished request), `sessions.json` (each run's start, end, configuration and samples) and the
requests a session runs (`session-<n>.jsonl`). A resumed run skips the requests that finished (published, or failed
for a reason of their own) and reruns those it interrupted; an asset found published with no record counts as done."""

from __future__ import annotations

import hashlib
import json
import os
import threading
import time
from collections.abc import Callable
from pathlib import Path

from pydantic import TypeAdapter

from contracts.asset_dir import ASSET_JSON
from contracts.errors import InputError
from contracts.request import AssetRequest
from tasks.batch_requests import BatchItem, RequestResult, parse_requests
from tasks.publish import write_text_atomic
from tasks.throughput.report import RequestRecord, RunConfig, Session, dir_bytes, l3_verdict, stage_times
from tasks.throughput.samplers import GpuStats, HostMemoryStats

DIR = "_throughput"
RECORDS = "records.jsonl"
SESSIONS = "sessions.json"
_sessions = TypeAdapter(list[Session])
SamplerStats = tuple[GpuStats | None, HostMemoryStats | None]  # what the GPU and host-memory samplers saw so far


def request_digest(request: AssetRequest) -> str:
    """sha256 of a request as canonical JSON (the same request under another name has the same digest)."""
    doc = json.dumps(request.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(doc.encode()).hexdigest()


def benchmark_items(path: Path, limit: int | None = None) -> list[BatchItem]:
    """The benchmark's requests: the file's first `limit` lines (all when None), each valid and distinct
    (InputError naming the line otherwise: a benchmark measures a clean set of distinct requests)."""
    items = parse_requests(path)[:limit]
    seen: dict[str, int] = {}
    for item in items:
        if item.request is None:
            raise InputError(f"{path}: line {item.line}: {item.error}")
        digest = request_digest(item.request)
        if digest in seen:
            raise InputError(f"{path}: line {item.line} repeats line {seen[digest]}'s request (a throughput benchmark "
                             "runs distinct requests: a repeat would be a cache hit)")
        seen[digest] = item.line
    return items


def gpu_slots(gpus: list[str], workers_per_gpu: int) -> list[dict[str, str]]:
    """One environment overlay per worker: workers_per_gpu of them per GPU, round robin over the GPUs, each pinning
    its request processes to its GPU (CUDA_VISIBLE_DEVICES; in nvidia-smi's order, so the sampler's GPU is the
    worker's, unless the user chose an order)."""
    order = {} if "CUDA_DEVICE_ORDER" in os.environ else {"CUDA_DEVICE_ORDER": "PCI_BUS_ID"}
    return [{"CUDA_VISIBLE_DEVICES": gpus[i % len(gpus)], **order} for i in range(len(gpus) * workers_per_gpu)]


def _interrupted(record: RequestRecord) -> bool:
    return record.status != "ok" and (record.reason or "").startswith("interrupted")


class Ledger:
    """The records and sessions of the throughput run in one output root."""

    def __init__(self, out_root: Path) -> None:
        self.out_root = Path(out_root)
        self.dir = self.out_root / DIR
        self._lock = threading.Lock()

    # -- sessions --
    def sessions(self) -> list[Session]:
        path = self.dir / SESSIONS
        if not path.is_file():
            return []
        return _sessions.validate_json(path.read_bytes())

    def _write_sessions(self, sessions: list[Session]) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        write_text_atomic(self.dir / SESSIONS, _sessions.dump_json(sessions, indent=2).decode("utf-8"))

    def start_session(self, config: RunConfig) -> Session:
        """A new session; InputError when the output root holds a run with another configuration."""
        sessions = self.sessions()
        if sessions and sessions[-1].config != config:
            ran = ", ".join(f"{k} {v}" for k, v in sessions[-1].config.model_dump().items())
            raise InputError(f"{self.out_root} holds a throughput run with other options ({ran}); resume it with the "
                             "same options or use another --out")
        session = Session(index=len(sessions), started_at=time.time(), config=config)
        self._write_sessions([*sessions, session])
        return session

    def alive(self, session: Session, stats: SamplerStats | None = None) -> None:
        """Note that the session is running (its end, should it be killed) and, given, what its samplers saw so far
        (so that a killed session keeps them)."""
        update: dict[str, object] = {"alive_at": time.time()}
        if stats is not None:
            update.update({k: v for k, v in zip(("gpu", "host_memory"), stats) if v is not None})
        with self._lock:
            self._write_sessions([s if s.index != session.index else s.model_copy(update=update)
                                  for s in self.sessions()])

    def heartbeat(self, session: Session, interval_s: float = 5.0,
                  stats: Callable[[], SamplerStats] | None = None) -> Callable[[], None]:
        """Note the session running, with its samplers' stats so far (`stats()`), every interval_s in a daemon
        thread; returns what stops it."""
        stop = threading.Event()

        def beat() -> None:
            while not stop.wait(interval_s):
                try:
                    self.alive(session, stats() if stats is not None else None)
                except (OSError, ValueError):  # (a full disk, a sessions file cut short: the run goes on; its wall
                    pass  # time and samples may end short)

        thread = threading.Thread(target=beat, name="throughput-heartbeat", daemon=True)
        thread.start()

        def halt() -> None:
            stop.set()
            thread.join(timeout=10.0)

        return halt

    def end_session(self, session: Session, gpu: GpuStats | None = None,
                    host_memory: HostMemoryStats | None = None) -> Session:
        """Record the session's end and what its samplers saw (a sampler's None keeps what its last beat wrote)."""
        with self._lock:
            sessions = self.sessions()
            stored = next((s for s in sessions if s.index == session.index), session)  # (its last beat kept)
            session = stored.model_copy(update={"ended_at": time.time(), "gpu": stored.gpu if gpu is None else gpu,
                                                "host_memory": stored.host_memory if host_memory is None
                                                else host_memory})
            self._write_sessions([s if s.index != session.index else session for s in sessions])
        return session

    # -- records --
    def records(self) -> dict[str, RequestRecord]:
        """The latest record of each request name (a line cut short by a kill is skipped)."""
        path = self.dir / RECORDS
        out: dict[str, RequestRecord] = {}
        if path.is_file():
            for raw in path.read_text(encoding="utf-8").splitlines():
                try:
                    rec = RequestRecord.model_validate_json(raw)
                except ValueError:
                    continue
                out[rec.name] = rec
        return out

    def append(self, record: RequestRecord) -> None:
        """Append one record (one line, flushed)."""
        with self._lock:
            self.dir.mkdir(parents=True, exist_ok=True)
            with (self.dir / RECORDS).open("a", encoding="utf-8") as fh:
                fh.write(record.model_dump_json() + "\n")
                fh.flush()
                os.fsync(fh.fileno())

    def _finished(self, item: BatchItem, rec: RequestRecord | None) -> bool:
        """Whether a record says the item is done: a record of the same request, not interrupted (an interrupted
        request is pending) and, when ok, whose asset is still published."""
        return rec is not None and item.request is not None and rec.request_digest == request_digest(item.request) \
            and not _interrupted(rec) and (rec.status != "ok" or (self.out_root / item.name / ASSET_JSON).is_file())

    def current(self, items: list[BatchItem]) -> list[RequestRecord]:
        """The latest record of each of the benchmark's requests that is done (`_finished`)."""
        known = self.records()
        return [known[i.name].model_copy(update={"line": i.line}) for i in items
                if self._finished(i, known.get(i.name))]

    # -- resuming --
    def plan(self, items: list[BatchItem], session: int) -> tuple[list[BatchItem], list[RequestRecord]]:
        """(the requests to run, the records of those already done). Done: a record of the same request that
        finished (not interrupted) and, when ok, whose asset is still published; or, with no such record, an asset
        published under its name (a run killed between the publish and the record), recorded now as recovered."""
        known = self.records()
        todo: list[BatchItem] = []
        done: list[RequestRecord] = []
        for item in items:
            assert item.request is not None
            digest = request_digest(item.request)
            asset = self.out_root / item.name
            published = (asset / ASSET_JSON).is_file()
            rec = known.get(item.name)
            if rec is not None and self._finished(item, rec):
                done.append(rec.model_copy(update={"line": item.line}))
            elif published and _same_request(asset, item.request):
                recovered = RequestRecord(name=item.name, line=item.line, request_digest=digest, status="ok",
                                          asset_dir=str(asset), asset_bytes=dir_bytes(asset),
                                          l3_passed=l3_verdict(asset), session=session, finished_at=time.time(),
                                          recovered=True)
                self.append(recovered)
                done.append(recovered)
            else:
                todo.append(item)
        return todo, done

    def write_requests(self, items: list[BatchItem], session: int) -> Path:
        """The requests a session runs, as a batch file (each under its name: its output directory is the same)."""
        self.dir.mkdir(parents=True, exist_ok=True)
        path = self.dir / f"session-{session}.jsonl"
        lines = [json.dumps({"name": i.name, **i.request.model_dump(mode="json")})
                 for i in items if i.request is not None]
        path.write_text("".join(line + "\n" for line in lines), encoding="utf-8")
        return path

    def record(self, result: RequestResult, item: BatchItem, session: int, logs: Path) -> RequestRecord:
        """The record of a finished request (its stage times from its result file, its asset's size and L3 verdict
        when published), appended."""
        assert item.request is not None
        asset = Path(result.asset_dir) if result.asset_dir else self.out_root / item.name
        published = result.status == "ok" and (asset / ASSET_JSON).is_file()
        rec = RequestRecord(name=item.name, line=item.line, request_digest=request_digest(item.request),
                            status=result.status, reason=result.reason, asset_dir=str(asset) if published else None,
                            wall_s=result.wall_s or None,
                            stage_s=stage_times(logs / f"{item.name}.result.json") if result.status == "ok" else {},
                            asset_bytes=dir_bytes(asset) if published else None,
                            l3_passed=l3_verdict(asset) if published else None, tasks_executed=result.tasks_executed,
                            tasks_cached=result.tasks_cached, session=session, finished_at=time.time())
        self.append(rec)
        return rec


def _same_request(asset: Path, request: AssetRequest) -> bool:
    """Whether a published asset was made from this request (asset.json's request)."""
    try:
        manifest = json.loads((asset / ASSET_JSON).read_text(encoding="utf-8"))
        return request_digest(AssetRequest.model_validate(manifest["request"])) == request_digest(request)
    except (OSError, ValueError, KeyError, TypeError):
        return False
