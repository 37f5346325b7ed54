"""CPU rollouts that an engine refactor must reproduce bit for bit: save them once, check them after each change.

    python -m benchmarks.engine.bitexact_reference save /tmp/ref.npz
    python -m benchmarks.engine.bitexact_reference check /tmp/ref.npz

Scenes (fixed dt 1e-4 s unless adaptive): a cube dropped on the ground (adaptive dt, 1 and 2 threads); a cube pressed
by a moving box next to a cube thrown onto the ground (one batched model of 2 scenes, 1 and 2 threads, and the same
through ``Solver.step`` one step at a time); two finger pads squeezing a cube and carrying it on a lattice moving
with them (``Control.set_grid_velocity``); a cube with a NaN particle (the failure tables). Each rollout saves the
final particle x, v, F, C, the reported ground and collider forces of every interval and the failure tables.
"""

from __future__ import annotations

import sys

import numpy as np

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm import Simulator, Solver, box_collider, build_model, pad_collider
from tasks.mpm.scene import box_scene

MAT = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)


def _pressed_and_thrown() -> list:
    a = box_scene((0.0, 0.0, 0.001), (0.04, 0.04, 0.041), 0.0025, MAT, 400.0,
                  colliders=[box_collider((0.02, 0.05, 0.05), position_m=(-0.021, 0.02, 0.03), friction=0.6,
                                          linear_velocity_m_per_s=(0.2, 0.0, 0.0))])
    b = box_scene((0.0, 0.0, 0.002), (0.035, 0.04, 0.042), 0.0025, MAT, 400.0, velocity_m_per_s=(0.5, 0.0, -0.3))
    return [a, b]


def _final(sim: Simulator, prefix: str, out: dict[str, np.ndarray]) -> None:
    st = sim.state
    out[f"{prefix}/x"], out[f"{prefix}/v"] = st.x.numpy().copy(), st.v.numpy().copy()
    out[f"{prefix}/F"], out[f"{prefix}/C"] = st.F.numpy().copy(), st.C.numpy().copy()
    fs, fp = sim.solver.read_failures()
    out[f"{prefix}/fail_step"], out[f"{prefix}/fail_particle"] = fs, fp
    out[f"{prefix}/time"] = np.array([sim.solver.time_s, sim.solver.steps])


def _intervals(sim: Simulator, prefix: str, out: dict, durations: list[float]) -> None:
    for k, d in enumerate(durations):
        rep = sim.advance(d)
        out[f"{prefix}/ground{k}"], out[f"{prefix}/collider{k}"] = rep.ground_force_n, rep.collider_force_n


def drop(threads: int, out: dict) -> None:
    """A 4 cm cube falling 2 cm onto the ground, adaptive dt."""
    sc = box_scene((0.0, 0.0, 0.02), (0.04, 0.04, 0.06), 0.0025, MAT, 400.0)
    sim = Simulator(build_model([sc], SimConfig(device="cpu", cpu_threads=threads)), health_interval_steps=37)
    _intervals(sim, f"drop{threads}", out, [0.03, 0.03, 0.02])
    _final(sim, f"drop{threads}", out)


def press(threads: int, out: dict) -> None:
    """Batched: a cube pressed by a moving box and a cube thrown onto the ground, 150 steps."""
    cfg = SimConfig(device="cpu", dt_fixed_s=1e-4, cpu_threads=threads)
    sim = Simulator(build_model(_pressed_and_thrown(), cfg), health_interval_steps=37)
    _intervals(sim, f"press{threads}", out, [0.005, 0.005, 0.005])
    _final(sim, f"press{threads}", out)


def press_steps(out: dict) -> None:
    """The batched press through Solver.step (no fused steps, no Simulator), 80 steps with a re-fit every 10."""
    model = build_model(_pressed_and_thrown(), SimConfig(device="cpu", dt_fixed_s=1e-4))
    sim = Simulator(model)
    solver = Solver(model)
    sim.solver = solver
    for k in range(80):
        solver.step(sim.state, sim.state, sim.control, 1e-4)
        if k % 10 == 9:
            solver.refit(sim.state)
    g, c = solver.read_impulses()
    out["steps/ground"], out["steps/collider"] = g, c
    _final(sim, "steps", out)


def pads(out: dict) -> None:
    """Two pads squeeze a 3 cm cube and carry it upwards on a lattice moving with them."""
    half = (0.01, 0.0087, 0.0088)
    edge, dx, gap, v = 0.03, 0.005, 0.003, 0.1
    reach = edge / 2 + half[0] + gap
    cols = [pad_collider(half, "+x", position_m=(-reach, 0.0, edge / 2), friction=0.9),
            pad_collider(half, "-x", position_m=(reach, 0.0, edge / 2), friction=0.9)]
    mat = Material(youngs_modulus_pa=8.3e4, poisson_ratio=0.3, damping_rate_per_s=40.0)
    sc = box_scene((-edge / 2, -edge / 2, 0.0), (edge / 2, edge / 2, edge), dx / 2, mat, 70.0, colliders=cols)
    model = build_model([sc], SimConfig(device="cpu", dx_m=dx, grid_margin_m=0.02))
    sim = Simulator(model)
    for i, sign in enumerate((1.0, -1.0)):
        sim.control.set_collider(0, i, linear_velocity_m_per_s=(sign * v, 0.0, 0.0))
    _intervals(sim, "pads_close", out, [0.04])
    up = (0.0, 0.0, 0.2)
    for i in range(2):
        sim.control.set_collider(0, i, linear_velocity_m_per_s=up)
    sim.control.set_grid_velocity(0, up)
    _intervals(sim, "pads_lift", out, [0.02, 0.02])
    _final(sim, "pads", out)


def nan_particle(out: dict) -> None:
    """A thrown cube with one NaN velocity: the failure tables (scene, step, particle)."""
    sc = box_scene((0.0, 0.0, 0.002), (0.03, 0.03, 0.032), 0.0025, MAT, 400.0, velocity_m_per_s=(0.5, 0.0, -0.3))
    sim = Simulator(build_model([sc], SimConfig(device="cpu", dt_fixed_s=1e-4)), health_interval_steps=1000)
    v = sim.state.v.numpy()
    v[17] = (np.nan, 0.0, 0.0)
    sim.state.v.assign(v)
    sim.solver.advance_steps(sim.state, sim.control, 1e-4, 30)
    _final(sim, "nan", out)


def run() -> dict[str, np.ndarray]:
    """Every rollout's arrays, by 'rollout/array' name."""
    out: dict[str, np.ndarray] = {}
    for threads in (1, 2):
        drop(threads, out)
        press(threads, out)
    press_steps(out)
    pads(out)
    nan_particle(out)
    return out


def main(argv: list[str]) -> int:
    """save PATH: write the rollouts' arrays; check PATH: compare them with a saved file (exit 1 on a difference)."""
    mode, path = argv[0], argv[1]
    out = run()
    if mode == "save":
        np.savez(path, **out)  # type: ignore[arg-type]
        print(f"saved {len(out)} arrays to {path}")
        return 0
    ref = np.load(path)
    bad = [k for k in ref.files if k not in out or not np.array_equal(ref[k], out[k], equal_nan=True)]
    missing = [k for k in out if k not in ref.files]
    print(f"compared {len(ref.files)} arrays: {len(bad)} differ {bad[:10]}; {len(missing)} new {missing[:5]}")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
