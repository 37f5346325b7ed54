"""Driver for ncu: `batch` bench cubes of n^3 particles advanced `warm` steps (to rest on the ground), then `steps`
steps (multi-step graphs, as the bench runs them) inside cudaProfilerStart/Stop; further arguments are
``contracts.sim.KernelOptions`` name=value pairs. Device machine only (uses the image's PyTorch for the profiler
calls), e.g.

    ncu --profile-from-start off --clock-control none --cache-control none -o $OUT/prof \
        --section SpeedOfLight --section Occupancy --section LaunchStats --section WarpStateStats \
        python3 -m benchmarks.engine.gpu_ncu_drive 20 16 1200 12 [name=value ...]
    ncu -i $OUT/prof.ncu-rep --page raw --csv > $OUT/ncu_raw.csv
"""
from __future__ import annotations

import sys

from contracts.sim import KernelOptions
from tasks.mpm.scene import BENCH_DT_S, bench_cube_model
from tasks.mpm.simulator import Simulator


def main() -> None:
    import torch  # the device image's; only for cudaProfilerStart/Stop
    import warp as wp

    n, batch, warm, steps = (int(a) for a in sys.argv[1:5])
    kernel = KernelOptions.from_assignments(sys.argv[5:])
    wp.init()
    sim = Simulator(bench_cube_model(n, batch, "cuda", kernel=kernel), health_interval_steps=100)
    sim.advance(warm * BENCH_DT_S * 1.5, max_steps=warm)
    sim.advance(steps * BENCH_DT_S * 1.5, max_steps=steps)  # capture the profiled call's graphs first
    wp.synchronize_device("cuda")
    torch.cuda.profiler.start()
    sim.advance(steps * BENCH_DT_S * 1.5, max_steps=steps)
    wp.synchronize_device("cuda")
    torch.cuda.profiler.stop()
    print("done", sim.solver.steps)


if __name__ == "__main__":
    main()
