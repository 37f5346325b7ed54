"""What a throughput run samples in the background, about once a second: the GPUs (`nvidia-smi`: utilisation and
memory in use) and the host memory of the batch's worker processes (the resident set sizes of every request process
and its descendants, read from /proc). Each sampler is a daemon thread started and stopped by the run; what it saw
is a small typed summary (SI: bytes, seconds; utilisation in percent)."""

from __future__ import annotations

import os
import shutil
import subprocess
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel, Field

NVIDIA_SMI = "nvidia-smi"
GPU_QUERY = ("--query-gpu=utilization.gpu,memory.used", "--format=csv,noheader,nounits")
MIB = 1024 * 1024
WORKER_MARKER = "flows.batch_job"  # a batch request's process: `python -P -m flows.batch_job ...` (flows.batch)


class GpuUse(BaseModel):
    """One GPU over a run: mean and peak utilisation, peak memory in use (all processes on it, as nvidia-smi says)."""

    gpu: str = Field(description="the index (or UUID) nvidia-smi and CUDA_VISIBLE_DEVICES name it by")
    samples: int
    util_percent_mean: float
    util_percent_max: float
    peak_memory_bytes: int


class GpuStats(BaseModel):
    """What the GPU sampler saw: per GPU, and the mean utilisation over every GPU and sample."""

    samples: int
    interval_s: float
    util_percent_mean: float
    peak_memory_bytes: int = Field(description="the highest memory in use on any one GPU")
    gpus: list[GpuUse]


class HostMemoryStats(BaseModel):
    """What the host-memory sampler saw (bytes). RSS counts pages shared between processes once per process, so the
    sum is an upper bound of what the workers hold together."""

    samples: int
    interval_s: float
    peak_workers_rss_bytes: int = Field(description="the largest sum of RSS over the worker processes and their "
                                        "children at one sample")
    peak_worker_rss_bytes: int = Field(description="the largest RSS of one process of them at one sample")
    peak_host_used_bytes: int | None = Field(default=None, description="the largest MemTotal - MemAvailable of the "
                                             "whole machine (other jobs included); None without /proc/meminfo")


# ---- GPUs ------------------------------------------------------------------------------------------


def nvidia_smi_available() -> bool:
    """Whether nvidia-smi is on PATH."""
    return shutil.which(NVIDIA_SMI) is not None


def parse_gpu_query(text: str) -> list[tuple[float | None, float | None]]:
    """nvidia-smi's `utilization.gpu,memory.used` CSV (no header, no units) -> (percent, MiB) per line, in order;
    a field nvidia-smi cannot read ('[N/A]', '[Not Supported]') is None."""

    def number(field: str) -> float | None:
        try:
            return float(field.strip())
        except ValueError:
            return None

    rows = []
    for line in text.splitlines():
        if not line.strip():
            continue
        parts = line.split(",")
        rows.append((number(parts[0]), number(parts[1]) if len(parts) > 1 else None))
    return rows


def query_gpus(gpus: list[str] | None, timeout_s: float = 5.0) -> str:
    """One nvidia-smi query (of the GPUs named, else of every GPU); its stdout."""
    cmd = [NVIDIA_SMI, *GPU_QUERY] + (["-i", ",".join(gpus)] if gpus else [])
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s, check=True).stdout


def list_gpus(timeout_s: float = 10.0) -> list[str] | None:
    """The GPUs this process may use, by the names CUDA_VISIBLE_DEVICES takes: its own list when it is set, else
    nvidia-smi's indices; None when neither says (no nvidia-smi)."""
    visible = os.environ.get("CUDA_VISIBLE_DEVICES")
    if visible is not None:
        return [g.strip() for g in visible.split(",") if g.strip()]
    if not nvidia_smi_available():
        return None
    try:
        out = subprocess.run([NVIDIA_SMI, "--query-gpu=index", "--format=csv,noheader"], capture_output=True,
                             text=True, timeout=timeout_s, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    return [line.strip() for line in out.splitlines() if line.strip()]


def _mean(values: list[float]) -> float:
    return round(sum(values) / len(values), 2) if values else 0.0


class _Sampler:
    """A daemon thread that calls `sample()` every interval_s until stopped (once more at the stop). Its `stats()` may
    be read while it runs (the heartbeat writes them with each beat): a sample's result is added under `_lock`."""

    def __init__(self, interval_s: float) -> None:
        self.interval_s = interval_s
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    def sample(self) -> None:  # pragma: no cover - overridden
        raise NotImplementedError

    def _loop(self) -> None:
        while True:
            try:
                self.sample()
            except Exception:  # a failed sample (a process gone mid-read, nvidia-smi busy) is one sample missed
                pass
            if self._stop.wait(self.interval_s):
                return

    def start(self) -> None:
        self._thread = threading.Thread(target=self._loop, name=type(self).__name__, daemon=True)
        self._thread.start()

    def stop(self, timeout_s: float = 10.0) -> None:
        """Stop sampling; wait up to timeout_s for a sample under way (its stats are whole either way)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=timeout_s)


class GpuSampler(_Sampler):
    """Samples utilisation and memory in use of the GPUs named (all when None) through nvidia-smi. `query` stands in
    for nvidia-smi in tests: () -> its CSV output."""

    def __init__(self, gpus: list[str] | None = None, interval_s: float = 1.0,
                 query: Callable[[], str] | None = None) -> None:
        super().__init__(interval_s)
        self.gpus = gpus
        self.query = query or (lambda: query_gpus(gpus))
        self.rows: list[list[tuple[float | None, float | None]]] = []

    def sample(self) -> None:
        rows = parse_gpu_query(self.query())  # (outside the lock: nvidia-smi may take a second)
        if rows:
            with self._lock:
                self.rows.append(rows)

    @staticmethod
    def _column(samples: list[list[tuple[float | None, float | None]]], gpu: int, field: int) -> list[float]:
        """The readable values of one field (0: utilisation, 1: memory) of one GPU over the samples."""
        out = []
        for rows in samples:
            value = rows[gpu][field] if gpu < len(rows) else None
            if value is not None:
                out.append(value)
        return out

    def stats(self) -> GpuStats | None:
        """The summary (of the samples so far, while it runs); None when no sample was read."""
        with self._lock:
            samples = list(self.rows)
        if not samples:
            return None
        n = max(len(r) for r in samples)
        names = self.gpus if self.gpus and len(self.gpus) == n else [str(i) for i in range(n)]
        per: list[GpuUse] = []
        all_util: list[float] = []
        for i, name in enumerate(names):
            util, mem = self._column(samples, i, 0), self._column(samples, i, 1)
            all_util += util
            per.append(GpuUse(gpu=name, samples=len(util), util_percent_mean=_mean(util),
                              util_percent_max=max(util, default=0.0),
                              peak_memory_bytes=int(max(mem, default=0.0) * MIB)))
        return GpuStats(samples=len(samples), interval_s=self.interval_s,
                        util_percent_mean=_mean(all_util),
                        peak_memory_bytes=max(g.peak_memory_bytes for g in per), gpus=per)


# ---- host memory -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class ProcInfo:
    """One process as /proc shows it."""

    ppid: int
    rss_bytes: int
    cmdline: str


def read_process(proc_dir: Path, page_bytes: int) -> ProcInfo | None:
    """ppid (from stat), RSS (statm's resident pages) and command line of one /proc/<pid>; None when it is gone."""
    try:
        stat = (proc_dir / "stat").read_text()
        statm = (proc_dir / "statm").read_text().split()
        cmdline = (proc_dir / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
    except (OSError, IndexError):
        return None
    fields = stat.rsplit(")", 1)[-1].split()  # the name, in parentheses, may hold spaces and parentheses
    try:
        return ProcInfo(ppid=int(fields[1]), rss_bytes=int(statm[1]) * page_bytes, cmdline=cmdline)
    except (IndexError, ValueError):
        return None


def process_table(proc_root: Path = Path("/proc"), page_bytes: int | None = None) -> dict[int, ProcInfo]:
    """Every process of a /proc tree, by pid."""
    page = page_bytes or os.sysconf("SC_PAGE_SIZE")
    table = {}
    for entry in proc_root.iterdir():
        if entry.name.isdigit():
            info = read_process(entry, page)
            if info is not None:
                table[int(entry.name)] = info
    return table


def worker_rss(table: dict[int, ProcInfo], root_pid: int, marker: str = WORKER_MARKER) -> tuple[int, int]:
    """(sum, largest) RSS of the worker processes under root_pid: its descendants whose command line holds
    `marker`, and every descendant of theirs (the encoders and helpers a request starts). Other children of root_pid
    (a local Prefect server) are not counted."""
    children: dict[int, list[int]] = {}
    for pid, info in table.items():
        children.setdefault(info.ppid, []).append(pid)
    counted: list[int] = []

    def walk(pid: int, inside: bool) -> None:
        for child in children.get(pid, []):
            here = inside or marker in table[child].cmdline
            if here:
                counted.append(child)
            walk(child, here)

    walk(root_pid, False)
    sizes = [table[p].rss_bytes for p in counted]
    return sum(sizes), max(sizes, default=0)


def host_used_bytes(meminfo: Path = Path("/proc/meminfo")) -> int | None:
    """MemTotal - MemAvailable of the machine [bytes]; None when unreadable."""
    try:
        values = {}
        for line in meminfo.read_text().splitlines():
            key, _, rest = line.partition(":")
            values[key] = int(rest.split()[0]) * 1024  # kB
        return values["MemTotal"] - values["MemAvailable"]
    except (OSError, KeyError, ValueError, IndexError):
        return None


class HostMemorySampler(_Sampler):
    """Samples the RSS of the worker processes under root_pid (flows.batch's request processes) from a /proc tree."""

    def __init__(self, root_pid: int | None = None, interval_s: float = 1.0, proc_root: Path = Path("/proc"),
                 page_bytes: int | None = None) -> None:
        super().__init__(interval_s)
        self.root_pid = root_pid if root_pid is not None else os.getpid()
        self.proc_root = proc_root
        self.page_bytes = page_bytes
        self.samples = 0
        self.peak_sum = self.peak_one = 0
        self.peak_host: int | None = None

    def sample(self) -> None:
        total, largest = worker_rss(process_table(self.proc_root, self.page_bytes), self.root_pid)
        used = host_used_bytes(self.proc_root / "meminfo")
        with self._lock:
            self.samples += 1
            self.peak_sum, self.peak_one = max(self.peak_sum, total), max(self.peak_one, largest)
            if used is not None:
                self.peak_host = max(self.peak_host or 0, used)

    def stats(self) -> HostMemoryStats | None:
        """The summary (of the samples so far, while it runs); None when nothing was sampled."""
        with self._lock:
            if not self.samples:
                return None
            return HostMemoryStats(samples=self.samples, interval_s=self.interval_s,
                                   peak_workers_rss_bytes=self.peak_sum, peak_worker_rss_bytes=self.peak_one,
                                   peak_host_used_bytes=self.peak_host)
