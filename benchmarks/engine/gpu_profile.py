"""Per-kernel GPU time of the MPM step on the standard cube (CUDA activity timing, no graphs).

    python -m benchmarks.engine.gpu_profile --particles 8000 [--batch 16] [--steps 60] [--warmup N] [--json] \
        [--kernel name=value ...]

Runs `steps` plain (ungraphed) steps after a warm-up (default: two re-fit cycles, the cube still falling; --warmup 1200
profiles it on the ground, where the ground contact runs, as in most of the bench's steps) and prints the mean time
per launch of each kernel [us] and the share of the re-fit launches per step. ``--kernel cuda_fast=false`` profiles
the plain kernels (any ``contracts.sim.KernelOptions`` field can be set so).
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict

import warp as wp

from contracts.sim import KernelOptions
from tasks.mpm.scene import BENCH_DT_S, bench_cube_model
from tasks.mpm.simulator import Simulator


def profile(particles: int, batch: int = 1, steps: int = 60, warmup: int | None = None,
            kernel: KernelOptions | None = None) -> dict:
    """Mean GPU time per launch [us] of each kernel over `steps` ungraphed steps (after a warm-up)."""
    wp.init()
    n = max(2, int(round(particles ** (1.0 / 3.0))))
    sim = Simulator(bench_cube_model(n, batch, "cuda", kernel=kernel), health_interval_steps=10**9, use_graph=False)
    solver = sim.solver
    if warmup is None:
        warmup = 2 * (sim.model.refit_interval + 1)
    sim.advance(warmup * BENCH_DT_S * 1.5, max_steps=warmup)  # as the bench: health checks on the way
    for _ in range(2 * (sim.model.refit_interval + 1)):
        solver.step(sim.state, sim.state, sim.control, BENCH_DT_S)
    wp.synchronize_device("cuda")
    wp.timing_begin(cuda_filter=wp.TIMING_KERNEL)
    for _ in range(steps):
        solver.step(sim.state, sim.state, sim.control, BENCH_DT_S)
    results = wp.timing_end()
    per: dict[str, list[float]] = defaultdict(list)
    for r in results:
        name = r.name.removeprefix("forward kernel ").rsplit("_", 1)[0]  # drop the module hash
        per[name].append(r.elapsed * 1e3)  # ms -> us
    kernels = {k: {"launches": len(v), "mean_us": sum(v) / len(v), "per_step_us": sum(v) / steps}
               for k, v in sorted(per.items())}
    return {
        "device_name": wp.get_device("cuda").name,
        "particles": sim.model.n_particles,
        "batch": batch,
        "steps": steps,
        "warmup_steps": warmup,
        "refit_interval": sim.model.refit_interval,
        "fast_cuda": bool(solver.fast_cuda),
        "kernel_options": sim.model.config.kernel.model_dump(mode="json"),
        "kernels": kernels,
        "kernel_us_per_step": sum(k["per_step_us"] for k in kernels.values()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=8000)
    ap.add_argument("--batch", type=int, default=1)
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--warmup", type=int, default=None, help="steps before profiling (default: 2 re-fit cycles)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--kernel", action="append", default=[], help="KernelOptions name=value (repeatable)")
    a = ap.parse_args()
    r = profile(a.particles, a.batch, a.steps, a.warmup, KernelOptions.from_assignments(a.kernel))
    if a.json:
        print(json.dumps(r))
        return
    print(f"{r['device_name']} particles={r['particles']} batch={r['batch']} fast={r['fast_cuda']} "
          f"R={r['refit_interval']} kernel time/step={r['kernel_us_per_step']:.1f} us")
    for k, v in r["kernels"].items():
        print(f"  {k:40s} {v['launches']:5d} launches {v['mean_us']:8.1f} us each {v['per_step_us']:8.1f} us/step")


if __name__ == "__main__":
    main()
