"""CUDA block-level kernels (kernels_cuda.py) against the plain CUDA kernels and the CPU: same rollouts, same health
reports, for ordered particles (shared-memory p2g), shuffled ones (global-atomic fallback) and batched scenes."""

from __future__ import annotations

import numpy as np
import pytest
import warp as wp

from contracts.material import Material
from contracts.sim import KernelOptions, SimConfig
from tasks.mpm import Simulator, box_collider, build_model
from tasks.mpm import kernels_cuda as KC
from tasks.mpm.plan_cpu import CpuLaunchPlan
from tasks.mpm.plan_cuda import CudaLaunchPlan
from tasks.mpm.scene import box_scene

pytestmark = pytest.mark.gpu

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)


def _need_cuda() -> None:
    if not wp.is_cuda_available():
        pytest.skip("no CUDA device")


def _scenes(shuffle: bool) -> list:
    """Three scenes of a 12^3 cube: one dropped on the ground, one pressed by a moving box, one thrown sideways."""
    out = []
    rng = np.random.default_rng(3)
    for k in range(3):
        kw = {}
        if k == 1:
            kw["colliders"] = [box_collider((0.02, 0.05, 0.05), position_m=(-0.021, 0.03, 0.05), friction=0.6,
                                            linear_velocity_m_per_s=(0.2, 0.0, 0.0))]
        if k == 2:
            kw["velocity_m_per_s"] = (0.5, 0.0, 0.3)
        sc = box_scene((0.0, 0.0, 0.001 + 0.01 * k), (0.06, 0.06, 0.061 + 0.01 * k), 0.005, MAT, 400.0, **kw)
        if shuffle:
            perm = rng.permutation(len(sc.positions_m))
            sc.positions_m = sc.positions_m[perm]
            sc.volumes_m3 = sc.volumes_m3[perm]
            if sc.velocities_m_per_s is not None:
                sc.velocities_m_per_s = sc.velocities_m_per_s[perm]
        out.append(sc)
    return out


def _rollout(device: str, fast: bool, shuffle: bool, **options) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    kernel = KernelOptions(cuda_fast=fast, **options)
    model = build_model(_scenes(shuffle), SimConfig(device=device, dt_fixed_s=1e-4, kernel=kernel))
    sim = Simulator(model)
    assert sim.solver.fast_cuda == (fast and device == "cuda")
    rep = sim.advance(0.03)
    assert rep.health.ok, rep.health.issues
    return sim.particles()["x"], rep.ground_force_n, rep.collider_force_n


@pytest.mark.parametrize("shuffle", [False, True])
def test_fast_cuda_path_matches_reference_and_cpu(shuffle: bool) -> None:
    _need_cuda()
    ref = _rollout("cuda", False, shuffle)
    fast = _rollout("cuda", True, shuffle)
    cpu = _rollout("cpu", False, shuffle)
    for other in (ref, cpu):
        np.testing.assert_allclose(fast[0], other[0], atol=1e-4)
        np.testing.assert_allclose(fast[1], other[1], rtol=2e-2, atol=2e-3)
        np.testing.assert_allclose(fast[2], other[2], rtol=2e-2, atol=2e-3)


def test_fast_cuda_refit_stats_match_reference() -> None:
    """Fused re-fit on one state: bounds, max speed and window exact, kinetic energy to float rounding."""
    _need_cuda()
    sim = Simulator(build_model(_scenes(True), SimConfig(device="cuda", dt_fixed_s=1e-4)))
    sim.advance(0.005)
    stats = []
    fast_plan = sim.solver.plan
    for plan in (CpuLaunchPlan(sim.solver, KernelOptions()), fast_plan):  # the reference plan, then the fast one
        sim.solver.plan = plan
        sim.solver._refit_cmds.clear()
        sim.solver.grid_origin.zero_()
        st = sim.solver.scene_stats(sim.state)
        st["origin"] = sim.solver.grid_origin.numpy()
        stats.append(st)
    for k in ("bmin", "bmax", "speed_max", "origin", "overflow"):
        np.testing.assert_array_equal(stats[0][k], stats[1][k])
    np.testing.assert_allclose(stats[0]["kinetic"], stats[1]["kinetic"], rtol=1e-5)


def test_fast_cuda_nan_is_gated_and_reported() -> None:
    _need_cuda()
    model = build_model(_scenes(False), SimConfig(device="cuda", dt_fixed_s=1e-4))
    sim = Simulator(model)
    v = sim.state.v.numpy()
    bad = int(model.scene_start_np[1]) + 7
    v[bad] = (np.nan, 0.0, 0.0)
    sim.state.v.assign(v)
    rep = sim.advance(0.001)
    issue = rep.health.first()
    assert issue is not None and issue.check == "nonfinite" and issue.scene == 1 and issue.particle == 7
    x = sim.particles()["x"]
    good = np.ones(len(x), bool)
    good[bad] = False
    assert np.all(np.isfinite(x[good]))


# the kernel variants of the fast path (KernelOptions specialize / agg / coop...): every variant forced on small
# problems, where the size policy would not pick all of them
_ALL_VARIANTS = {"coop_min_particles": 0, "coop_max_particles": 0, "coop_p2g": True,
                 "p2g_parts": 1}  # one thread per particle in p2g: its cooperative loads
_NO_VARIANTS = {"specialize": False, "agg": False, "coop": False}


@pytest.mark.parametrize("shuffle", [False, True])
def test_fast_cuda_variants_with_colliders_match_cpu(shuffle: bool) -> None:
    """Warp-cooperative particle loads/stores (g2p and p2g) and warp-summed ground impulses, with a moving box
    collider, for lattice-ordered and shuffled particles."""
    _need_cuda()
    fast = _rollout("cuda", True, shuffle, **_ALL_VARIANTS)
    cpu = _rollout("cpu", False, shuffle)
    np.testing.assert_allclose(fast[0], cpu[0], atol=1e-4)
    np.testing.assert_allclose(fast[1], cpu[1], rtol=2e-2, atol=2e-3)
    np.testing.assert_allclose(fast[2], cpu[2], rtol=2e-2, atol=2e-3)


@pytest.mark.parametrize("options", [_ALL_VARIANTS, {}, _NO_VARIANTS])
def test_fast_cuda_variants_without_colliders_match_cpu(options: dict) -> None:
    """Two 11^3 cubes (1331 particles each: a warp spans both scenes, the last warp is partial) dropped onto the
    ground, no kinematic colliders (the specialised kernels): CUDA matches the CPU after landing."""
    _need_cuda()
    from tasks.mpm.scene import bench_cube_model

    out = []
    for device, kernel in (("cuda", KernelOptions(**options)), ("cpu", KernelOptions())):
        sim = Simulator(bench_cube_model(11, 2, device, kernel=kernel))
        sim.advance(0.12)  # falls 0.05 m (~0.1 s), then rests on the ground
        rep = sim.advance(0.02)
        assert rep.health.ok, rep.health.issues
        out.append((sim.particles()["x"], rep.ground_force_n))
    np.testing.assert_allclose(out[0][0], out[1][0], atol=2e-4)
    assert np.all(out[1][1][:, 2] < -1.0)  # landed: the cubes push on the ground (force on the ground, along -z)
    np.testing.assert_allclose(out[0][1], out[1][1], rtol=5e-2, atol=2e-2)


# the fused g2p + next p2g (KernelOptions.fuse, default on; fuse_keep_c loads and stores C) and the scatter variants
# (scatter: scan, the default, or warp), also with the row-scan p2g of one thread per particle (p2g_parts=1) and
# uncapped registers
@pytest.mark.parametrize("options", [
    {"fuse": False},
    {"scatter": "warp"},
    {"p2g_parts": 1, "fuse_max_registers": 0},
    {"p2g_parts": 1, "scatter": "warp", "fuse": False},
    {"fuse_keep_c": True},  # the fused kernel round-trips C through memory (default: it keeps C in registers)
    {"grid_lazy": False},  # the grid update writes every node (default: only nodes with mass)
])
@pytest.mark.parametrize("shuffle", [False, True])
def test_fast_cuda_fusion_and_scatter_variants_match_cpu(options: dict, shuffle: bool) -> None:
    """Ground, a moving box collider and a thrown cube, lattice-ordered and shuffled, for each variant."""
    _need_cuda()
    fast = _rollout("cuda", True, shuffle, **options)
    cpu = _rollout("cpu", False, shuffle)
    np.testing.assert_allclose(fast[0], cpu[0], atol=1e-4)
    np.testing.assert_allclose(fast[1], cpu[1], rtol=2e-2, atol=2e-3)
    np.testing.assert_allclose(fast[2], cpu[2], rtol=2e-2, atol=2e-3)


def test_fast_cuda_default_runs_fused_blocks() -> None:
    """The default fast path replays multi-step graphs with the fused kernel and the row-scan scatter."""
    _need_cuda()
    from tasks.mpm.scene import bench_cube_model

    sim = Simulator(bench_cube_model(10, 2, "cuda"))
    sim.advance(0.005)
    sol = sim.solver
    assert isinstance(sol.plan, CudaLaunchPlan) and sol.plan.fuse and sol.plan.scatter == KC.SCATTER_SCAN
    names = {c.kernel.key for entry in sol._blocks.values() for c in entry[2]}
    assert any("g2p2g" in n for n in names), names
