"""Model: what does not change during a rollout (particles' rest volume and mass, materials, colliders, grid size)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, TypedDict, Unpack, cast

import numpy as np
import warp as wp

from contracts.errors import InputError, SimulationError
from contracts.material import Material
from contracts.sim import SimConfig
from tasks.mpm.control import Control
from tasks.mpm.state import State

if TYPE_CHECKING:
    from tasks.mpm.control import Control
    from tasks.mpm.state import State

ColliderKind = Literal["box", "capsule", "halfspace", "pad", "convex"]
_KIND_CODE = {"box": 0, "capsule": 1, "halfspace": 2}
PAD_FACES = ("-x", "+x", "-y", "+y", "-z", "+z")  # kernel code of a pad = 3 + index here


def kind_code(c: ColliderSpec) -> int:
    """The kernels' code of a collider kind (a pad's code also names its gripping face)."""
    if c.kind == "convex":
        if c.planes is None or len(c.planes) < 4:
            raise InputError(f"collider {c.name or 'convex'}: a convex collider needs >= 4 planes (convex_collider)")
        return 9
    if c.kind == "pad":
        if c.face not in PAD_FACES:
            raise InputError(f"collider {c.name or 'pad'}: face must be one of {PAD_FACES}, got {c.face!r}")
        return 3 + PAD_FACES.index(c.face)
    if c.kind not in _KIND_CODE:
        raise InputError(f"unknown collider kind {c.kind!r}")
    return _KIND_CODE[c.kind]


@dataclass
class ColliderSpec:
    """A kinematic collider: its shape in its local frame, friction, and initial pose and velocity (SI).

    kind: "box" (size = half extents [m]), "capsule" (size = (radius [m], half length [m] along local z, 0)),
    "halfspace" (solid below the local z = 0 plane; size unused), "pad" (a box, size = half extents [m], that grips
    through one face, ``face`` in local axes such as "-y": a node or particle inside it leaves through that face, as
    material squeezed by a finger does; a plain box sends it to the nearest face, which for a pad only a few grid
    cells wide is often a side face, and the squeezed material then flows into the pad unresisted), "convex" (a convex
    polytope, ``planes`` (P, 4) = outward unit normal n and offset d [m] of each face, inside iff n . x <= d for all;
    size = half extents [m] of its bounding box about the local origin; built by ``convex_collider`` from points).
    rotation_xyzw is a unit quaternion (x, y, z, w).
    bonded = True glues the object to the collider (v = collider velocity inside it, no separation: clamps).
    """

    kind: ColliderKind
    size_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    friction: float = 0.5
    bonded: bool = False
    position_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation_xyzw: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
    linear_velocity_m_per_s: tuple[float, float, float] = (0.0, 0.0, 0.0)
    angular_velocity_rad_per_s: tuple[float, float, float] = (0.0, 0.0, 0.0)
    name: str = ""
    face: str = ""  # pads only: the gripping face, one of PAD_FACES
    planes: np.ndarray | None = None  # convex only: (P, 4) face planes (n_x, n_y, n_z, d) in the local frame


class ColliderKw(TypedDict, total=False):
    """The keyword fields of ColliderSpec that the ``*_collider`` helpers pass through."""

    friction: float
    bonded: bool
    position_m: tuple[float, float, float]
    rotation_xyzw: tuple[float, float, float, float]
    linear_velocity_m_per_s: tuple[float, float, float]
    angular_velocity_rad_per_s: tuple[float, float, float]
    name: str


def _size3(values: Sequence[float] | np.ndarray) -> tuple[float, float, float]:
    """Floats of a 3-vector as a tuple (the length is not checked here, as before)."""
    return cast(tuple[float, float, float], tuple(float(h) for h in values))


def box_collider(half_extents_m: Sequence[float] | np.ndarray, **kw: Unpack[ColliderKw]) -> ColliderSpec:
    """A box collider with half extents [m] (see ColliderSpec for the keyword fields)."""
    return ColliderSpec(kind="box", size_m=_size3(half_extents_m), **kw)


def pad_collider(half_extents_m: Sequence[float] | np.ndarray, face: str, **kw: Unpack[ColliderKw]) -> ColliderSpec:
    """A finger pad: a box with half extents [m] that grips through ``face`` ("-x" ... "+z", local axes)."""
    return ColliderSpec(kind="pad", size_m=_size3(half_extents_m), face=face, **kw)


def convex_collider(points_m: np.ndarray, **kw: Unpack[ColliderKw]) -> ColliderSpec:
    """A convex collider: the convex hull of points [m] given in the collider's local frame (a CoACD part, a tool,
    a fixture). Coplanar hull facets are merged into one plane."""
    from scipy.spatial import ConvexHull, QhullError

    pts = np.asarray(points_m, dtype=np.float64).reshape(-1, 3)
    if len(pts) < 4 or not np.all(np.isfinite(pts)):
        raise InputError("a convex collider needs >= 4 finite points")
    try:
        hull = ConvexHull(pts)
    except QhullError as exc:
        raise InputError(f"a convex collider needs points spanning a volume: {str(exc).splitlines()[0]}") from exc
    eq = hull.equations  # rows (n, offset): n . x + offset <= 0 inside, |n| = 1
    planes = np.column_stack([eq[:, :3], -eq[:, 3]])
    planes = np.unique(np.round(planes, 9), axis=0)
    half = np.max(np.abs(pts[hull.vertices]), axis=0)
    return ColliderSpec(kind="convex", size_m=_size3(half), planes=planes, **kw)


def capsule_collider(radius_m: float, half_length_m: float, **kw: Unpack[ColliderKw]) -> ColliderSpec:
    """A capsule collider along its local z axis: radius [m], half length of the segment [m]."""
    return ColliderSpec(kind="capsule", size_m=(float(radius_m), float(half_length_m), 0.0), **kw)


def halfspace_collider(**kw: Unpack[ColliderKw]) -> ColliderSpec:
    """A half-space collider: solid below the plane z = 0 of its local frame (walls, inclines)."""
    return ColliderSpec(kind="halfspace", **kw)


class SceneKw(TypedDict, total=False):
    """The optional ground, gravity and domain fields of SceneSpec that scene builders pass through."""

    ground: bool
    ground_height_m: float | None
    ground_friction: float | None
    gravity_m_per_s2: tuple[float, float, float] | None
    domain_min_m: tuple[float, float, float] | None
    domain_max_m: tuple[float, float, float] | None


@dataclass
class SceneSpec:
    """One independent scene: an object's particles, its material and density, its colliders and ground (SI)."""

    positions_m: np.ndarray  # (N, 3)
    volumes_m3: np.ndarray  # (N,) rest volumes, sum = object volume
    density_kg_per_m3: float
    material: Material
    colliders: list[ColliderSpec] = field(default_factory=list)
    velocities_m_per_s: np.ndarray | None = None  # (N, 3); None = at rest
    ground: bool = True
    ground_height_m: float | None = None  # None = SimConfig.ground_height_m
    ground_friction: float | None = None  # None = SimConfig.ground_friction
    gravity_m_per_s2: tuple[float, float, float] | None = None  # None = SimConfig.gravity_m_per_s2
    domain_min_m: tuple[float, float, float] | None = None  # allowed region; None = generous box around start
    domain_max_m: tuple[float, float, float] | None = None


def _bounding_radius(c: ColliderSpec) -> float:
    """Radius [m] of a sphere around the collider origin that contains its solid (inf for a half-space)."""
    if c.kind in ("box", "pad", "convex"):
        return float(np.linalg.norm(c.size_m))
    if c.kind == "capsule":
        return float(c.size_m[0] + c.size_m[1])
    return 1.0e30


def _vec3_array(a: np.ndarray, device: str) -> wp.array:
    """Float32 (N, 3) numpy -> wp.array(vec3)."""
    return wp.array(np.ascontiguousarray(a, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3, device=device)


def _check_time_step(model: Model, config: SimConfig) -> None:
    """SimulationError when a scene's material alone needs CFL (or viscous) steps below config.dt_min_s (explicit
    MPM)."""
    if model.viscous_dt_s / config.substeps < config.dt_min_s:
        k = int(np.argmin(model.viscous_dt_np))
        raise SimulationError(
            f"the material is too viscous for explicit MPM at dx = {model.dx:.3g} m: eta = "
            f"{model.materials[k].viscosity_pa_s:.3g} Pa s, density {model.densities[k]:.4g} kg/m^3 give viscous time "
            f"steps of {model.viscous_dt_s / config.substeps:.2g} s, below the {config.dt_min_s:g} s floor "
            "(SimConfig.dt_min_s): lower the viscosity, or coarsen the grid"
        )
    worst = int(np.argmax(model.p_wave_speed))
    c = float(model.p_wave_speed[worst])
    dt = config.cfl * model.dx / c / config.substeps
    if dt < config.dt_min_s:
        m = model.materials[worst]
        raise SimulationError(
            f"the material is too stiff for explicit MPM at dx = {model.dx:.3g} m: E = {m.wall_modulus_pa:.3g} Pa, "
            f"nu = {m.poisson_ratio:g}, density {model.densities[worst]:.4g} kg/m^3 give a p-wave speed of {c:.3g} m/s "
            f"and CFL time steps of {dt:.2g} s, below the {config.dt_min_s:g} s floor (SimConfig.dt_min_s): "
            "lower E or nu, or coarsen the grid"
        )


class Model:
    """Static data of B batched scenes on one Warp device; build with ``build_model``."""

    def __init__(self, scenes: Sequence[SceneSpec], config: SimConfig) -> None:
        if not scenes:
            raise InputError("an MPM model needs at least one scene")
        self.config = config
        self.device = config.device
        if self.device == "cuda" and not wp.is_cuda_available():
            raise SimulationError("device 'cuda' requested but no CUDA device is available to Warp")
        self.scenes = list(scenes)
        self.n_scenes = len(scenes)
        counts = []
        for i, sc in enumerate(scenes):
            pos = np.asarray(sc.positions_m, dtype=np.float64)
            vol = np.asarray(sc.volumes_m3, dtype=np.float64)
            if pos.ndim != 2 or pos.shape[1] != 3 or len(pos) == 0:
                raise InputError(f"scene {i}: positions_m must be a non-empty (N, 3) array")
            if vol.shape != (len(pos),) or not np.all(vol > 0) or not np.all(np.isfinite(pos)):
                raise InputError(f"scene {i}: volumes_m3 must be (N,) positive and positions finite")
            if not (sc.density_kg_per_m3 > 0 and math.isfinite(sc.density_kg_per_m3)):
                raise InputError(f"scene {i}: density must be positive [kg/m^3]")
            counts.append(len(pos))
        self.scene_counts = np.asarray(counts, dtype=np.int64)
        self.scene_start_np = np.concatenate([[0], np.cumsum(self.scene_counts)[:-1]]).astype(np.int32)
        self.n_particles = int(self.scene_counts.sum())
        if self.n_particles >= 2**31 - 1:
            raise InputError("too many particles for int32 indexing")

        # grid spacing: config or twice the mean particle spacing of the first scene
        if config.dx_m is not None:
            self.dx = float(config.dx_m)
        else:
            spacing = float(np.mean(np.asarray(scenes[0].volumes_m3)) ** (1.0 / 3.0))
            self.dx = 2.0 * spacing
        dx = self.dx

        pos_all = np.concatenate([np.asarray(s.positions_m, dtype=np.float64) for s in scenes])
        vol_all = np.concatenate([np.asarray(s.volumes_m3, dtype=np.float64) for s in scenes])
        rho_per_p = np.concatenate([np.full(c, s.density_kg_per_m3) for c, s in zip(counts, scenes)])
        vel_all = np.concatenate(
            [
                np.zeros((c, 3)) if s.velocities_m_per_s is None else np.asarray(s.velocities_m_per_s, float)
                for c, s in zip(counts, scenes)
            ]
        )
        if vel_all.shape != pos_all.shape:
            raise InputError("velocities_m_per_s must match positions_m in shape")
        self.x0 = pos_all.astype(np.float32)
        self.v0 = vel_all.astype(np.float32)
        self.particle_vol_np = vol_all.astype(np.float32)
        self.particle_mass_np = (vol_all * rho_per_p).astype(np.float32)
        self.particle_scene_np = np.repeat(np.arange(self.n_scenes, dtype=np.int32), self.scene_counts)
        self.scene_mass_kg = np.asarray(
            [float(np.sum(np.asarray(s.volumes_m3)) * s.density_kg_per_m3) for s in scenes]
        )

        # per-scene material
        self.materials = [s.material for s in scenes]
        self.densities = np.asarray([s.density_kg_per_m3 for s in scenes], dtype=np.float64)
        self.mu_np = np.asarray([m.mu_pa for m in self.materials], dtype=np.float32)
        self.lambda_np = np.asarray([m.lambda_pa for m in self.materials], dtype=np.float32)
        self.damping_np = np.asarray([m.damping_rate_per_s for m in self.materials], dtype=np.float32)
        self.eta_np = np.asarray([m.viscosity_pa_s for m in self.materials], dtype=np.float32)
        self.p_wave_speed = np.asarray(
            [m.p_wave_speed_m_per_s(r) for m, r in zip(self.materials, self.densities)], dtype=np.float64
        )
        # the explicit viscous stress's own step limit (Material.viscous_time_step_s; inf without viscosity)
        self.viscous_dt_np = np.asarray(
            [m.viscous_time_step_s(r, self.dx) for m, r in zip(self.materials, self.densities)], dtype=np.float64
        )
        self.viscous_dt_s = float(np.min(self.viscous_dt_np))
        if config.dt_fixed_s is None:
            _check_time_step(self, config)

        # ground and gravity
        self.ground_enabled_np = np.asarray([1 if s.ground else 0 for s in scenes], dtype=np.int32)
        self.ground_height_np = np.asarray(
            [config.ground_height_m if s.ground_height_m is None else s.ground_height_m for s in scenes],
            dtype=np.float32,
        )
        self.ground_mu_np = np.asarray(
            [config.ground_friction if s.ground_friction is None else s.ground_friction for s in scenes],
            dtype=np.float32,
        )
        self.gravity_np = np.asarray(
            [config.gravity_m_per_s2 if s.gravity_m_per_s2 is None else s.gravity_m_per_s2 for s in scenes],
            dtype=np.float64,
        )

        # allowed domain per scene
        lo_list, hi_list, ext_list = [], [], []
        for i, s in enumerate(scenes):
            p = np.asarray(s.positions_m, dtype=np.float64)
            lo, hi = p.min(axis=0), p.max(axis=0)
            ext_list.append(hi - lo)
            pad = max(0.5, 2.0 * float(np.max(hi - lo)))
            dlo = lo - pad
            if s.ground:
                dlo[2] = min(lo[2], float(self.ground_height_np[i])) - pad
            dhi = hi + pad
            if s.domain_min_m is not None:
                dlo = np.asarray(s.domain_min_m, dtype=np.float64)
            if s.domain_max_m is not None:
                dhi = np.asarray(s.domain_max_m, dtype=np.float64)
            if np.any(lo < dlo) or np.any(hi > dhi):
                raise InputError(f"scene {i}: particles start outside the allowed domain")
            lo_list.append(dlo)
            hi_list.append(dhi)
        self.domain_lo_np = np.asarray(lo_list, dtype=np.float32)
        self.domain_hi_np = np.asarray(hi_list, dtype=np.float32)

        # grid window: the object's extent plus a margin of free cells each side (fitted, moves with the object)
        self.margin_cells = int(min(32, max(4, math.ceil(config.grid_margin_m / dx))))
        self.guard_cells = 2
        ext_max = np.max(np.asarray(ext_list), axis=0)
        self.grid_dims = tuple(int(math.ceil(e / dx)) + 2 * self.margin_cells + 4 for e in ext_max)
        # particles move < cfl*dx per step (CFL), so a refit every K steps keeps them inside the margin
        self.refit_interval = int(max(1, min(16, math.floor((self.margin_cells - self.guard_cells) / config.cfl))))

        # colliders (grouped by scene)
        specs: list[ColliderSpec] = []
        col_start, col_count = [], []
        for s in scenes:
            col_start.append(len(specs))
            col_count.append(len(s.colliders))
            for c in s.colliders:
                kind_code(c)  # raises on an unknown kind or pad face
                if c.friction < 0 or not math.isfinite(c.friction):
                    raise InputError("collider friction must be >= 0")
                specs.append(c)
        self.collider_specs = specs
        self.n_colliders = len(specs)
        self.col_start_np = np.asarray(col_start, dtype=np.int32)
        self.col_count_np = np.asarray(col_count, dtype=np.int32)
        self.col_kind_np = np.asarray([kind_code(c) for c in specs], dtype=np.int32)
        planes: list[np.ndarray] = [np.zeros((1, 4))]
        params: list[tuple[float, ...]] = []
        first = 1  # plane 0 is a placeholder so the array is never empty
        for c in specs:
            if c.kind == "convex":
                assert c.planes is not None
                params.append((float(first), float(len(c.planes)), 0.0))
                planes.append(np.asarray(c.planes, dtype=np.float64))
                first += len(c.planes)
            else:
                params.append(tuple(c.size_m))
        self.col_planes_np = np.concatenate(planes).astype(np.float32)
        self.col_params_np = np.asarray(params, dtype=np.float32).reshape(-1, 3)
        self.col_mu_np = np.asarray([c.friction for c in specs], dtype=np.float32)
        self.col_radius2_np = np.asarray([_bounding_radius(c) ** 2 for c in specs], dtype=np.float32)
        self.col_bonded_np = np.asarray([1 if c.bonded else 0 for c in specs], dtype=np.int32)

        # reduction chunks (contiguous, one scene each); on CUDA short chunks keep the serial loop off the
        # critical path for small scenes, long ones limit same-address atomics for large scenes. (Interleaving a
        # scene's chunks for coalesced loads was measured on an H200 and gained nothing: the loop is latency-bound.)
        cs, cb, ce = [], [], []
        for si in range(self.n_scenes):
            b0 = int(self.scene_start_np[si])
            b1 = b0 + int(self.scene_counts[si])
            n_s = b1 - b0
            chunk = 256 if self.device == "cpu" else int(min(256, max(32, n_s // 128)))
            for b in range(b0, b1, chunk):
                cs.append(si)
                cb.append(b)
                ce.append(min(b + chunk, b1))
        d = self.device
        self.chunk_scene: wp.array = wp.array(np.asarray(cs, np.int32), dtype=wp.int32, device=d)
        self.chunk_begin: wp.array = wp.array(np.asarray(cb, np.int32), dtype=wp.int32, device=d)
        self.chunk_end: wp.array = wp.array(np.asarray(ce, np.int32), dtype=wp.int32, device=d)
        self.n_chunks = len(cs)

        # device arrays
        self.particle_mass: wp.array = wp.array(self.particle_mass_np, dtype=float, device=d)
        self.particle_vol: wp.array = wp.array(self.particle_vol_np, dtype=float, device=d)
        self.particle_scene: wp.array = wp.array(self.particle_scene_np, dtype=wp.int32, device=d)
        self.scene_start: wp.array = wp.array(self.scene_start_np, dtype=wp.int32, device=d)
        self.scene_mu: wp.array = wp.array(self.mu_np, dtype=float, device=d)
        self.scene_lambda: wp.array = wp.array(self.lambda_np, dtype=float, device=d)
        self.scene_damping: wp.array = wp.array(self.damping_np, dtype=float, device=d)
        self.scene_eta: wp.array = wp.array(self.eta_np, dtype=float, device=d)
        self.ground_enabled: wp.array = wp.array(self.ground_enabled_np, dtype=wp.int32, device=d)
        self.ground_height: wp.array = wp.array(self.ground_height_np, dtype=float, device=d)
        self.ground_mu: wp.array = wp.array(self.ground_mu_np, dtype=float, device=d)
        self.domain_lo = _vec3_array(self.domain_lo_np, d)
        self.domain_hi = _vec3_array(self.domain_hi_np, d)
        nc = max(1, self.n_colliders)  # keep arrays non-empty for kernel arguments
        pad = nc - self.n_colliders
        self.col_start: wp.array = wp.array(self.col_start_np, dtype=wp.int32, device=d)
        self.col_count: wp.array = wp.array(self.col_count_np, dtype=wp.int32, device=d)
        self.col_kind: wp.array = wp.array(np.concatenate([self.col_kind_np, np.zeros(pad, np.int32)]), dtype=wp.int32,
                                           device=d)
        self.col_params = _vec3_array(np.concatenate([self.col_params_np, np.zeros((pad, 3), np.float32)]), d)
        self.col_planes: wp.array = wp.array(self.col_planes_np, dtype=wp.vec4, device=d)
        self.col_radius2: wp.array = wp.array(
            np.concatenate([self.col_radius2_np, np.zeros(pad, np.float32)]), dtype=float, device=d
        )
        self.col_mu: wp.array = wp.array(np.concatenate([self.col_mu_np, np.zeros(pad, np.float32)]), dtype=float,
                                         device=d)
        self.col_bonded: wp.array = wp.array(
            np.concatenate([self.col_bonded_np, np.zeros(pad, np.int32)]), dtype=wp.int32, device=d
        )

    # -- queries -------------------------------------------------------------------------------------------------
    def collider_index(self, scene: int, index: int) -> int:
        """Global collider index of the index-th collider of a scene."""
        if not (0 <= scene < self.n_scenes) or not (0 <= index < int(self.col_count_np[scene])):
            raise InputError(f"no collider {index} in scene {scene}")
        return int(self.col_start_np[scene]) + index

    def scene_slice(self, scene: int) -> slice:
        """Particle index range of a scene in the batched arrays."""
        b = int(self.scene_start_np[scene])
        return slice(b, b + int(self.scene_counts[scene]))

    def set_collider_friction(self, scene: int, index: int, friction: float) -> None:
        """Change a collider's Coulomb friction coefficient [-] (takes effect at the next step)."""
        c = self.collider_index(scene, index)
        self.col_mu_np[c] = float(friction)
        self.col_mu.assign(np.concatenate([self.col_mu_np, np.zeros(max(1, self.n_colliders) - self.n_colliders)]))

    def set_ground_friction(self, scene: int, friction: float) -> None:
        """Change a scene's ground friction coefficient [-]."""
        self.ground_mu_np[scene] = float(friction)
        self.ground_mu.assign(self.ground_mu_np)

    def max_wave_speed(self) -> float:
        """Largest dilatational wave speed c_p over the scenes [m/s]."""
        return float(np.max(self.p_wave_speed))

    def state(self) -> State:
        """A fresh State at the initial positions/velocities, F = I, C = 0."""
        return State.initial(self)

    def control(self) -> Control:
        """A Control holding the colliders' initial poses/velocities and the scenes' gravity."""
        return Control(self)


def build_model(scenes: Sequence[SceneSpec], config: SimConfig | None = None) -> Model:
    """Build the static Model of B batched scenes (all on config.device)."""
    return Model(scenes, config or SimConfig())

