"""Engine behaviour: contact and friction law, reaction-force sign, health reporting, determinism, batching."""

from __future__ import annotations

import math

import numpy as np
import pytest
import warp as wp

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import Simulator, box_collider, build_model, capsule_collider
from tasks.mpm.scene import bench_cube_model, box_scene

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3)


def _cube(lo=(0.0, 0.0, 0.0), a=0.05, n=5, **kw):
    """A small cube scene (n particles per axis)."""
    hi = tuple(lo_i + a for lo_i in lo)
    return box_scene(lo, hi, a / n, kw.pop("material", MAT), kw.pop("density", 500.0), **kw)


def _cfg(**kw) -> SimConfig:
    return SimConfig(grid_margin_m=0.0, **kw)


def test_sliding_block_decelerates_at_mu_g_and_frictionless_does_not() -> None:
    """Coulomb law on the grid: a block launched at 1 m/s slows at mu g; with mu = 0 it keeps its speed."""
    mus = [0.0, 0.3]
    scenes = [_cube(velocity_m_per_s=(1.0, 0.0, 0.0), ground_friction=mu) for mu in mus]
    sim = Simulator(build_model(scenes, _cfg()))
    sim.advance(0.05)  # contact established
    v0 = [sim.particles(s)["v"][:, 0].mean() for s in range(2)]
    sim.advance(0.15)
    v1 = [sim.particles(s)["v"][:, 0].mean() for s in range(2)]
    assert v1[0] == pytest.approx(v0[0], abs=0.01)  # frictionless: not sticky
    decel = (v0[1] - v1[1]) / 0.15
    assert decel == pytest.approx(0.3 * 9.81, rel=0.15)
    assert v1[1] > 0.2  # still sliding: friction is a rate, not a velocity reset


def test_reaction_force_on_a_table_points_into_it_and_equals_weight() -> None:
    """An object resting on a box collider exerts -m g on it (mean over an interval)."""
    table = box_collider((0.1, 0.1, 0.02), position_m=(0.025, 0.025, 0.08), friction=0.5)
    mat = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=30.0)
    sc = _cube(lo=(0.0, 0.0, 0.1), colliders=[table], ground=False, material=mat)
    model = build_model([sc], _cfg())
    sim = Simulator(model)
    sim.advance(0.3)
    rep = sim.advance(0.1)
    f = rep.collider_force(model, 0, 0)
    w = model.scene_mass_kg[0] * 9.81
    assert f[2] == pytest.approx(-w, rel=0.03)
    assert abs(f[0]) < 0.02 * w and abs(f[1]) < 0.02 * w
    assert rep.health.ok


def test_capsule_supports_the_object() -> None:
    """A horizontal capsule holds a block up; its reported force balances the weight."""
    cap = capsule_collider(0.02, 0.06, position_m=(0.025, 0.025, 0.075), rotation_xyzw=(0.0, math.sin(math.pi / 4),
                                                                                      0.0, math.cos(math.pi / 4)))
    mat = Material(youngs_modulus_pa=2e5, poisson_ratio=0.3, damping_rate_per_s=30.0)
    sc = _cube(lo=(0.0, 0.0, 0.1), colliders=[cap], ground=False, material=mat)
    model = build_model([sc], _cfg())
    sim = Simulator(model)
    sim.advance(0.3)
    rep = sim.advance(0.1)
    z = sim.particles(0)["x"][:, 2]
    assert z.min() > 0.08  # did not fall through
    assert rep.collider_force(model, 0, 0)[2] == pytest.approx(-model.scene_mass_kg[0] * 9.81, rel=0.05)


def test_moving_collider_pose_follows_control() -> None:
    """The device collider pose equals p_ref + v t and the host evaluation of the same formula."""
    box = box_collider((0.02, 0.02, 0.02), position_m=(0.3, 0.0, 0.3))
    sim = Simulator(build_model([_cube(colliders=[box])], _cfg()))
    sim.control.set_collider(0, 0, linear_velocity_m_per_s=(0.0, 0.1, 0.0), angular_velocity_rad_per_s=(0, 0, 2.0))
    sim.advance(0.1)
    pos_dev = sim.solver.col_pos1.numpy()[0]  # end-of-last-step pose
    pos, q = sim.control.collider_pose(0, sim.time_s)
    assert pos_dev == pytest.approx(pos, abs=1e-5)
    assert pos[1] == pytest.approx(0.01, abs=1e-6)
    assert sim.solver.col_rot1.numpy()[0] == pytest.approx(q, abs=1e-5)
    assert 2 * math.degrees(math.acos(q[3])) == pytest.approx(math.degrees(0.2), abs=0.01)


def test_damping_is_a_rate_independent_of_dt() -> None:
    """v(t) = v0 exp(-rate t) whatever the time step."""
    mat = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)
    out = []
    for dt in (1e-4, 4e-4):
        sc = _cube(velocity_m_per_s=(1.0, 0.0, 0.0), ground=False, gravity_m_per_s2=(0, 0, 0), material=mat)
        sim = Simulator(build_model([sc], _cfg(dt_fixed_s=dt)))
        sim.advance(0.2)
        out.append(sim.particles(0)["v"][:, 0].mean())
    assert out[0] == pytest.approx(math.exp(-1.0), rel=0.01)
    assert out[1] == pytest.approx(out[0], rel=0.01)


def test_adaptive_dt_respects_cfl_and_cap() -> None:
    """dt = min(dt_max, C dx / (c_p + |v|max))."""
    stiff = Material(youngs_modulus_pa=1e7, poisson_ratio=0.3)
    sim = Simulator(build_model([_cube(material=stiff, density=1000.0)], _cfg(cfl=0.4)))
    cp = stiff.p_wave_speed_m_per_s(1000.0)
    assert sim.stable_dt() == pytest.approx(0.4 * sim.model.dx / cp, rel=1e-6)
    soft = Simulator(build_model([_cube()], _cfg(dt_max_s=1e-4)))
    assert soft.stable_dt() == pytest.approx(1e-4)


def test_material_too_stiff_for_the_time_step_floor_is_refused_before_the_rollout() -> None:
    """E = 1e12 Pa at 500 kg/m^3 on 2 cm cells: c_p = sqrt(1.346e12 / 500) = 5.19e4 m/s, CFL steps of 1.5e-7 s (a 1 s
    probe: ~7e6 steps): refused with the numbers, at model build; 1e5 Pa builds; a fixed time step is the user's own
    choice and is not checked; a lower floor admits it."""
    from contracts.errors import SimulationError

    stiff = Material(youngs_modulus_pa=1e12, poisson_ratio=0.3)
    with pytest.raises(SimulationError, match=r"too stiff .*p-wave speed of 5.19e\+04 m/s.*below the 1e-06 s floor"):
        build_model([_cube(material=stiff)], _cfg())
    build_model([_cube()], _cfg())
    build_model([_cube(material=stiff)], _cfg(dt_fixed_s=1e-7))
    build_model([_cube(material=stiff)], _cfg(dt_min_s=1e-8))


def test_nan_is_reported_with_scene_and_particle_not_spread() -> None:
    """A NaN in one particle of scene 1 is a structured failure naming scene 1 and that particle; no crash."""
    model = build_model([_cube(), _cube()], _cfg())
    sim = Simulator(model)
    v = sim.state.v.numpy()
    bad = int(model.scene_start_np[1]) + 7
    v[bad] = (np.nan, 0.0, 0.0)
    sim.state.v.assign(v)
    rep = sim.advance(0.01)
    assert not rep.health.ok
    issue = rep.health.first()
    assert issue is not None and issue.check == "nonfinite" and issue.scene == 1 and issue.particle == 7
    assert issue.step == 1
    x = sim.particles()["x"]
    good = np.ones(len(x), bool)
    good[bad] = False
    assert np.all(np.isfinite(x[good]))  # the NaN never entered the grid
    assert rep.health.scene_ok(0)


def test_particle_leaving_domain_is_reported_without_crash() -> None:
    """An object thrown out of its allowed box is reported as left_domain (step, time, particle); no crash."""
    sc = _cube(ground=False, gravity_m_per_s2=(0, 0, 0), velocity_m_per_s=(10.0, 0.0, 0.0),
               domain_min_m=(-0.1, -0.1, -0.1), domain_max_m=(0.1, 0.1, 0.1))
    model = build_model([sc], _cfg(dt_fixed_s=1e-4))
    sim = Simulator(model)
    rep = sim.advance(0.05)
    issue = rep.health.first()
    assert issue is not None and issue.check == "left_domain" and issue.scene == 0
    # the leading face (x = 0.045 m, particle spacing 0.01) crosses x = 0.1 after (0.1 - 0.045) / 10 s
    assert issue.sim_time_s == pytest.approx(0.0055, abs=2e-4)
    x0 = model.x0[issue.particle]
    assert x0[0] == pytest.approx(0.045, abs=1e-6)
    assert rep.t_end_s < 0.05 and np.all(np.isfinite(sim.particles()["x"]))


def test_j_out_of_bounds_is_reported() -> None:
    """A particle whose det(F) is below j_min is reported with its index."""
    model = build_model([_cube(ground=False)], _cfg(j_min=0.5))
    sim = Simulator(model)
    F = sim.state.F.numpy()
    F[11] = np.eye(3) * 0.6  # J = 0.216
    sim.state.F.assign(F)
    rep = sim.advance(0.002)
    issue = rep.health.first()
    assert issue is not None and issue.check == "j_out_of_bounds" and issue.particle == 11


def test_unstable_time_step_is_caught_not_silent() -> None:
    """A fixed dt far above the CFL limit blows up; the rollout stops with a fatal status instead of NaN output."""
    stiff = Material(youngs_modulus_pa=1e7, poisson_ratio=0.3)
    sim = Simulator(build_model([_cube(material=stiff, density=100.0)], _cfg(dt_fixed_s=2e-3)),
                    health_interval_steps=10)
    rep = sim.advance(1.0)
    assert not rep.health.ok
    assert rep.health.first().check in {"nonfinite", "energy_blowup", "j_out_of_bounds", "left_domain"}
    assert rep.t_end_s < 1.0  # stopped early


def test_grid_window_follows_and_grows_with_the_object() -> None:
    """The grid is fitted to the object: it moves with a fast-flying block and is enlarged when the body expands."""
    soft = Material(youngs_modulus_pa=1e-2, poisson_ratio=0.3)  # nearly free expansion
    sc = _cube(ground=False, gravity_m_per_s2=(0, 0, 0), material=soft, domain_min_m=(-1, -1, -1),
               domain_max_m=(2, 1, 1))
    pos = sc.positions_m
    sc.velocities_m_per_s = 20.0 * (pos - pos.mean(axis=0)) + np.array([3.0, 0.0, 0.0])
    model = build_model([sc], _cfg(j_max=500.0))
    sim = Simulator(model)
    dims0 = sim.solver.grid_dims
    # fitted: the object's cells + a margin of model.margin_cells each side, not a fixed box
    assert max(dims0) <= math.ceil(0.05 / model.dx) + 2 * model.margin_cells + 4
    rep = sim.advance(0.3)
    assert rep.health.ok, rep.health.issues
    x = sim.particles(0)["x"]
    assert x[:, 0].mean() == pytest.approx(0.025 + 0.9, abs=0.02)  # flew 0.9 m, grid followed
    assert max(sim.solver.grid_dims) > max(dims0)  # expanded body -> larger window


def test_cpu_rollout_is_deterministic() -> None:
    """Two CPU rollouts of the same scene are bitwise identical."""
    out = []
    for _ in range(2):
        sim = Simulator(build_model([_cube(lo=(0, 0, 0.02), velocity_m_per_s=(0.3, 0.1, 0.0))], _cfg()))
        sim.advance(0.05)
        out.append(sim.particles()["x"])
    assert np.array_equal(out[0], out[1])


def test_batched_scenes_match_single_runs() -> None:
    """Scenes advanced together in one batch give the same result as each run alone (fixed dt)."""
    mats = [Material(youngs_modulus_pa=e, poisson_ratio=0.3) for e in (3e4, 1e5)]
    scenes = [_cube(lo=(0, 0, 0.03), material=m) for m in mats]
    batch = Simulator(build_model(scenes, _cfg(dt_fixed_s=2e-4)))
    batch.advance(0.06)
    for s in range(len(scenes)):
        single = Simulator(build_model([_cube(lo=(0, 0, 0.03), material=mats[s])], _cfg(dt_fixed_s=2e-4)))
        single.advance(0.06)
        np.testing.assert_allclose(batch.particles(s)["x"], single.particles(0)["x"], atol=1e-6)
    # and the materials really differ: the stiffer cube deforms less on impact
    assert not np.allclose(batch.particles(0)["x"], batch.particles(1)["x"], atol=1e-5)


def test_bench_scene_is_the_standard_cube() -> None:
    """Bench model: n^3 particles of a 0.2 m cube at dx = 0.4/n, 0.05 m above the ground."""
    model = bench_cube_model(10)
    assert model.n_particles == 1000
    assert model.dx == pytest.approx(0.04)
    assert model.x0[:, 2].min() == pytest.approx(0.05 + 0.01, abs=1e-6)
    assert model.scene_mass_kg[0] == pytest.approx(200.0 * 0.2**3)


@pytest.mark.gpu
def test_cuda_matches_cpu_within_tolerance() -> None:
    """Same API on cuda: the rollout agrees with the CPU one (float atomics reorder on GPU)."""
    if not wp.is_cuda_available():
        pytest.skip("no CUDA device")
    out = []
    for device in ("cpu", "cuda"):
        sim = Simulator(build_model([_cube(lo=(0, 0, 0.02))], _cfg(device=device, dt_fixed_s=2e-4)))
        sim.advance(0.05)
        out.append(sim.particles()["x"])
    np.testing.assert_allclose(out[0], out[1], atol=1e-4)
