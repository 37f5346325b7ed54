"""MPM engine (NVIDIA Warp): 3D MLS-MPM, quadratic B-splines, neo-Hookean, grid Coulomb contact. SI units.

Physics: Kirchhoff stress tau = mu (F F^T - I) + lambda ln(J) I + J eta (C + C^T) (neo-Hookean + Kelvin-Voigt
viscosity eta, C the APIC velocity gradient: the loss in the material); damping as a rate (v *= exp(-rate dt),
relative to the scene's lattice velocity: zero unless set); gravity per scene; adaptive dt = min(dt_max, C dx / (c_p
+ |v|max + collider speed), 0.15 rho dx^2 / eta) or SimConfig.dt_fixed_s; a dense grid window per scene fitted to the particles (bounds + margin),
re-centred on the device every few steps and enlarged when the body outgrows it. The lattice is the world lattice
unless ``Control.set_grid_velocity`` moves it (a gripper carrying the object: pads crossing lattice planes would
release and re-grip node layers and the squeeze would leak away). Contact on grid nodes (ground plane + kinematic box / capsule / half-space / finger-pad /
convex-polytope colliders): for u = v - v_b with u_n < 0, v+ = v_b + max(0, 1 - mu (-u_n)/max(|u_t|, eps)) u_t; separation allowed; residual
penetration of particles corrected after grid-to-particle. ``bonded=True`` colliders clamp (v = v_b inside).

Public API (Model / State / Control / Solver, plus a Simulator that drives reporting intervals)::

    from contracts.material import Material
    from contracts.sim import SimConfig
    from tasks.mpm import SceneSpec, box_collider, capsule_collider, build_model, Simulator

    finger = box_collider((0.01, 0.02, 0.04), friction=0.8, position_m=(0.1, 0, 0.05))   # half extents [m]
    scene = SceneSpec(positions_m=P, volumes_m3=V, density_kg_per_m3=rho, material=Material(...),
                      colliders=[finger, ...], ground=True)          # one per material candidate -> batch
    model = build_model([scene0, scene1, ...], SimConfig(device="cpu"|"cuda"))
    sim = Simulator(model)                     # owns State (sim.state), Control (sim.control), Solver (sim.solver)
    sim.control.set_collider(scene, index, position_m=..., rotation_xyzw=..., linear_velocity_m_per_s=...,
                             angular_velocity_rad_per_s=...)        # pose re-anchored now; moves at that velocity
    sim.control.set_gravity(scene, (gx, gy, gz))
    sim.control.set_grid_velocity(scene, (vx, vy, vz))  # lattice (and damping frame) moves with a carrying hand [m/s]
    report = sim.advance(0.01)                 # one reporting interval [s]; adaptive/fixed dt inside
    report.collider_force(model, scene, index) # mean force [N] the OBJECT exerts ON that collider over the interval
    report.ground_force_n[scene]               # same for the ground; f = -(1/dt_k) sum J_c, J_c = m (v+ - v)
    report.health.ok / report.health.first()   # HealthIssue(check, scene, step, sim_time_s, particle, detail)
    sim.particles(scene)                       # {"x": (N,3) m, "v": (N,3) m/s, "F": (N,3,3)}

A fingertip pressing the object in +x reports a force along -x (into the finger). Health checks: "nonfinite",
"left_domain", "j_out_of_bounds" (SimConfig.j_min/j_max), "energy_blowup" (SimConfig.energy_growth_max); the
offending particle is gated (never written to the grid), so no kernel crashes; the rollout stops at the next
check (every ``health_interval_steps`` steps and at the end of each ``advance``). Lower level:
``Solver(model).step(state_in, state_out, control, dt)`` (state_out may be state_in). On CUDA a step is captured
once into a CUDA graph and replayed. ``advance_parallel([sim_a, sim_b], t)`` runs independent simulators in
threads (Warp CPU kernels are single-threaded; launches release the GIL).
"""

from __future__ import annotations

from tasks.native_output import init_warp_quietly

# Warp: banner and module loads off stdout (it belongs to --json data), no CUDA-driver notice on a CPU machine
WARP_INIT_NOTES = init_warp_quietly()

from tasks.mpm.control import Control  # noqa: E402
from tasks.mpm.health import HealthIssue, HealthStatus  # noqa: E402
from tasks.mpm.model import (  # noqa: E402
    ColliderSpec,
    Model,
    SceneSpec,
    box_collider,
    build_model,
    capsule_collider,
    convex_collider,
    halfspace_collider,
    pad_collider,
)
from tasks.mpm.simulator import IntervalReport, Simulator, advance_parallel, side_by_side  # noqa: E402
from tasks.mpm.solver import Solver  # noqa: E402
from tasks.mpm.state import State  # noqa: E402

__all__ = [
    "ColliderSpec",
    "Control",
    "HealthIssue",
    "HealthStatus",
    "IntervalReport",
    "Model",
    "SceneSpec",
    "Simulator",
    "Solver",
    "State",
    "advance_parallel",
    "side_by_side",
    "box_collider",
    "build_model",
    "capsule_collider",
    "convex_collider",
    "halfspace_collider",
    "pad_collider",
]
