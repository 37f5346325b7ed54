"""Reference renders on the CPU without a display: orthographic z-buffer rasteriser with Lambert shading.

L0's own views stay in tasks/geometry, not tasks/render (#37): L0's writer (outputs.write_outputs) and the shape
Designer's vision Critic (shape_designer.render_pngs) draw them, and tasks/render sits above geometry in the layering
test's TASKS_ORDER (it deforms geometry's Gaussians and draws the robot), so a move would be an import back up.
"""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import trimesh

from tasks.geometry.raster import triangle_column_pairs

# view name -> (screen-right axis, screen-up axis, towards-viewer axis) in the asset frame
VIEWS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]] = {
    "front": ((0, 1, 0), (0, 0, 1), (1, 0, 0)),    # camera on +x looking back at the object
    "side": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),    # camera on -y
    "top": ((1, 0, 0), (0, 1, 0), (0, 0, 1)),      # camera above
}


def render_view(mesh: trimesh.Trimesh, view: str, size_px: int = 384) -> np.ndarray:
    """RGB uint8 image (size_px, size_px, 3) of the mesh from a named view, object filling ~85 % of the frame."""
    right, up, toward = (np.asarray(a, dtype=np.float64) for a in VIEWS[view])
    basis = np.stack([right, up, toward], axis=1)
    v = (mesh.vertices - mesh.bounds.mean(axis=0)) @ basis
    span = float(np.abs(v[:, :2]).max()) * 2.0 / 0.85
    px = span / size_px
    origin = np.array([-span / 2.0 + px / 2.0, -span / 2.0 + px / 2.0])
    tri = v[mesh.faces]
    vn = np.asarray(mesh.vertex_normals) @ basis
    vc = np.asarray(mesh.visual.vertex_colors, dtype=np.float64)[:, :3] / 255.0 if mesh.visual.kind == "vertex" \
        else np.full((len(mesh.vertices), 3), 0.75)
    depth = np.full(size_px * size_px, -np.inf)
    color = np.ones((size_px * size_px, 3))
    light = np.array([0.35, 0.45, 0.82])
    light /= np.linalg.norm(light)
    for t, ix, iy, w in triangle_column_pairs(tri[:, :, :2], origin, px, (size_px, size_px)):
        z = np.einsum("ij,ij->i", w, tri[t, :, 2])
        pix = iy * size_px + ix
        order = np.lexsort((-z, pix))
        pix_o, first = np.unique(pix[order], return_index=True)
        sel = order[first]
        better = z[sel] > depth[pix_o]
        sel, pix_o = sel[better], pix_o[better]
        f = mesh.faces[t[sel]]
        n = np.einsum("ij,ijk->ik", w[sel], vn[f])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        c = np.einsum("ij,ijk->ik", w[sel], vc[f])
        shade = 0.35 + 0.65 * np.clip(np.abs(n @ light), 0, 1)
        depth[pix_o] = z[sel]
        color[pix_o] = np.clip(c * shade[:, None], 0, 1)
    img = color.reshape(size_px, size_px, 3)[::-1]  # row 0 is the top of the image
    return (img * 255).round().astype(np.uint8)


def write_renders(mesh: trimesh.Trimesh, out_dir: Path, size_px: int = 384) -> dict[str, str]:
    """front.png, side.png and top.png in out_dir; returns view -> file name."""
    out_dir.mkdir(parents=True, exist_ok=True)
    files = {}
    for view in VIEWS:
        iio.imwrite(out_dir / f"{view}.png", render_view(mesh, view, size_px))
        files[view] = f"{view}.png"
    return files
