"""Recorded CPU launches replayed with a prebuilt argument struct (tasks/mpm/cpu_launch.py): the same rollout, bit for
bit, as Warp's own Launch.launch, with colliders, re-fits and two CPU threads; a launch Warp packs differently falls
back to Launch.launch."""

from __future__ import annotations

import numpy as np

from contracts.sim import SimConfig
from tasks.mpm import Simulator, build_model
from tasks.mpm import cpu_launch
from tasks.mpm import solver as solver_mod
from tasks.mpm.cpu_launch import PackedCpuLaunch, pack_cpu_launches
from tests.mpm.scenes import pressed_and_thrown


def _rollout(threads: int) -> tuple[dict, Simulator]:
    """A cube pressed by a moving box and a second cube thrown onto the ground, 0.03 s."""
    sim = Simulator(build_model(pressed_and_thrown(), SimConfig(device="cpu", dt_fixed_s=1e-4, cpu_threads=threads)))
    rep = sim.advance(0.03)
    assert rep.health.ok
    out = dict(sim.particles())
    out.update(ground=rep.ground_force_n, collider=rep.collider_force_n)
    return out, sim


def test_packed_launches_replay_the_rollout_bit_for_bit(monkeypatch) -> None:
    for threads in (1, 2):
        packed, sim = _rollout(threads)
        steps = [c for entry in sim.solver._graphs.values() for c in entry[0]]
        inner = [c for c in steps if isinstance(c, PackedCpuLaunch)]
        inner += [x for c in steps for x in getattr(c, "cmds", []) if isinstance(x, PackedCpuLaunch)]
        assert inner and all(c.packed for c in inner)  # the fast path is taken, not the fallback
        refits = [c for entry in sim.solver._refit_cmds.values() for c in entry[0]]
        assert refits and all(isinstance(c, PackedCpuLaunch) and c.packed for c in refits)
        with monkeypatch.context() as m:
            m.setattr(solver_mod, "pack_cpu_launches", lambda cmds: cmds)  # Warp's Launch.launch
            plain, _ = _rollout(threads)
        for k, v in plain.items():
            np.testing.assert_array_equal(packed[k], v, err_msg=f"{k} ({threads} threads)")
        assert np.abs(packed["collider"]).sum() > 0 and np.abs(packed["ground"]).sum() > 0


class _Foreign:
    """A launch object whose internals are not Warp 1.x's (another version): no params, hooks or adjoint."""

    def __init__(self) -> None:
        self.kernel = "k"
        self.calls = 0

    def launch(self) -> None:
        self.calls += 1


def test_a_launch_packed_differently_falls_back_to_its_own_launch() -> None:
    foreign = _Foreign()
    p = PackedCpuLaunch(foreign)
    assert not p.packed
    p.launch()
    p.launch()
    assert foreign.calls == 2
    assert cpu_launch._packed_call(foreign) is None
    assert pack_cpu_launches(["not a launch"]) == ["not a launch"]
