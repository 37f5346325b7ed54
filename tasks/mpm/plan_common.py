"""What the CPU and CUDA launch plans share: the solver whose buffers they launch on and the kernels' arguments.

A launch plan (``plan_cpu.CpuLaunchPlan``, ``plan_cuda.CudaLaunchPlan``) decides which kernels one MPM step
launches, over how many threads and in which blocks; the ``Solver`` owns the buffers, the clock and the replay
(recorded launches, CUDA graphs). Every kernel of ``kernels.py`` and its CUDA variants take the same arguments, built
here, so both plans pass the same buffers in the same order.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import warp as wp

from tasks.mpm import kernels as K
from tasks.mpm.control import Control
from tasks.mpm.state import State

if TYPE_CHECKING:
    from tasks.mpm.solver import Solver


def whole(arr: wp.array) -> wp.array:
    """A per-particle array as a kernel over all particles takes it."""
    return arr


class LaunchPlan(ABC):
    """Base of the launch plans: argument lists of the step's kernels on the solver's buffers."""

    #: advance_steps may run a step's g2p fused with the next step's p2g (no re-fit between them)
    fuse: bool = False

    def __init__(self, solver: Solver) -> None:
        self.solver = solver
        self.model = solver.model
        self.device = solver.device
        m = self.model
        # the model's static argument bundles (kernels.py structs; a recorded launch holds a copy)
        self.ground = K.Ground()
        self.ground.enabled, self.ground.height, self.ground.mu = m.ground_enabled, m.ground_height, m.ground_mu
        self.colliders = K.Colliders()
        c = self.colliders
        c.start, c.count, c.kind, c.params = m.col_start, m.col_count, m.col_kind, m.col_params
        c.planes, c.radius2, c.mu, c.bonded = m.col_planes, m.col_radius2, m.col_mu, m.col_bonded
        self.limits = K.HealthLimits()
        self.limits.domain_lo, self.limits.domain_hi = m.domain_lo, m.domain_hi
        self.limits.j_min, self.limits.j_max = float(m.config.j_min), float(m.config.j_max)

    # -- what the solver asks of a plan ----------------------------------------------------------------------------
    def alloc_scatter(self, nodes: int) -> wp.array:
        """A zeroed scatter buffer (momentum, mass) of `nodes` nodes."""
        return wp.zeros(nodes, dtype=wp.vec4, device=self.device)

    @abstractmethod
    def record_refit(self, state: State) -> list:
        """Recorded launches of the per-scene bounds reduction and the window fit."""

    @abstractmethod
    def record_step(self, state_in: State, state_out: State, control: Control, refit: bool, skip_p2g: bool = False,
                    fuse_next: bool = False) -> list:
        """Recorded launches of one step: skip_p2g = the previous step's fused g2p did this step's p2g (no re-fit in
        between); fuse_next = end with a g2p that also does the next step's p2g."""

    # -- shared pieces ---------------------------------------------------------------------------------------------
    def collider_motion(self, control: Control, end: bool) -> K.ColliderMotion:
        """The colliders' poses at the step's start (end=False) or end, with the control's velocities."""
        s = self.solver
        out = K.ColliderMotion()
        out.pos, out.rot = (s.col_pos1, s.col_rot1) if end else (s.col_pos0, s.col_rot0)
        out.lin_vel, out.ang_vel = control.d_lin_vel, control.d_ang_vel
        return out

    def collider_poses_cmd(self, control: Control) -> Any:
        """The recorded launch that moves the kinematic colliders to their poses at the start and end of the step."""
        s, m = self.solver, self.model
        return wp.launch(
            K.update_collider_poses,
            dim=m.n_colliders,
            inputs=[control.d_ref_pos, control.d_ref_rot, control.d_ref_time, control.d_lin_vel, control.d_ang_vel,
                    s.clock_time, s.dt_arr, s.col_pos0, s.col_rot0, s.col_pos1, s.col_rot1],
            device=self.device,
            record_cmd=True,
        )

    def p2g_inputs(self, state: State, per_thread: int, n: int, sl: Callable[[wp.array], wp.array] = whole,
                   scene_start: wp.array | None = None, own: dict[str, wp.array] | None = None) -> list:
        """Arguments of the p2g kernels (per_thread: items per thread, or threads per particle on CUDA) for n
        particles: all, or a CPU chunk's slice `sl` with its shifted scene_start and own buffers."""
        s, m = self.solver, self.model
        nx, ny, nz = s.grid_dims
        grid, fs, fp = ((s.grid_mvm, s.fail_step, s.fail_particle) if own is None else
                        (own["grid"], own["fail_step"], own["fail_particle"]))
        return [sl(state.x), sl(state.v), sl(state.C), sl(state.F), sl(m.particle_mass), sl(m.particle_vol),
                sl(m.particle_scene), m.scene_start if scene_start is None else scene_start, m.scene_mu,
                m.scene_lambda, m.scene_eta, s.grid_origin, nx, ny, nz, m.dx, s.dt_arr, s.clock_step, grid, fs, fp, per_thread, n]

    def grid_update_inputs(self, control: Control, scatter: wp.array, per_thread: int) -> list:
        """Arguments of the grid update kernels (scatter: the buffer it reads and clears)."""
        s, m = self.solver, self.model
        nx, ny, nz = s.grid_dims
        return [scatter, s.grid_v, s.grid_origin, nx, ny, nz, m.dx, s.dt_arr, control.d_gravity, m.scene_damping,
                control.d_grid_slide, self.ground, s.ground_impulse, self.colliders,
                self.collider_motion(control, end=False), s.collider_impulse, s.clock_time, s.clock_step, per_thread,
                s.grid_nodes]

    def g2p_head_inputs(self, state_in: State, control: Control, sl: Callable[[wp.array], wp.array] = whole,
                        scene_start: wp.array | None = None, own: dict[str, wp.array] | None = None) -> list:
        """Arguments of the g2p kernels up to the output state (shared by the plain and the fused kernels)."""
        s, m = self.solver, self.model
        nx, ny, nz = s.grid_dims
        ground, collider, fs, fp = ((s.ground_impulse, s.collider_impulse, s.fail_step, s.fail_particle)
                                    if own is None else
                                    (own["ground"], own["collider"], own["fail_step"], own["fail_particle"]))
        return [sl(state_in.x), sl(state_in.v), sl(state_in.C), sl(state_in.F), sl(m.particle_mass),
                sl(m.particle_scene), m.scene_start if scene_start is None else scene_start, s.grid_v, s.grid_origin,
                nx, ny, nz, m.dx, s.dt_arr, control.d_gravity, self.ground, ground, self.colliders,
                self.collider_motion(control, end=True), collider, self.limits, s.clock_step, fs, fp]

    def g2p_tail_inputs(self, state_out: State, sl: Callable[[wp.array], wp.array] = whole,
                        own: dict[str, wp.array] | None = None) -> list:
        """Arguments of the g2p kernels from the output state on: the state, and what the next step's p2g needs."""
        s, m = self.solver, self.model
        grid = s.grid_mvm if own is None else own["grid"]
        return [sl(state_out.x), sl(state_out.v), sl(state_out.C), sl(state_out.F), sl(m.particle_vol), m.scene_mu,
                m.scene_lambda, m.scene_eta, grid]
