"""Benchmark of the standard scene: 0.2 m cube, n^3 particles, E = 1e5 Pa, nu = 0.3, rho = 200 kg/m^3, dt = 1e-4 s.

    python -m benchmarks.mpm_bench [--device cpu|cuda] [--particles N] [--steps N] [--batch N] [--workers N]
                                   [--cpu-threads N] [--compare-sequential] [--kernel NAME=V ...] [--json]
"""

from __future__ import annotations

import contextlib
import functools
import os
import platform
import resource
import sys
import time
from datetime import UTC, datetime

import numpy as np
import typer
import warp as wp

from contracts.errors import InputError, SimulationError
from contracts.sim import KernelOptions
from flows.cli.apps import emit_json, fail, results
from tasks.mpm.scene import BENCH_DT_S, bench_cube_model
from tasks.mpm.simulator import Simulator, side_by_side


def _cpu_name() -> str:
    """Processor model name (Linux /proc/cpuinfo, else platform)."""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "cpu"


def _model_bytes(sim: Simulator) -> int:
    """Bytes of the device arrays the engine holds for one simulator (state, model, grid, solver)."""
    total = 0
    seen: set[int] = set()
    for obj in (sim.state, sim.model, sim.solver, sim.control):
        for val in vars(obj).values():
            if isinstance(val, wp.array) and id(val) not in seen:
                seen.add(id(val))
                total += int(val.capacity)
    return total


def run_bench(
    device: str = "cpu", particles: int = 64000, steps: int = 200, batch: int = 1, workers: int | None = None,
    cpu_threads: int = 1, compare_sequential: bool = False, kernel: KernelOptions | None = None,
) -> dict:
    """Time `steps` fixed-dt steps of `batch` standard cubes of ~particles each; returns the figures as a dict.
    workers: CPU threads each advancing a share of the batch; cpu_threads: threads sharing each of those rollouts;
    compare_sequential: also run the batch's scenes one after another in the same process
    (``sequential_comparison``); kernel: the engine's kernel options (SimConfig.kernel; None = defaults)."""
    kernel = kernel or KernelOptions()
    if particles < 8 or steps < 1 or batch < 1 or not 1 <= cpu_threads <= 64:
        raise InputError("need particles >= 8, steps >= 1, batch >= 1, 1 <= cpu_threads <= 64")
    if compare_sequential and batch < 2:
        raise InputError("--compare-sequential needs --batch >= 2")
    if device not in ("cpu", "cuda"):
        raise InputError("device must be cpu or cuda")
    wp.init()
    if device == "cuda" and not wp.is_cuda_available():
        raise SimulationError("no CUDA device is available to Warp")
    n = max(2, int(round(particles ** (1.0 / 3.0))))
    if workers is None:
        workers = min(batch, os.cpu_count() or 1) if device == "cpu" else 1
    workers = max(1, min(workers, batch))
    shares = [batch // workers + (1 if i < batch % workers else 0) for i in range(workers)]
    sims = [Simulator(bench_cube_model(n, b, device, cpu_threads, kernel), health_interval_steps=100) for b in shares]

    # warm-up (excluded from the timing): kernel compilation/loading, CUDA graph capture, first launches. On CUDA
    # the warm-up replays the timed run's exact call sequence (every advance ends with a health check that re-fits
    # the grid, so both start at the same refit phase): each multi-step graph the timed run replays is captured
    # here, not inside the timing.
    duration = steps * BENCH_DT_S * 1.5  # max_steps ends the run at exactly `steps` steps
    t0 = time.perf_counter()
    warm = steps if device == "cuda" else 3
    for s in sims:
        s.advance(duration if device == "cuda" else 10 * BENCH_DT_S, max_steps=warm)
    wp.synchronize_device(device)
    warm_s = time.perf_counter() - t0

    t = time.perf_counter()
    if len(sims) == 1:
        reports = [sims[0].advance(duration, max_steps=steps)]
    else:
        reports = advance_parallel_steps(sims, duration, steps)
    wp.synchronize_device(device)
    seconds = time.perf_counter() - t

    total_particles = sum(s.model.n_particles for s in sims)
    finite = all(r.health.ok for r in reports) and all(
        bool(np.all(np.isfinite(s.particles()["x"]))) for s in sims
    )
    if device == "cuda":
        dev = wp.get_device("cuda")
        peak = int(wp.get_mempool_used_mem_high(dev)) if wp.is_mempool_enabled(dev) else None
        mem_kind = "gpu_mempool_high_water_bytes"
        dev_name = dev.name
    else:
        peak = int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024
        mem_kind = "host_peak_rss_bytes"
        dev_name = _cpu_name()
    engine_bytes = sum(_model_bytes(s) for s in sims)
    comparison = sequential_comparison(device, n, batch, steps, cpu_threads, seconds / steps * 1e6, kernel) \
        if compare_sequential else None
    return {
        "device": device,
        "device_name": dev_name,
        "warp_version": wp.config.version,
        "date_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "scene": "0.2 m cube, E=1e5 Pa, nu=0.3, rho=200 kg/m^3, 0.05 m above ground, fixed dt=1e-4 s",
        "particles": total_particles,
        "particles_per_scene": n**3,
        "batch": batch,
        "workers": len(sims),
        "cpu_threads": sims[0].model.config.cpu_threads,
        "kernel_options": kernel.model_dump(mode="json"),
        "steps": steps,
        "dt_s": BENCH_DT_S,
        "seconds": seconds,
        "us_per_step": seconds / steps * 1e6,
        "particle_steps_per_s": total_particles * steps / seconds,
        "peak_memory_bytes": peak,
        "peak_memory_kind": mem_kind,
        "engine_array_bytes": engine_bytes,
        "engine_bytes_per_particle": engine_bytes / total_particles,
        "grid_nodes": sum(s.solver.grid_nodes for s in sims),
        "finite": bool(finite),
        "health_ok": all(r.health.ok for r in reports),
        "warmup_excluded": True,
        "warmup_seconds": warm_s,
        "cuda_graph": bool(sims[0].solver.use_graph),
        "warmup_steps": warm,
        "note": "timing excludes the first launches (kernel compile/load, graph capture); includes health checks",
        "host": platform.node(),
        "cpu_count": os.cpu_count(),
        "sequential_comparison": comparison,
    }


def _rollout_seconds(device: str, n: int, batch: int, steps: int, cpu_threads: int, kernel: KernelOptions) -> float:
    """Wall time of one whole rollout of `batch` cubes: model build, simulator, `steps` steps (graph capture
    included; kernels already loaded in this process), synchronised."""
    t = time.perf_counter()
    sim = Simulator(bench_cube_model(n, batch, device, cpu_threads, kernel), health_interval_steps=100)
    sim.advance(steps * BENCH_DT_S * 1.5, max_steps=steps)
    wp.synchronize_device(device)
    return time.perf_counter() - t


def sequential_comparison(device: str, n: int, batch: int, steps: int, cpu_threads: int, batch_us: float,
                          kernel: KernelOptions | None = None) -> dict:
    """The batch against its scenes run one after another, in this process: per step (each scene's own timed run,
    warm-up excluded, as the batch's) and end to end (each rollout built and run from scratch: model, simulator,
    graph capture, steps; the batch likewise). Ratios > 1: the batch is faster."""
    kernel = kernel or KernelOptions()
    single = [run_bench(device, n**3, steps, 1, 1, cpu_threads, kernel=kernel)["us_per_step"] for _ in range(batch)]
    seq_e2e = [_rollout_seconds(device, n, 1, steps, cpu_threads, kernel) for _ in range(batch)]
    batch_e2e = _rollout_seconds(device, n, batch, steps, cpu_threads, kernel)
    return {
        "scenes": batch,
        "single_us_per_step": single,
        "sequential_us_per_step": float(sum(single)),
        "batch_us_per_step": batch_us,
        "ratio_per_step": float(sum(single)) / batch_us,
        "sequential_rollouts_s": float(sum(seq_e2e)),
        "batch_rollout_s": batch_e2e,
        "ratio_end_to_end": float(sum(seq_e2e)) / batch_e2e,
        "note": "per step: timed steps only, warm-up excluded, one scene at a time vs the batch; end to end: "
                f"{batch} whole rollouts of {steps} steps one after another (model build, graph capture, steps) vs "
                "one batched rollout, kernels already loaded",
    }


def advance_parallel_steps(sims: list[Simulator], duration: float, steps: int) -> list:
    """Advance each simulator by exactly `steps` steps, concurrently in threads."""
    return side_by_side([functools.partial(s.advance, duration, max_steps=steps) for s in sims], len(sims),
                        sims[0].model.device)


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
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
    try:
        options = KernelOptions.from_assignments(kernel or [])
    except ValueError as exc:
        fail(f"--kernel: {exc}")
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


if __name__ == "__main__":
    app()
