"""One rollout's particles shared by several CPU threads (SimConfig.cpu_threads, tasks/mpm/cpu_threads.py): the same
physics as one thread (contacts, forces, health reports), the same bits on every run, and the cache keys of
single-threaded configurations unchanged."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import Simulator, box_collider, build_model
from tasks.mpm.cpu_threads import MIN_PARTICLES_PER_CHUNK, chunk_bounds
from tasks.mpm.scene import box_scene

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)


def _scenes() -> list:
    """A cube pressed by a moving box, a cube thrown down and sideways in shuffled order, a cube at rest: 3 x 1728 particles,
    so the two chunks' boundary falls inside the second scene."""
    rng = np.random.default_rng(4)
    a = box_scene((0.0, 0.0, 0.001), (0.06, 0.06, 0.061), 0.005, MAT, 400.0,
                  colliders=[box_collider((0.02, 0.05, 0.05), position_m=(-0.021, 0.03, 0.05), friction=0.6,
                                          linear_velocity_m_per_s=(0.2, 0.0, 0.0))])
    b = box_scene((0.0, 0.0, 0.001), (0.06, 0.06, 0.061), 0.005, MAT, 400.0, velocity_m_per_s=(0.5, 0.0, -0.3))
    perm = rng.permutation(len(b.positions_m))
    b.positions_m, b.volumes_m3 = b.positions_m[perm], b.volumes_m3[perm]
    b.velocities_m_per_s = b.velocities_m_per_s[perm]
    c = box_scene((0.0, 0.0, 0.001), (0.06, 0.06, 0.061), 0.005, MAT, 400.0)
    return [a, b, c]


def _sim(threads: int) -> Simulator:
    sim = Simulator(build_model(_scenes(), SimConfig(device="cpu", dt_fixed_s=1e-4, cpu_threads=threads)))
    assert (sim.solver.plan.chunks is not None) == (threads > 1)
    return sim


def _rollout(threads: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    sim = _sim(threads)
    rep = sim.advance(0.03)
    assert rep.health.ok, rep.health.issues
    return sim.particles()["x"], rep.ground_force_n, rep.collider_force_n


def test_chunk_bounds_cover_the_particles_in_balanced_chunks() -> None:
    assert chunk_bounds(10_000, 3) == [(0, 3333), (3333, 6667), (6667, 10_000)]
    assert chunk_bounds(10_000, 1) == [(0, 10_000)]
    n = 3 * MIN_PARTICLES_PER_CHUNK - 1  # room for 2 chunks of at least MIN_PARTICLES_PER_CHUNK, not 3
    assert chunk_bounds(n, 8) == [(0, round(n / 2)), (round(n / 2), n)]
    assert chunk_bounds(100, 4) == [(0, 100)]  # too small to share


def test_threads_give_the_single_thread_physics() -> None:
    """Ground, a moving box and a thrown cube: positions within 0.1 mm and forces within 2 % of one thread."""
    one = _rollout(1)
    for threads in (2, 3):
        many = _rollout(threads)
        np.testing.assert_allclose(many[0], one[0], atol=1e-4)
        np.testing.assert_allclose(many[1], one[1], rtol=2e-2, atol=2e-3)
        np.testing.assert_allclose(many[2], one[2], rtol=2e-2, atol=2e-3)
    assert np.all(one[1][:, 2] < -0.5)  # every cube pushes on the ground (a resting one: its weight, 0.85 N)
    assert np.abs(one[2]).sum() > 0.1  # the box pressed its cube


def test_threads_are_deterministic() -> None:
    """The same chunk count gives the same bits: chunks add into the grid in a fixed order, whatever the timing."""
    a, b = _rollout(2), _rollout(2)
    for u, w in zip(a, b):
        np.testing.assert_array_equal(u, w)


def test_nan_in_a_later_chunk_is_reported_like_one_thread() -> None:
    """A NaN particle of scene 2 (second chunk) is reported with its scene, scene-local index and step."""
    reports = []
    for threads in (1, 2):
        sim = _sim(threads)
        v = sim.state.v.numpy()
        bad = int(sim.model.scene_start_np[2]) + 11
        assert bad >= sim.solver.plan.chunks.bounds[1][0] if threads > 1 else True
        v[bad] = (np.nan, 0.0, 0.0)
        sim.state.v.assign(v)
        rep = sim.advance(0.002)
        issue = rep.health.first()
        assert issue is not None and issue.check == "nonfinite" and issue.scene == 2 and issue.particle == 11
        x = sim.particles()["x"]
        good = np.ones(len(x), bool)
        good[bad] = False
        assert np.all(np.isfinite(x[good]))
        reports.append(issue.step)
    assert reports[0] == reports[1] == 1


def test_single_thread_cache_keys_are_unchanged() -> None:
    """cpu_threads = 1 is left out of the canonical JSON (keys of earlier configurations); any other value is in it."""
    assert "cpu_threads" not in SimConfig().canonical_json()
    assert '"cpu_threads":2' in SimConfig(cpu_threads=2).canonical_json()
    assert SimConfig(**SimConfig(cpu_threads=2).model_dump()) == SimConfig(cpu_threads=2)
    with pytest.raises(ValueError):
        SimConfig(cpu_threads=0)


def test_trial_settings_keep_single_thread_keys_and_pass_threads_to_the_mpm() -> None:
    """L3: one thread is left out of a trial's task inputs (earlier trials stay cache hits); two are kept and restored."""
    from tasks.manipulation.context import settings_inputs
    from tasks.manipulation.trial import TrialSettings

    assert "cpu_threads" not in settings_inputs(TrialSettings())
    two = settings_inputs(TrialSettings(cpu_threads=2))
    assert two["cpu_threads"] == 2 and TrialSettings(**two).cpu_threads == 2


def test_l3_revalidates_in_l2_with_its_own_device_and_threads() -> None:
    """An L3 material revision's L2 probes run under the trials' device and CPU threads (not a default CPU config)."""
    from tasks.manipulation.context import L3Options

    assert L3Options(cpu_threads=2).sim() == SimConfig(device="cpu", cpu_threads=2)
    assert L3Options(device="cuda", cpu_threads=2).sim() == SimConfig(device="cuda")
    assert L3Options().sim() == SimConfig()  # the single-threaded CPU default: earlier revalidations stay cache hits


def test_threads_follow_a_grid_reallocation() -> None:
    """After the solver reallocates a larger grid mid-rollout, the chunks scatter into new buffers of the new size."""
    out = []
    for threads in (1, 2):
        sim = _sim(threads)
        sim.advance(0.01)
        before = sim.solver.grid_dims
        sim.solver.grow_grid(np.array(before, dtype=float) + 6.0)
        assert sim.solver.grid_dims > before
        if threads > 1:
            assert sim.solver.plan.chunks.grid_nodes == sim.solver.grid_nodes
        rep = sim.advance(0.01)
        assert rep.health.ok, rep.health.issues
        out.append((sim.particles()["x"], rep.ground_force_n))
    np.testing.assert_allclose(out[1][0], out[0][0], atol=1e-4)
    np.testing.assert_allclose(out[1][1], out[0][1], rtol=2e-2, atol=2e-3)
