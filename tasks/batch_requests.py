"""A batch of asset requests as data: the JSONL requests file parsed into items (a valid request with its output name,
or the reason a line is unusable), how each request ended, and the batch report with its throughput (SI: seconds,
assets per hour), and how a request's process ended read from what it left (its result file, exit status, log and
the cache's event log). flows.batch runs them in processes; flows.batch_flows through a Prefect work pool."""

from __future__ import annotations

import json
import re
import signal
from collections.abc import Callable
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, Field, ValidationError

from contracts.errors import InputError, validation_message
from contracts.request import AssetRequest
from tasks.publish import write_text_atomic

REPORT_JSON = "batch_report.json"
NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,95}$")
Status = Literal["ok", "failed"]
ItemCallback = Callable[["RequestResult"], None]
INTERRUPTED = "interrupted"
REQUESTS_PER_WORKER = 20  # requests a batch's worker process serves before a fresh one replaces it (what a long-lived
# process may gather, host or GPU memory, is returned this often) [-]


class BatchItem(BaseModel):
    """One line of the requests file: a valid request with its output name, or the reason it is unusable."""

    line: int
    name: str
    request: AssetRequest | None = None
    error: str | None = None
    explicit_name: bool = False


class RequestResult(BaseModel):
    """How one request of a batch ended."""

    name: str
    line: int
    status: Status
    reason: str | None = None
    asset_dir: str | None = None
    wall_s: float = 0.0
    attempts: int = 1
    tasks_executed: int | None = Field(default=None, description="cached-task misses recorded by this request")
    tasks_cached: int | None = Field(default=None, description="cached-task hits recorded by this request")
    log: str | None = None


class BatchReport(BaseModel):
    """The batch report: one result per line, totals and throughput (SI: seconds; assets per hour)."""

    schema_version: int = 1
    requests_file: str
    out_root: str
    runner: str = "local"
    concurrency: int | None = Field(default=None, description="requests at once (None: set by the pool)")
    device: str
    wall_s: float
    requested: int
    ok: int
    failed: int
    assets_per_hour: float
    results: list[RequestResult]

    @classmethod
    def build(cls, results: list[RequestResult], wall_s: float, **fields: Any) -> BatchReport:
        """Totals and throughput from the per-request results."""
        results = sorted(results, key=lambda r: r.line)
        ok = sum(r.status == "ok" for r in results)
        return cls(results=results, wall_s=round(wall_s, 3), requested=len(results), ok=ok, failed=len(results) - ok,
                   assets_per_hour=round(3600.0 * ok / wall_s, 2) if wall_s > 0 else 0.0, **fields)

    def write(self, out_root: Path) -> Path:
        """Write the report atomically as out_root/batch_report.json."""
        return write_text_atomic(Path(out_root) / REPORT_JSON, self.model_dump_json(indent=2) + "\n")


# ---- parsing ----------------------------------------------------------------------------------------


def slug(text: str) -> str:
    """A name for a folder: lower-case letters and digits joined by '_', at most 48 characters ('asset' when empty)."""
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")[:48] or "asset"


def _default_name(request: AssetRequest) -> str:
    src = request.mesh_path or request.image_path
    return slug(src.stem if src is not None else request.text or "asset")


def parse_line(line_no: int, text: str) -> BatchItem:
    """One JSONL line -> a BatchItem (invalid lines carry their reason instead of a request)."""
    fallback = f"line-{line_no}"
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        return BatchItem(line=line_no, name=fallback, error=f"malformed JSON: {exc}")
    if not isinstance(data, dict):
        return BatchItem(line=line_no, name=fallback, error="a line must be a JSON object (an AssetRequest)")
    name = data.pop("name", None)
    if name is not None and (not isinstance(name, str) or not NAME_RE.match(name)):
        return BatchItem(line=line_no, name=fallback,
                         error=f"invalid name {name!r}: letters, digits, '.', '_', '-'; no leading dot or slash")
    try:
        request = AssetRequest.model_validate(data)
    except ValidationError as exc:
        return BatchItem(line=line_no, name=name or fallback, error="invalid request: " + validation_message(exc))
    return BatchItem(line=line_no, name=name or _default_name(request), request=request, explicit_name=bool(name))


def parse_requests(path: Path) -> list[BatchItem]:
    """All non-blank, non-comment lines of a JSONL file; names made unique (explicit duplicates fail)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"requests file not found: {path}")
    items: list[BatchItem] = []
    for no, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        if raw.strip() and not raw.lstrip().startswith("#"):
            items.append(parse_line(no, raw))
    if not items:
        raise InputError(f"{path} holds no requests")
    seen: set[str] = set()
    for item in items:
        if item.name in seen:
            if item.explicit_name:
                item.error, item.request = f"duplicate name {item.name!r}", None
            else:
                item.name = f"{item.name}-{item.line}"
        seen.add(item.name)
    return items


def failed_result(item: BatchItem) -> RequestResult:
    """The result of a line that never ran."""
    return RequestResult(name=item.name, line=item.line, status="failed", reason=item.error, attempts=0)


# ---- a request's process, ended -----------------------------------------------------------------------


def not_started(item: BatchItem) -> RequestResult:
    """The result of a request that an interrupted batch never started."""
    return RequestResult(name=item.name, line=item.line, status="failed", attempts=0,
                         reason=f"{INTERRUPTED} before it started")


def cache_counts(events_file: Path, pid: int, since: int) -> tuple[int, int]:
    """(misses, hits) of one process in the cache's execution log, reading from byte offset `since`."""
    if not events_file.is_file():
        return 0, 0
    miss = hit = 0
    with events_file.open("rb") as fh:
        fh.seek(since)
        for raw in fh:
            try:
                ev = json.loads(raw)
            except json.JSONDecodeError:
                continue
            if ev.get("pid") == pid:
                miss += ev.get("outcome") == "miss"
                hit += ev.get("outcome") == "hit"
    return miss, hit


def death_reason(rc: int) -> str:
    """Why a process that wrote no result ended: the signal that killed it, or its exit code."""
    if rc < 0:
        try:
            return f"process died from signal {signal.Signals(-rc).name}"
        except ValueError:
            return f"process died from signal {-rc}"
    return f"process exited with code {rc} without a result"


def last_log_line(log: Path) -> str:
    """The last non-blank line of a log (its last 300 characters; '' when unreadable or empty)."""
    try:
        lines = [ln.strip() for ln in log.read_text(encoding="utf-8", errors="replace").splitlines() if ln.strip()]
    except OSError:
        return ""
    return lines[-1][-300:] if lines else ""


def process_result(item: BatchItem, rc: int, wall_s: float, result_file: Path, log: Path, counts: tuple[int, int],
                   reason: str | None = None, stopping: bool = False) -> RequestResult:
    """How a request's process ended: its result file, else why it has none (`reason`: a timeout; `stopping`: the
    batch was interrupted; else the signal or exit code, with the log's last line). counts: its cache (misses, hits)."""
    if reason is None and stopping and not result_file.is_file():
        reason = f"{INTERRUPTED} after {wall_s:.1f} s"
    misses, hits = counts
    common: dict[str, Any] = dict(name=item.name, line=item.line, wall_s=round(wall_s, 3), tasks_executed=misses,
                                  tasks_cached=hits, log=str(log))
    if reason is None and result_file.is_file():
        data = json.loads(result_file.read_text(encoding="utf-8"))
        return RequestResult(status=data["status"], reason=data.get("reason"), asset_dir=data.get("asset_dir"),
                             **common)
    reason = reason or death_reason(rc)
    tail = "" if reason.startswith(INTERRUPTED) else last_log_line(log)  # its last line is the KeyboardInterrupt
    return RequestResult(status="failed", reason=f"{reason}; last log line: {tail}" if tail else reason, **common)
