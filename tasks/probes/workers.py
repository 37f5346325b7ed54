"""How many independent probe rollouts run side by side in threads on the CPU (tasks.mpm.side_by_side runs them).

Warp's CPU launches release the GIL, and since the engine replays them with a prebuilt argument struct
(tasks/mpm/cpu_launch.py) little Python runs between them: two 1k-particle rollouts in two threads take 0.40-0.44 s
against 0.60-0.62 s one after another on the 2-core VM (benchmarks/engine/BENCHMARKS.md), with the same results
bit for bit. On CUDA the rollouts share the device's stream and its graph captures, so they run one at a time there.
"""

from __future__ import annotations

import os

# at most this many probe rollouts at a time (1 = one after another); default: the cores this process may use
PROBE_WORKERS_ENV = "DEFORMSMITH_PROBE_WORKERS"


def cores() -> int:
    """CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def probe_workers(n_jobs: int, device: str = "cpu") -> int:
    """Threads for n_jobs independent rollouts: 1 on CUDA, else min(jobs, cores, $DEFORMSMITH_PROBE_WORKERS)."""
    if device != "cpu" or n_jobs <= 1:
        return 1
    env = os.environ.get(PROBE_WORKERS_ENV, "").strip()
    cap = int(env) if env.isdigit() and int(env) > 0 else cores()
    return max(1, min(n_jobs, cores(), cap))


# the numerical libraries' thread pools (OpenMP: CoACD, scikit-image; BLAS: numpy, scipy): each sizes itself to every
# core of the machine, so 24 workers on 32 cores ran 768 spinning threads (s30: L0 and L1 slowed 2-25x with 24 workers)
POOL_THREAD_ENVS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def child_probe_workers(processes: int) -> dict[str, str]:
    """Environment for one of `processes` concurrent worker processes (batch, eval): the cores shared out, so the
    workers' probes and thread pools together do not run more threads than there are cores; a variable the user set
    is left as it is."""
    share = str(max(1, cores() // max(1, processes)))
    return {name: share for name in (PROBE_WORKERS_ENV, *POOL_THREAD_ENVS) if name not in os.environ}


__all__ = ["POOL_THREAD_ENVS", "PROBE_WORKERS_ENV", "child_probe_workers", "cores", "probe_workers"]
