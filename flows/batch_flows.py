"""Prefect flows behind the deployments: `deformsmith-generate` (one request -> one asset) and `deformsmith-batch`.

The batch flow fans a JSONL file out as runs of the generate deployment (`run_deployment`), so the runs spread over
the workers polling the pool, and waits for them. A run that is lost is submitted again, at most `max_attempts`
times: lost means CRASHED (the worker saw its process die, or the server's zombie automation saw its heartbeats
stop), RUNNING with no heartbeat for `heartbeat_timeout_s`, or PENDING (claimed by a worker that never started it)
for `pending_timeout_s`. The batch flow marks a run it judges lost as Crashed before resubmitting it. The content
cache makes the rerun resume: finished task results are hits; a task the dead process never published runs again.
"""

from __future__ import annotations

import shutil
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, cast
from uuid import UUID

import cache  # noqa: F401  (sets the local Prefect environment before prefect is imported)
from prefect import flow, get_run_logger
from prefect.client.orchestration import SyncPrefectClient, get_client
from prefect.client.schemas.objects import FlowRun, StateType
from prefect.deployments import run_deployment
from prefect.events.filters import EventFilter, EventNameFilter, EventResourceFilter
from prefect.states import Crashed

from contracts.errors import DeformSmithError
from contracts.request import AssetRequest
from flows.batch import DEFAULT_JOB
from tasks.batch_requests import BatchItem, BatchReport, RequestResult, failed_result, parse_requests
from flows.batch_job import run_request

GENERATE_DEPLOYMENT = "deformsmith-generate/generate"
HEARTBEAT_EVENT = "prefect.flow-run.heartbeat"


class RequestFailed(DeformSmithError):
    """A generate run whose request failed (bad input or a layer said no); the flow run ends Failed."""


@flow(name="deformsmith-generate", persist_result=False, log_prints=True)
def generate_flow(request: dict[str, Any], out_dir: str, device: str = "cpu", job: str = DEFAULT_JOB) -> dict[str, Any]:
    """One request -> one published asset directory (the on-demand generation deployment)."""
    req = AssetRequest.model_validate(request)
    result = run_request(req, Path(out_dir), device, job)
    if result["status"] != "ok":
        raise RequestFailed(result["reason"])
    return result


# ---- the batch flow ---------------------------------------------------------------------------------


def _now() -> datetime:
    return datetime.now(UTC)


def _last_heartbeat(client: SyncPrefectClient, run_id: UUID) -> datetime | None:
    """Time of the newest heartbeat event of a flow run (None when it never sent one)."""
    page = client.read_events(EventFilter(event=EventNameFilter(name=[HEARTBEAT_EVENT]),
                                          resource=EventResourceFilter(id=[f"prefect.flow-run.{run_id}"])), limit=1)
    return page.events[0].occurred if page.events else None


def lost_reason(client: SyncPrefectClient, run: FlowRun, pending_timeout_s: float,
                heartbeat_timeout_s: float) -> str | None:
    """Why a non-final run counts as lost (None while it looks alive)."""
    state = run.state
    if state is None or state.timestamp is None:
        return None
    age = (_now() - state.timestamp).total_seconds()
    if state.type == StateType.PENDING and age > pending_timeout_s:
        return f"pending for {age:.0f} s (its worker never started it)"
    if state.type == StateType.RUNNING and age > heartbeat_timeout_s:
        beat = _last_heartbeat(client, run.id)
        silent = age if beat is None else (_now() - beat).total_seconds()
        if silent > heartbeat_timeout_s:
            return f"no heartbeat for {silent:.0f} s"
    return None


def _clean_partials(out_dir: Path) -> None:
    """Remove working directories a dead run left next to its asset directory (never the asset itself)."""
    for partial in out_dir.parent.glob(f".{out_dir.name}.partial-*"):
        shutil.rmtree(partial, ignore_errors=True)


class _Tracker:
    """Submits requests as generate runs and follows them to a final outcome."""

    def __init__(self, deployment: str, out_root: Path, device: str, job: str, max_attempts: int) -> None:
        self.deployment, self.out_root, self.device, self.job = deployment, out_root, device, job
        self.max_attempts = max_attempts
        self.runs: dict[str, UUID] = {}
        self.attempts: dict[str, int] = {}
        self.started: dict[str, float] = {}
        self.history: dict[str, list[str]] = {}

    def submit(self, item: BatchItem) -> None:
        """Create a flow run of the generate deployment for one request (returns at once)."""
        assert item.request is not None
        n = self.attempts.get(item.name, 0) + 1
        self.attempts[item.name] = n
        self.started.setdefault(item.name, time.perf_counter())
        # run_deployment is sync_compatible (typed FlowRun | Coroutine): called from sync code it returns the FlowRun
        run = cast(FlowRun, run_deployment(
            self.deployment, timeout=0, flow_run_name=f"{item.name}#{n}", tags=["deformsmith-batch"],
            parameters={"request": item.request.model_dump(mode="json"), "device": self.device,
                        "out_dir": str(self.out_root / item.name), "job": self.job}))
        self.runs[item.name] = run.id
        get_run_logger().info("submitted %s (attempt %d) as flow run %s", item.name, n, run.id)

    def result(self, item: BatchItem, run: FlowRun, status: str, reason: str | None) -> RequestResult:
        """The request's result from its final run."""
        ok = status == "ok"
        return RequestResult(name=item.name, line=item.line, status="ok" if ok else "failed", reason=reason,
                             asset_dir=str(self.out_root / item.name) if ok else None,
                             wall_s=round(time.perf_counter() - self.started[item.name], 3),
                             attempts=self.attempts[item.name], log=f"flow run {run.id}")


def follow(tracker: _Tracker, items: list[BatchItem], poll_s: float, pending_timeout_s: float,
           heartbeat_timeout_s: float, timeout_s: float) -> list[RequestResult]:
    """Poll the submitted runs until each ends (resubmitting lost ones) or the batch times out."""
    logger = get_run_logger()
    open_items = {item.name: item for item in items}
    results: list[RequestResult] = []
    deadline = time.monotonic() + timeout_s
    with get_client(sync_client=True) as client:
        while open_items and time.monotonic() < deadline:
            time.sleep(poll_s)
            for name, item in list(open_items.items()):
                run = client.read_flow_run(tracker.runs[name])
                state = run.state
                if state is None:
                    continue
                lost = None
                if state.type == StateType.COMPLETED:
                    results.append(tracker.result(item, run, "ok", None))
                elif state.type in (StateType.FAILED, StateType.CANCELLED):
                    results.append(tracker.result(item, run, "failed", state.message or state.name))
                elif state.type == StateType.CRASHED:
                    lost = f"crashed: {state.message or state.name}"
                else:
                    lost = lost_reason(client, run, pending_timeout_s, heartbeat_timeout_s)
                    if lost is not None:
                        client.set_flow_run_state(run.id, Crashed(message=f"lost: {lost}"), force=True)
                if lost is None:
                    if state.is_final():
                        del open_items[name]
                    continue
                logger.warning("run %s of %s lost (%s)", run.id, name, lost)
                tracker.history.setdefault(name, []).append(f"attempt {tracker.attempts[name]}: {lost}")
                if tracker.attempts[name] >= tracker.max_attempts:
                    results.append(tracker.result(item, run, "failed", "; ".join(tracker.history[name])))
                    del open_items[name]
                    continue
                _clean_partials(tracker.out_root / name)
                tracker.submit(item)
    for name, item in open_items.items():
        results.append(RequestResult(name=name, line=item.line, status="failed", attempts=tracker.attempts[name],
                                     reason=f"batch timed out after {timeout_s:g} s (flow run {tracker.runs[name]})"))
    return results


@flow(name="deformsmith-batch", persist_result=False, log_prints=True)
def batch_flow(requests_jsonl: str, out_root: str, device: str = "cpu", deployment: str = GENERATE_DEPLOYMENT,
               job: str = DEFAULT_JOB, max_attempts: int = 3, poll_s: float = 5.0, pending_timeout_s: float = 180.0,
               heartbeat_timeout_s: float = 150.0, timeout_s: float = 6 * 3600.0) -> dict[str, Any]:
    """Fan a JSONL file out over the generate deployment's workers; resubmit lost runs; write the batch report."""
    t0 = time.perf_counter()
    root = Path(out_root).absolute()
    root.mkdir(parents=True, exist_ok=True)
    items = parse_requests(Path(requests_jsonl))
    results = [failed_result(item) for item in items if item.request is None]
    runnable = [item for item in items if item.request is not None]
    tracker = _Tracker(deployment, root, device, job, max_attempts)
    for item in runnable:
        tracker.submit(item)
    results += follow(tracker, runnable, poll_s, pending_timeout_s, heartbeat_timeout_s, timeout_s)
    report = BatchReport.build(results, time.perf_counter() - t0, requests_file=str(Path(requests_jsonl).absolute()),
                               out_root=str(root), runner=f"deployment:{deployment}", concurrency=None, device=device)
    report.write(root)
    get_run_logger().info("batch: %d ok, %d failed, %.1f assets/hour", report.ok, report.failed, report.assets_per_hour)
    return report.model_dump(mode="json")
