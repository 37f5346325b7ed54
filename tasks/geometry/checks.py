"""L0 hard-gate metrics: watertightness, volume, extents, and mesh <-> particle / Gaussian / proxy alignment."""

from __future__ import annotations

import numpy as np
import trimesh
from pydantic import Field
from scipy.spatial import cKDTree

from contracts.base import Model
from contracts.evidence import GateResult
from contracts.stage import StageContract

_SURFACE_SAMPLES = 40_000
_VERIFY_ABOVE_M = 1e-3  # estimated-outside points farther than this are confirmed by the winding number [m]
_VERIFY_MAX = 128  # at most this many (the farthest) are confirmed; the rest keep the conservative estimate
# point x triangle pairs per block of winding_numbers: its ~20 temporaries of this many float64 stay small enough for
# the allocator's heap; blocks of 4M pairs (32 MB each) were mapped and unmapped afresh, and the page faults made the
# first call in a process 15x slower (3.7 s against 0.2 s for 128 points on a 21k-face plush koala)
_WINDING_BLOCK = 262_144


def winding_numbers(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """Generalised winding number of each point (1 inside, 0 outside a closed outward mesh; Van Oosterom-Strackee),
    on coordinate planes (P x F arrays per axis: numpy's norms, dots and cross products over a last axis of 3 are
    several times slower)."""
    tri = mesh.triangles
    corner = [[np.ascontiguousarray(tri[:, k, i]) for i in range(3)] for k in range(3)]  # [corner][axis] (F,)
    out = np.zeros(len(points))
    step = max(1, _WINDING_BLOCK // max(len(tri), 1))
    for s in range(0, len(points), step):
        pts = points[s : s + step]
        a, b, c = ([corner[k][i][None, :] - pts[:, None, i] for i in range(3)] for k in range(3))
        la, lb, lc = (np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) for v in (a, b, c))
        det = (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
               + a[2] * (b[0] * c[1] - b[1] * c[0]))
        ab, bc, ca = ((u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) for u, v in ((a, b), (b, c), (c, a)))
        den = la * lb * lc + ab * lc + bc * la + ca * lb
        out[s : s + step] = (2.0 * np.arctan2(det, den)).sum(axis=1) / (4.0 * np.pi)
    return out


class GeometryChecks(Model):
    """Observed metrics (SI units in the names) and the contract's gates evaluated on them."""

    metrics: dict[str, float]
    gates: list[GateResult]
    passed: bool = Field(description="every hard gate passed")

    @property
    def failed(self) -> list[str]:
        """Names of the failed gates."""
        return [g.gate for g in self.gates if not g.passed]


class SurfaceSamples:
    """A mesh's dense surface samples, their faces and a k-d tree over them (outside_distance's estimate)."""

    def __init__(self, mesh: trimesh.Trimesh, seed: int = 0) -> None:
        self.points, self.faces = trimesh.sample.sample_surface(mesh, _SURFACE_SAMPLES, seed=seed)
        self.tree = cKDTree(self.points)


def outside_distance(mesh: trimesh.Trimesh, points: np.ndarray, seed: int = 0,
                     surface: SurfaceSamples | None = None) -> np.ndarray:
    """Distance [m] of each point outside the surface (0 inside): nearest dense surface sample and its normal's side;
    the farthest estimated-outside points are confirmed by the winding number and measured exactly. `surface`: the
    mesh's SurfaceSamples (for `seed`) when several point sets are measured against one mesh."""
    if surface is None:
        surface = SurfaceSamples(mesh, seed)
    samples, fidx = surface.points, surface.faces
    d, i = surface.tree.query(points)
    side = np.einsum("ij,ij->i", points - samples[i], mesh.face_normals[fidx[i]])
    out = np.where(side > 0, d, 0.0)
    check = np.flatnonzero(out > _VERIFY_ABOVE_M)
    check = check[np.argsort(-out[check], kind="stable")][:_VERIFY_MAX]
    if len(check):
        inside = winding_numbers(mesh, points[check]) > 0.5
        out[check[inside]] = 0.0
        far = check[~inside]
        if len(far):
            out[far] = trimesh.proximity.closest_point(mesh, points[far])[1]
    return out


def geometry_metrics(
    mesh: trimesh.Trimesh, particles: dict[str, np.ndarray], gaussians: dict[str, np.ndarray],
    proxy_volume_m3: float, proxy_parts: int,
) -> dict[str, float]:
    """Every L0 observation named in the contract, plus alignment extras."""
    pos, vol = particles["positions_m"], particles["volumes_m3"]
    volume = float(mesh.volume) if mesh.is_watertight else 0.0
    ext = mesh.extents
    gpos = np.asarray(gaussians["positions_m"], dtype=np.float64)
    com = mesh.center_mass if mesh.is_watertight else mesh.centroid
    p_com = (pos * vol[:, None]).sum(axis=0) / vol.sum()
    surface = SurfaceSamples(mesh)  # sampled once for the Gaussians and the particles
    g_out = outside_distance(mesh, gpos, surface=surface)
    return {
        "watertight": float(mesh.is_watertight and mesh.is_winding_consistent),
        "volume_m3": volume,
        "min_extent_m": float(ext.min()),
        "max_extent_m": float(ext.max()),
        "extent_x_m": float(ext[0]), "extent_y_m": float(ext[1]), "extent_z_m": float(ext[2]),
        "min_z_m": float(mesh.bounds[0, 2]),
        "particle_count": float(len(pos)),
        "particle_spacing_m": float(particles["spacing_m"]),
        "particle_mesh_distance_max_m": float(outside_distance(mesh, pos, surface=surface).max()),
        # against what the particles fill: the mesh volume, or a hollow object's shell (build_body's body_volume_m3)
        "particle_volume_ratio": float(vol.sum() / float(particles.get("body_volume_m3", volume)))
        if volume > 0 else 0.0,
        "particle_body_volume_ratio": float(particles.get("body_volume_m3", volume)) / volume if volume > 0 else 0.0,
        "particle_lattice_fill_ratio": float(particles["lattice_fill_ratio"]),
        "particle_com_offset_m": float(np.linalg.norm(p_com - com)),
        "gaussian_count": float(len(gpos)),
        "gaussian_mesh_distance_p95_m": float(np.percentile(g_out, 95)),
        "gaussian_mesh_distance_max_m": float(g_out.max()),
        "proxy_volume_ratio": proxy_volume_m3 / volume if volume > 0 else 0.0,
        "proxy_parts": float(proxy_parts),
        "mesh_faces": float(len(mesh.faces)),
    }


def evaluate(metrics: dict[str, float], contract: StageContract) -> GeometryChecks:
    """Evaluate the contract's hard gates on the metrics."""
    gates = [
        GateResult(gate=g.name, metric=g.metric, value=metrics.get(g.metric), passed=g.passes(metrics.get(g.metric)))
        for g in contract.hard_gates
    ]
    return GeometryChecks(metrics=metrics, gates=gates, passed=all(g.passed for g in gates))
