"""Concurrency probe for the batch target (issue 3): 16 x 8k bench cubes as G groups, each a Simulator on its own
CUDA stream, all replayed from one host thread (graphs captured in a warm-up of the same sequence), against one
16-scene batch and against the 16 scenes one after another on one stream. No health checks in the timed part.

    python3 -m benchmarks.engine.gpu_streams        # device machine, repo root, Warp + pydantic on PYTHONPATH
"""

from __future__ import annotations

import json
import time

import numpy as np
import warp as wp

from tasks.mpm.scene import BENCH_DT_S, bench_cube_model
from tasks.mpm.simulator import Simulator

N_PER_AXIS = 20  # 8,000 particles per scene
STEPS = 2000
CHUNK = 100


def run(groups: int, per: int, same_stream: bool = False, device: str = "cuda") -> tuple[float, bool]:
    """us per step of `groups` simulators of `per` scenes each, replayed round-robin in chunks of CHUNK steps."""
    sims = [Simulator(bench_cube_model(N_PER_AXIS, per, device), health_interval_steps=100) for _ in range(groups)]
    streams = [wp.get_stream(device)] * groups if same_stream else [wp.Stream(device) for _ in range(groups)]

    def go(steps: int) -> None:
        for _ in range(steps // CHUNK):
            for s, st in zip(sims, streams):
                with wp.ScopedStream(st):
                    s.solver.advance_steps(s.state, s.control, BENCH_DT_S, CHUNK)
        wp.synchronize_device(device)

    go(STEPS)  # warm-up: captures every graph of the timed sequence
    t = time.perf_counter()
    go(STEPS)
    sec = time.perf_counter() - t
    return sec / STEPS * 1e6, all(bool(np.all(np.isfinite(s.particles()["x"]))) for s in sims)


def main() -> None:
    wp.init()
    plan = [("single_8k", 1, 1, False), ("batch16", 1, 16, False), ("seq16_one_stream", 16, 1, True),
            ("2x8_streams", 2, 8, False), ("4x4_streams", 4, 4, False), ("8x2_streams", 8, 2, False),
            ("16x1_streams", 16, 1, False), ("batch16_again", 1, 16, False), ("single_8k_again", 1, 1, False)]
    res = {}
    for name, groups, per, same in plan:
        us, fin = run(groups, per, same)
        res[name] = {"us_per_step": us, "finite": fin}
        print(f"{name:18s} {us:8.2f} us/step finite={fin}", flush=True)
    print(json.dumps({"device": wp.get_device("cuda").name, "steps": STEPS, "runs": res}))


if __name__ == "__main__":
    main()
