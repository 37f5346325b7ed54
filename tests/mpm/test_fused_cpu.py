"""The fast CUDA path's fused g2p + next p2g (kernels_cuda.make_g2p2g) and row-scan scatter, run through their
kernels' CPU branches (one particle per thread): the same steps as the unfused kernels, bit for bit. This checks the
fused step's bookkeeping (which step's p2g runs where, the clock, the grid window) on the CPU; the CUDA code paths
themselves are checked against the CPU by test_cuda_fast.py (gpu)."""

from __future__ import annotations

import numpy as np

from contracts.material import Material
from contracts.sim import KernelOptions, SimConfig
from tasks.mpm import Simulator, build_model
from tasks.mpm.plan_cuda import CudaLaunchPlan
from tests.mpm.scenes import MAT, pressed_and_thrown


def _model(material: Material | None = None):
    """A cube pressed by a moving box and a thrown cube in shuffled order, both landing on the ground (material: both
    cubes', else tests.mpm.scenes.MAT)."""
    rng = np.random.default_rng(5)
    a, b = pressed_and_thrown(0.005)
    if material is not None:
        a.material = b.material = material
    perm = rng.permutation(len(b.positions_m))
    b.positions_m, b.volumes_m3 = b.positions_m[perm], b.volumes_m3[perm]
    b.velocities_m_per_s = b.velocities_m_per_s[perm]
    return build_model([a, b], SimConfig(device="cpu", dt_fixed_s=1e-4))


def _run(fuse: bool, scatter: str, steps: int = 40, block: int = 13, keep_c: bool = False, lazy: bool = False,
         material: Material | None = None) -> dict:
    """`steps` steps of the fast CUDA path's launches on the CPU, in blocks as Solver._launch_block records them."""
    sim = Simulator(_model(material), use_graph=False)
    sol, st, ctl = sim.solver, sim.state, sim.control
    opts = KernelOptions(specialize=False, agg=False, coop_min_particles=0, p2g_parts=1, fuse=fuse, scatter=scatter,
                         fuse_keep_c=keep_c, grid_lazy=lazy)
    sol.plan = CudaLaunchPlan(sol, opts)  # the fast CUDA path's plan, one particle per thread, on the CPU
    assert sol.plan.with_colliders and sol.plan.coop_g2p and not sol.plan.agg
    ctl.sync(sol.time_s)
    sol.slide = ctl.d_grid_slide
    sol.set_dt(1e-4)
    R = sol.refit_interval(ctl)
    done, fused = 0, 0
    while done < steps:
        n = min(block, steps - done)
        since, prev = sol._since_refit, False
        for k in range(n):
            refit = since >= R
            since = 0 if refit else since + 1
            fuse_next = sol.plan.fuse and k + 1 < n and since < R
            for cmd in sol.plan.record_step(st, st, ctl, refit, skip_p2g=prev, fuse_next=fuse_next):
                fused += "g2p2g" in cmd.kernel.key
                cmd.launch()
            prev = fuse_next
        sol._since_refit = since
        sol.steps += n
        done += n
    out = {k: getattr(st, k).numpy() for k in ("x", "v", "F", "C")}
    out.update(ground=sol.ground_impulse.numpy(), collider=sol.collider_impulse.numpy(), fail=sol.fail_step.numpy(),
               clock=sol.clock_step.numpy(), fused=np.asarray(fused))
    return out


def test_fused_step_matches_unfused_bit_for_bit() -> None:
    ref = _run(False, "warp")
    # keep_c=False: the fused kernel neither loads nor stores C; the block's last (plain) g2p writes it
    # lazy: the grid update skips the nodes without mass (the window moves with both cubes: stale velocities are
    # left at nodes that change place, and never read with a non-zero weight)
    for scatter, keep_c, lazy in (("warp", True, False), ("scan", True, False), ("scan", False, False),
                                  ("scan", False, True)):
        out = _run(True, scatter, keep_c=keep_c, lazy=lazy)
        assert int(out.pop("fused")) > 20  # most steps ran fused
        for k, a in out.items():
            np.testing.assert_array_equal(a, ref[k], err_msg=f"{k} (scatter {scatter}, keep_c {keep_c}, lazy {lazy})")
    assert int(ref["clock"][0]) == 40
    assert np.abs(ref["ground"]).sum() > 0 and np.abs(ref["collider"]).sum() > 0  # both contacts were exercised


def test_the_cuda_variants_carry_the_viscosity() -> None:
    """A viscous material (eta 20 Pa s) through the fast CUDA path's kernels (plain p2g, fused g2p2g with C kept in
    registers): fused and unfused agree bit for bit, match the CPU plan's rollout, and differ from eta = 0."""
    visc = MAT.model_copy(update={"viscosity_pa_s": 20.0})
    ref = _run(False, "warp", material=visc)
    fused = _run(True, "scan", keep_c=False, material=visc)
    assert int(fused.pop("fused")) > 20
    for k in ("x", "v", "F", "ground", "collider"):
        np.testing.assert_array_equal(fused[k], ref[k], err_msg=k)
    sim = Simulator(_model(visc))  # the CPU plan (fused CPU steps)
    sim.solver.advance_steps(sim.state, sim.control, 1e-4, 40)
    np.testing.assert_allclose(sim.particles()["x"], ref["x"], atol=1e-6)
    elastic = _run(False, "warp")
    assert np.abs(elastic["v"] - ref["v"]).max() > 1e-3  # the viscosity acted
