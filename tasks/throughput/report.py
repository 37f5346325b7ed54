"""The throughput report: one record per request of the benchmark (how it ended, where its time went, how large its
asset is), the sessions that ran them (a killed run resumed is two sessions), and the figures made of them: distinct
assets per hour, per-stage time shares, GPU and host memory, bytes per asset and failures by reason (SI: seconds,
bytes; utilisation in percent)."""

from __future__ import annotations

import json
import os
import re
import statistics
from pathlib import Path
from typing import Any

from pydantic import BaseModel, Field

from contracts.asset_dir import ASSET_JSON
from tasks.publish import write_text_atomic
from tasks.throughput.samplers import GpuStats, GpuUse, HostMemoryStats

REPORT_JSON = "throughput_report.json"
# generate's stages in the order they start (flows.generate.TIMINGS, as the request process's result file carries
# them; with L3 the renders run beside it, so the stages' seconds may add up to more than the wall time); 'other' is
# the rest of the request's wall time: process start, imports, the request check, Prefect's set-up
STAGES = ("L0", "L1", "L2", "renders", "L3", "pick_and_place_video", "card", "publish")
OTHER = "other"


class RunConfig(BaseModel):
    """What a benchmark run is: a resumed run must be the same."""

    device: str
    gpus: list[str] | None = Field(default=None, description="the GPUs the workers are pinned to (None: the CPU)")
    workers_per_gpu: int | None = None
    workers: int = Field(description="requests running at once")
    l3: bool
    requests_per_worker: int = Field(default=1, description="requests a worker process serves before a fresh one "
                                     "replaces it (1: a new process for each; runs recorded before it was an option)")


class RequestRecord(BaseModel):
    """How one request of the benchmark ended."""

    name: str
    line: int
    request_digest: str = Field(description="sha256 of the request as JSON (its name left out)")
    status: str  # ok | failed
    reason: str | None = None
    asset_dir: str | None = None
    wall_s: float | None = Field(default=None, description="the request process's wall time (None: found published "
                                 "by a resumed run, with no record of its run)")
    stage_s: dict[str, float] = Field(default_factory=dict, description="generate's wall time per stage [s]")
    asset_bytes: int | None = None
    l3_passed: bool | None = Field(default=None, description="L3's verdict in asset.json (None: L3 did not run)")
    tasks_executed: int | None = None
    tasks_cached: int | None = None
    session: int
    finished_at: float = Field(description="when it ended (Unix time [s])")
    recovered: bool = Field(default=False, description="found published with no record (a run killed between the "
                            "publish and the record)")


class Session(BaseModel):
    """One run of the benchmark command over the same output root (a resumed run is a new session)."""

    index: int
    started_at: float
    ended_at: float | None = Field(default=None, description="None: the run was killed before it wrote its end")
    alive_at: float | None = Field(default=None, description="when the run last said it was running (every few "
                                   "seconds): the end of a killed run")
    config: RunConfig
    gpu: GpuStats | None = None
    host_memory: HostMemoryStats | None = None


class Failure(BaseModel):
    """The requests that failed for one reason."""

    count: int
    names: list[str]
    example: str


class SizeStats(BaseModel):
    """Bytes of the published asset directories."""

    assets: int
    mean: float
    median: float
    min: int
    max: int
    total: int


class ThroughputReport(BaseModel):
    """`deformsmith bench throughput`'s report (SI: seconds, bytes; assets per hour)."""

    schema_version: int = 1
    requests_file: str
    out_root: str
    cache_root: str
    config: RunConfig
    requested: int = Field(description="requests in the benchmark (after --limit)")
    ok: int = Field(description="assets published")
    failed: int
    pending: int = Field(description="requests not finished yet (an interrupted run: the next run does them)")
    l3_passed: int | None = Field(default=None, description="published assets whose L3 passed (None: --no-l3)")
    wall_s: float = Field(description="the sessions' wall time together")
    assets_per_hour: float = Field(description="distinct assets published per hour of wall time")
    l3_passed_per_hour: float | None = None
    request_wall_s: dict[str, float] = Field(default_factory=dict, description="mean / median / max of the published "
                                             "requests' own wall times")
    stage_s_per_asset: dict[str, float] = Field(default_factory=dict, description="mean seconds per published asset "
                                                "in each stage ('other': outside generate's stages)")
    stage_share: dict[str, float] = Field(default_factory=dict, description="each stage's fraction of the published "
                                          "requests' wall time together")
    gpu: GpuStats | None = Field(default=None, description="None: no nvidia-smi (or nothing sampled)")
    host_memory: HostMemoryStats | None = None
    bytes_per_asset: SizeStats | None = None
    cache: dict[str, int] = Field(default_factory=dict, description="cached tasks executed and taken from the cache by "
                                  "the requests (a cold run executes nearly all)")
    failures: dict[str, Failure] = Field(default_factory=dict, description="reason -> the requests that failed so")
    sessions: list[Session]
    records: list[RequestRecord]

    def write(self, out_root: Path) -> Path:
        """Write the report atomically as out_root/throughput_report.json."""
        return write_text_atomic(Path(out_root) / REPORT_JSON, self.model_dump_json(indent=2) + "\n")


# ---- what a request left ----------------------------------------------------------------------------


def dir_bytes(path: Path) -> int:
    """Bytes of the regular files under a directory (each inode once; links not followed)."""
    seen: set[tuple[int, int]] = set()
    total = 0
    for root, _, files in os.walk(path):
        for name in files:
            try:
                st = os.lstat(os.path.join(root, name))
            except OSError:
                continue
            if (st.st_dev, st.st_ino) not in seen and os.path.isfile(os.path.join(root, name)):
                seen.add((st.st_dev, st.st_ino))
                total += st.st_size
    return total


def stage_times(result_file: Path) -> dict[str, float]:
    """generate's per-stage wall times from a request process's result file (summary.wall_time_s); {} when absent."""
    try:
        data = json.loads(result_file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    times = ((data or {}).get("summary") or {}).get("wall_time_s") or {}
    return {str(k): round(float(v), 3) for k, v in times.items() if isinstance(v, int | float)}


def l3_verdict(asset_dir: Path) -> bool | None:
    """Whether asset.json says L3 passed; None when L3 did not run or asset.json is unreadable."""
    try:
        manifest = json.loads((asset_dir / ASSET_JSON).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    for stage in manifest.get("validation") or []:
        if isinstance(stage, dict) and stage.get("stage") == "L3":
            return bool(stage.get("passed"))
    return None


# ---- the figures ------------------------------------------------------------------------------------


_EXC = re.compile(r"^([A-Z][A-Za-z]+(?:Error|Failure|NotMet|Exception|Interrupt))\b:?\s*(.*)$")
_STAGE = re.compile(r"^(L[0-3])\b")


def reason_key(reason: str | None) -> str:
    """A failure's reason -> the group it is counted in: the exception's type (and the stage that failed, for a
    StageFailure or a requirement), a timeout, an interruption, or how the process died, without the particulars."""
    text = (reason or "unknown").strip()
    if text.startswith("timed out"):
        return "timed out"
    if text.startswith("interrupted"):
        return "interrupted"
    if text.startswith("process "):  # 'process died from signal SIGKILL; last log line: ...'
        return text.split(";")[0]
    m = _EXC.match(text)
    if m:
        stage = _STAGE.match(m.group(2))
        return f"{m.group(1)} {stage.group(1)}" if stage else m.group(1)
    return text.split(";")[0].split(":")[0][:80]


def _stats(values: list[float]) -> dict[str, float]:
    if not values:
        return {}
    return {"mean": round(statistics.fmean(values), 3), "median": round(statistics.median(values), 3),
            "max": round(max(values), 3)}


def session_wall_s(session: Session, records: list[RequestRecord]) -> float:
    """A session's wall time: start to end or, when it was killed before it wrote its end, to the last time it said
    it was running or its last record, whichever is later."""
    end = session.ended_at
    if end is None:
        end = max([r.finished_at for r in records if r.session == session.index]
                  + [session.alive_at or session.started_at])
    return max(0.0, end - session.started_at)


def _weighted(pairs: list[tuple[float, int]]) -> float:
    """The mean of values weighted by their sample counts (0 with no samples)."""
    n = sum(w for _, w in pairs)
    return round(sum(v * w for v, w in pairs) / n, 2) if n else 0.0


def merge_gpu(stats: list[GpuStats]) -> GpuStats | None:
    """The sessions' GPU samples as one: means weighted by samples, peaks the highest."""
    if not stats:
        return None
    by_gpu: dict[str, list[GpuUse]] = {}
    for s in stats:
        for g in s.gpus:
            by_gpu.setdefault(g.gpu, []).append(g)
    gpus = [GpuUse(gpu=name, samples=sum(u.samples for u in uses),
                   util_percent_mean=_weighted([(u.util_percent_mean, u.samples) for u in uses]),
                   util_percent_max=max(u.util_percent_max for u in uses),
                   peak_memory_bytes=max(u.peak_memory_bytes for u in uses)) for name, uses in by_gpu.items()]
    return GpuStats(samples=sum(s.samples for s in stats), interval_s=stats[-1].interval_s,
                    util_percent_mean=_weighted([(g.util_percent_mean, g.samples) for g in gpus]),
                    peak_memory_bytes=max(g.peak_memory_bytes for g in gpus), gpus=gpus)


def merge_host(stats: list[HostMemoryStats]) -> HostMemoryStats | None:
    """The sessions' host-memory samples as one: the highest peaks."""
    if not stats:
        return None
    hosts = [s.peak_host_used_bytes for s in stats if s.peak_host_used_bytes is not None]
    return HostMemoryStats(samples=sum(s.samples for s in stats), interval_s=stats[-1].interval_s,
                           peak_workers_rss_bytes=max(s.peak_workers_rss_bytes for s in stats),
                           peak_worker_rss_bytes=max(s.peak_worker_rss_bytes for s in stats),
                           peak_host_used_bytes=max(hosts) if hosts else None)


def build_report(records: list[RequestRecord], sessions: list[Session], requested: int, **fields: Any
                 ) -> ThroughputReport:
    """The figures from the records of the benchmark's requests (one each, the latest) and its sessions."""
    records = sorted(records, key=lambda r: r.line)
    ok = [r for r in records if r.status == "ok"]
    failed = [r for r in records if r.status != "ok"]
    wall = sum(session_wall_s(s, records) for s in sessions)

    def per_hour(n: int) -> float:
        return round(3600.0 * n / wall, 2) if wall > 0 else 0.0

    config = sessions[-1].config
    l3_passed = sum(bool(r.l3_passed) for r in ok) if config.l3 else None

    timed = [r for r in ok if r.stage_s and r.wall_s]
    totals: dict[str, float] = {}
    for r in timed:
        for stage, seconds in r.stage_s.items():
            totals[stage] = totals.get(stage, 0.0) + seconds
        totals[OTHER] = totals.get(OTHER, 0.0) + max(0.0, (r.wall_s or 0.0) - sum(r.stage_s.values()))
    order = [s for s in STAGES if s in totals] + sorted(set(totals) - set(STAGES) - {OTHER}) + [OTHER]
    grand = sum(totals.values())
    stage_s = {s: round(totals[s] / len(timed), 3) for s in order if s in totals}
    share = {s: round(totals[s] / grand, 4) for s in order if s in totals} if grand > 0 else {}

    sizes = [r.asset_bytes for r in ok if r.asset_bytes is not None]
    size_stats = SizeStats(assets=len(sizes), mean=round(statistics.fmean(sizes), 1),
                           median=float(statistics.median(sizes)), min=min(sizes), max=max(sizes),
                           total=sum(sizes)) if sizes else None

    failures: dict[str, Failure] = {}
    for r in failed:
        key = reason_key(r.reason)
        f = failures.setdefault(key, Failure(count=0, names=[], example=(r.reason or "")[:300]))
        f.count += 1
        f.names.append(r.name)

    return ThroughputReport(
        config=config, requested=requested, ok=len(ok), failed=len(failed), pending=requested - len(records),
        l3_passed=l3_passed, wall_s=round(wall, 3), assets_per_hour=per_hour(len(ok)),
        l3_passed_per_hour=per_hour(l3_passed) if l3_passed is not None else None,
        request_wall_s=_stats([r.wall_s for r in ok if r.wall_s]), stage_s_per_asset=stage_s, stage_share=share,
        gpu=merge_gpu([s.gpu for s in sessions if s.gpu is not None]),
        host_memory=merge_host([s.host_memory for s in sessions if s.host_memory is not None]),
        bytes_per_asset=size_stats,
        cache={"tasks_executed": sum(r.tasks_executed or 0 for r in records),
               "tasks_cached": sum(r.tasks_cached or 0 for r in records)},
        failures=dict(sorted(failures.items(), key=lambda kv: -kv[1].count)),
        sessions=sessions, records=records, **fields)


def summary_lines(report: ThroughputReport) -> list[str]:
    """The report in a few lines for the terminal (the JSON holds everything)."""
    mb = 1e6
    lines = [f"{report.ok} of {report.requested} assets published ({report.failed} failed, {report.pending} pending) "
             f"in {report.wall_s:.0f} s over {len(report.sessions)} session(s): "
             f"{report.assets_per_hour:.1f} distinct assets per hour"
             + (f", {report.l3_passed_per_hour:.1f} with L3 passed" if report.l3_passed_per_hour is not None else "")]
    c = report.config
    lines.append(f"workers: {c.workers} on {'GPUs ' + ','.join(c.gpus) if c.gpus else 'the CPU'}"
                 + (f" ({c.workers_per_gpu} per GPU)" if c.gpus else "") + f"; L3 {'on' if c.l3 else 'off'}")
    if report.stage_share:
        shares = report.stage_share
        lines.append("time per asset: " + ", ".join(
            f"{s} {report.stage_s_per_asset[s]:.1f} s ({100 * shares[s]:.0f} %)" for s in shares))
    if report.gpu is not None:
        lines.append(f"GPU: {report.gpu.util_percent_mean:.0f} % mean utilisation, peak memory "
                     f"{report.gpu.peak_memory_bytes / mb:.0f} MB ({report.gpu.samples} samples)")
    else:
        lines.append("GPU: not sampled (no nvidia-smi)")
    if report.host_memory is not None:
        lines.append(f"host memory: workers' RSS peak {report.host_memory.peak_workers_rss_bytes / mb:.0f} MB "
                     f"(one process {report.host_memory.peak_worker_rss_bytes / mb:.0f} MB)")
    if report.bytes_per_asset is not None:
        b = report.bytes_per_asset
        lines.append(f"asset size: mean {b.mean / mb:.1f} MB, max {b.max / mb:.1f} MB, {b.total / mb:.0f} MB in all")
    for key, f in report.failures.items():
        lines.append(f"failed ({f.count}): {key}: {', '.join(f.names[:5])}{' ...' if len(f.names) > 5 else ''}")
    return lines
