"""CPU steps whose g2p also does the next step's p2g (kernels.g2p_p2g_cpu, Solver.cpu_fuse): the same rollout, bit for
bit, as separate g2p and p2g passes, on one and two threads, with colliders, re-fits, a sliding lattice and a failure
flag; and the fused pass really runs."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.sim import KernelOptions, SimConfig
from tasks.mpm import Simulator, build_model
from tasks.mpm import kernels as K
from tasks.mpm.scene import box_scene
from tests.mpm.scenes import MAT, pressed_and_thrown


def _rollout(threads: int, kernel: KernelOptions | None = None) -> tuple[dict, Simulator]:
    """A cube pressed by a moving box, a cube thrown onto the ground, a cube carried by a sliding lattice; 0.03 s."""
    c = box_scene((0.0, 0.0, 0.01), (0.03, 0.03, 0.04), 0.0025, MAT, 400.0, velocity_m_per_s=(0.0, 0.3, 0.0))
    cfg = SimConfig(device="cpu", dt_fixed_s=1e-4, cpu_threads=threads, kernel=kernel or KernelOptions())
    sim = Simulator(build_model([*pressed_and_thrown(), c], cfg), health_interval_steps=37)
    out: dict = {}
    for k, slide in enumerate(((0.0, 0.0, 0.0), (0.0, 0.3, 0.0), (0.0, 0.0, 0.0))):
        sim.control.set_grid_velocity(2, slide)  # the middle interval re-fits every step (no fused steps)
        rep = sim.advance(0.01)
        assert rep.health.ok
        out[f"ground{k}"], out[f"collider{k}"] = rep.ground_force_n, rep.collider_force_n
    out.update(sim.particles())
    out["fail_step"], out["fail_particle"] = sim.solver.read_failures()
    return out, sim


@pytest.mark.parametrize("threads", [1, 2])
def test_fused_cpu_steps_give_the_separate_passes_rollout_bit_for_bit(threads: int) -> None:
    fused, sim = _rollout(threads)
    assert sim.solver.plan.fuse
    kernels = [getattr(c, "kernel", None) for e in sim.solver._graphs.values() for c in e[0]]
    kernels += [x.kernel for e in sim.solver._graphs.values() for c in e[0] for x in getattr(c, "cmds", [])]
    assert K.g2p_p2g_cpu in kernels and K.p2g_apic_neohookean in kernels
    n_fused = sum(1 for key in sim.solver._graphs if key[-1])
    assert n_fused >= 1
    plain, sim_plain = _rollout(threads, KernelOptions(cpu_fuse=False))
    assert not sim_plain.solver.plan.fuse
    assert K.g2p_p2g_cpu not in [getattr(c, "kernel", None) for e in sim_plain.solver._graphs.values()
                                 for c in e[0]]
    for k, v in plain.items():
        np.testing.assert_array_equal(fused[k], v, err_msg=f"{k} ({threads} threads)")
    assert np.abs(fused["collider0"]).sum() > 0 and np.abs(fused["ground1"]).sum() > 0


def test_preloaded_modules_cover_every_cpu_launch() -> None:
    """tasks.mpm.cpu_launch.load_cpu_modules loads what a CPU rollout launches (fused and chunked steps, colliders,
    re-fits, a sliding lattice): the rollout loads no Warp module after it, so rollouts side by side in threads never
    load one at the same time."""
    from warp._src.context import user_modules

    from tasks.mpm.cpu_launch import load_cpu_modules

    def loaded() -> dict:
        return {name: dict(m.execs) for name, m in list(user_modules.items()) if m.execs}

    load_cpu_modules()
    before = loaded()
    assert K.g2p_p2g_cpu.module.name in before and K.__name__ in before
    _rollout(2)
    assert loaded() == before


def test_grid_update_that_merges_the_chunk_grids_gives_the_separate_merge_rollout_bit_for_bit() -> None:
    folded, sim = _rollout(2)
    assert sim.solver.plan.merge_fold and sim.solver.plan.chunks is not None
    kernels = [getattr(c, "kernel", None) for e in sim.solver._graphs.values() for c in e[0]]
    assert K.grid_update_merge_cpu in kernels and K.grid_update not in kernels
    separate, sim_sep = _rollout(2, KernelOptions(cpu_merge=False))
    assert not sim_sep.solver.plan.merge_fold
    assert K.grid_update_merge_cpu not in [getattr(c, "kernel", None) for e in sim_sep.solver._graphs.values()
                                           for c in e[0]]
    for k, v in separate.items():
        np.testing.assert_array_equal(folded[k], v, err_msg=k)
    # the chunks' buffers are left clear for the next scatter
    assert not sim.solver.plan.chunks.grid_parts.numpy().any()
