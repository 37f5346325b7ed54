"""Scene builders: particle lattices for boxes, balls (solid or hollow) and the standard benchmark cube (SI units)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Unpack

import numpy as np

from contracts.material import Material
from contracts.sim import KernelOptions, SimConfig
from tasks.mpm.model import ColliderSpec, Model, SceneKw, SceneSpec, build_model


def box_particles(
    lo_m: Sequence[float], hi_m: Sequence[float], spacing_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Particles at cell centres of a lattice filling the box [lo, hi] (spacing [m]): positions (N,3), volumes (N,)."""
    lo = np.asarray(lo_m, dtype=np.float64)
    hi = np.asarray(hi_m, dtype=np.float64)
    counts = np.maximum(1, np.round((hi - lo) / spacing_m).astype(int))
    h = (hi - lo) / counts
    axes = [lo[a] + (np.arange(counts[a]) + 0.5) * h[a] for a in range(3)]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    pos = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    vol = np.full(len(pos), float(np.prod(h)))
    return pos, vol


def ball_particles(radius_m: float, spacing_m: float, wall_m: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Particles of a ball centred on the origin: the lattice cells of box_particles whose centres lie inside the
    sphere, or, given a wall, only those within wall_m of its surface (a hollow ball's shell: nothing inside it).
    A wall under two particle spacings is not a shell the grid (dx = 2 spacings) can resolve: refused."""
    if wall_m is not None and wall_m < 2.0 * spacing_m * (1.0 - 1e-9):
        raise ValueError(f"a {wall_m * 1e3:g} mm wall needs a particle spacing of at most half of it, got "
                         f"{spacing_m * 1e3:g} mm")
    r = float(radius_m)
    pos, vol = box_particles((-r, -r, -r), (r, r, r), spacing_m)
    dist = np.linalg.norm(pos, axis=1)
    keep = dist <= r if wall_m is None else (dist <= r) & (dist > r - wall_m)
    return pos[keep], vol[keep]


def box_scene(
    lo_m: Sequence[float],
    hi_m: Sequence[float],
    spacing_m: float,
    material: Material,
    density_kg_per_m3: float,
    colliders: list[ColliderSpec] | None = None,
    velocity_m_per_s: Sequence[float] | None = None,
    **kw: Unpack[SceneKw],
) -> SceneSpec:
    """A SceneSpec for a solid box of particles (2 per grid cell per axis when dx = 2 spacing)."""
    pos, vol = box_particles(lo_m, hi_m, spacing_m)
    vel = None if velocity_m_per_s is None else np.tile(np.asarray(velocity_m_per_s, float), (len(pos), 1))
    return SceneSpec(
        positions_m=pos,
        volumes_m3=vol,
        density_kg_per_m3=density_kg_per_m3,
        material=material,
        colliders=list(colliders or []),
        velocities_m_per_s=vel,
        **kw,
    )


BENCH_MATERIAL = Material(youngs_modulus_pa=1.0e5, poisson_ratio=0.3, damping_rate_per_s=0.0)
BENCH_DENSITY = 200.0  # kg/m^3
BENCH_EDGE_M = 0.2
BENCH_LIFT_M = 0.05
BENCH_DT_S = 1.0e-4


def bench_cube_scene(n_per_axis: int, material: Material = BENCH_MATERIAL) -> SceneSpec:
    """The standard scene: 0.2 m cube, n^3 particles, resting 0.05 m above the ground (dx = 0.4/n m)."""
    spacing = BENCH_EDGE_M / n_per_axis
    lo = (-0.5 * BENCH_EDGE_M, -0.5 * BENCH_EDGE_M, BENCH_LIFT_M)
    hi = (0.5 * BENCH_EDGE_M, 0.5 * BENCH_EDGE_M, BENCH_LIFT_M + BENCH_EDGE_M)
    return box_scene(lo, hi, spacing, material, BENCH_DENSITY)


def bench_cube_model(n_per_axis: int, batch: int = 1, device: str = "cpu", cpu_threads: int = 1,
                     kernel: KernelOptions | None = None) -> Model:
    """Model of `batch` copies of the standard cube, fixed dt 1e-4 s, dx = 0.4/n m (cpu_threads, kernel: SimConfig's
    fields)."""
    cfg = SimConfig(device=device, dx_m=2.0 * BENCH_EDGE_M / n_per_axis, dt_fixed_s=BENCH_DT_S, cpu_threads=cpu_threads,
                    kernel=kernel or KernelOptions())
    return build_model([bench_cube_scene(n_per_axis) for _ in range(batch)], cfg)
