"""A CUDA graph capture survives Python's garbage collector: a collection in the middle of a capture freed an
unreachable solver's pinned host buffer (its release synchronises with the legacy stream) and the capture failed with Warp CUDA error 906 or 901 (two
requests of session 40's 1-GPU throughput run, two of the 2-GPU runs before). Here every allocation is made to start
a collection (threshold 1) while cyclic garbage holding device arrays waits, and a rollout captures its graphs."""

from __future__ import annotations

import gc

import pytest
import warp as wp

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import Simulator, build_model
from tasks.mpm.scene import box_scene

pytestmark = pytest.mark.gpu

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)


class _Cycle:
    """Unreachable memory only the cyclic collector frees: a device array and a pinned host buffer, as a finished
    rollout's solver holds for its readbacks (freeing pinned memory synchronises with the legacy stream)."""

    def __init__(self) -> None:
        self.me = self
        self.array = wp.zeros(4096, dtype=float, device="cuda")
        self.staging = wp.zeros(4096, dtype=float, device="cpu", pinned=True)


def test_a_collection_during_a_capture_frees_nothing_and_the_rollout_runs() -> None:
    if not wp.is_cuda_available():
        pytest.skip("no CUDA device")
    before = gc.get_threshold()
    try:
        gc.set_threshold(1, 1, 1)
        for _ in range(200):
            _Cycle()  # garbage for the next collection
        model = build_model([box_scene((0.0, 0.0, 0.001), (0.04, 0.04, 0.041), 0.004, MAT, 400.0)],
                            SimConfig(device="cuda", dt_fixed_s=1e-4))
        sim = Simulator(model)
        for _ in range(5):
            for _ in range(50):
                _Cycle()
            rep = sim.advance(0.01)
            assert rep.health.ok, rep.health.issues
        assert gc.isenabled()
    finally:
        gc.set_threshold(*before)
        gc.collect()
