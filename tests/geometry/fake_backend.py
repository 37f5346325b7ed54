"""A small reconstruction backend for the tests: the documented Python entry-point interface, no model inside."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import trimesh

CALLS: list[dict[str, Any]] = []


def icosphere(request: dict[str, Any]) -> trimesh.Trimesh:
    """A unit-diameter icosphere stretched 2:1:1 along y (normalised, y-long, as image-to-3D models return)."""
    CALLS.append(dict(request))
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    mesh.apply_scale([0.5, 1.0, 0.5])
    return mesh


def red_bean_file(request: dict[str, Any]) -> dict[str, Any]:
    """A red capsule written as a PLY file into the scratch directory, plus red Gaussians on its surface."""
    CALLS.append(dict(request))
    mesh = trimesh.creation.capsule(height=0.6, radius=0.2, count=[24, 24])
    path = Path(request["out_dir"]) / "bean.ply"
    mesh.export(path)
    rng = np.random.default_rng(int(request["seed"]))
    pts, _ = trimesh.sample.sample_surface(mesh, 2000, seed=int(request["seed"]))
    write_gaussians(Path(request["out_dir"]) / "bean_gaussians.ply", pts + rng.normal(0, 1e-4, pts.shape),
                    np.tile([0.9, 0.1, 0.1], (len(pts), 1)))
    return {"mesh": str(path), "gaussians_ply": str(Path(request["out_dir"]) / "bean_gaussians.ply")}


def metric_box(request: dict[str, Any]) -> dict[str, Any]:
    """A 12 x 8 x 5 cm box as arrays, in metres."""
    box = trimesh.creation.box(extents=[0.12, 0.08, 0.05])
    return {"mesh": {"vertices": box.vertices, "faces": box.faces}, "metric": True}


def two_spheres(request: dict[str, Any]) -> trimesh.Trimesh:
    """Two separate spheres of equal size: two objects, not one."""
    a = trimesh.creation.icosphere(subdivisions=2, radius=0.3)
    b = a.copy()
    b.apply_translation([1.0, 0, 0])
    return trimesh.util.concatenate([a, b])


def open_sheet(request: dict[str, Any]) -> dict[str, Any]:
    """A flat square of two triangles: no volume at all."""
    return {"vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "faces": [[0, 1, 2], [0, 2, 3]]}


def not_a_mesh(request: dict[str, Any]) -> str:
    """A string that is no file: the answer of a backend that reports an error as text."""
    return "CUDA out of memory"


def broken(request: dict[str, Any]) -> None:
    """A backend whose model code raises."""
    raise RuntimeError("checkpoint not found: /models/sam3d.ckpt")


def write_gaussians(path: Path, positions: np.ndarray, rgb: np.ndarray) -> None:
    """A minimal 3DGS .ply: centres, SH DC colours, opacity logits, log scales, unit quaternions."""
    from plyfile import PlyData, PlyElement

    from tasks.geometry.gaussians import SH_C0

    names = ["x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
             "rot_0", "rot_1", "rot_2", "rot_3"]
    data = np.zeros(len(positions), dtype=[(n, "f4") for n in names])
    for i, k in enumerate("xyz"):
        data[k] = positions[:, i]
    for i in range(3):
        data[f"f_dc_{i}"] = (rgb[:, i] - 0.5) / SH_C0
    data["opacity"] = 4.0
    data["scale_0"] = data["scale_1"] = data["scale_2"] = np.log(0.005)
    data["rot_0"] = 1.0
    PlyData([PlyElement.describe(data, "vertex")]).write(str(path))
