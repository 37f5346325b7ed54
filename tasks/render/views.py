"""L0's reference views (front, side, top) on the CPU without a display: orthographic Cameras (tasks.render.camera),
a z-buffer over the triangle / pixel overlap (tasks.render.columns), Lambert shading.

Each view is a camera looking at the centre of the mesh's bounding box: "front" from +x (looking along -x, +y to the
right), "side" from -y (looking along +y, +x to the right), "top" from above (looking down, +x to the right, +y up the
image), "iso" from the front, the side and above at once (a three-quarter view 26 deg above the ground: what a person
names an object from; a long tube seen end-on in "front" reads as a washer); the object fills FILL of the frame. L0's writer (tasks.geometry.outputs), the shape Designer's vision Critic
and the drop videos' view names (tasks.render.protocol_video) use them.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import imageio.v3 as iio
import numpy as np

from tasks.render.camera import Camera, project
from tasks.render.columns import triangle_column_pairs
from tasks.render.finish import MATTE, Finish, shade_pixels
from tasks.render.scale_bar import draw_scale_bar

if TYPE_CHECKING:  # a mesh is only read here (vertices, faces, normals, colours): the card's import stays light
    import trimesh


class View(NamedTuple):
    """A named view's direction: from the object towards the camera (it looks along -toward) and the screen's up."""

    toward: tuple[float, float, float]
    up: tuple[float, float, float]


VIEWS: dict[str, View] = {
    "front": View((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),   # camera on +x looking back at the object
    "side": View((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),   # camera on -y
    "top": View((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),     # camera above, looking straight down
    "iso": View((1.0, -0.75, 0.6), (0.0, 0.0, 1.0)),   # camera front-right (37 deg round from the front), 26 deg up
}
FILL = 0.85  # the mesh's widest extent across the frame, as a fraction of it
FLAT = 0.25  # an object whose height is under this share of its second extent lies flat (a towel, a slice) [-]


def telling_views(extents_m: np.ndarray) -> tuple[str, str, str]:
    """The three stills a person names an object from: the three-quarter view first, then front and side; a flat
    object (a folded towel, a T-shirt laid out, a slice) from above and the front, its side seen edge-on telling
    nothing of its outline."""
    e = np.asarray(extents_m, np.float64)
    flat = e[2] < FLAT * float(np.sort(e[:2])[0])
    return ("iso", "top", "front") if flat else ("iso", "front", "side")
LIGHT = (0.35, 0.45, 0.82)  # towards the light in the view's (screen-right, screen-up, towards-viewer) axes
BACKGROUND = 1.0  # white


def view_camera(view: str, centre_m: np.ndarray, height_m: float, size_px: int) -> Camera:
    """The orthographic camera of a named view looking at centre_m, a square frame height_m high (a KeyError names an
    unknown view)."""
    toward, up = VIEWS[view]
    centre = np.asarray(centre_m, np.float64)
    return Camera(tuple(centre + np.asarray(toward)), tuple(centre), width=size_px, height=size_px, up=up,
                  ortho_height_m=height_m)


def view_axes(view: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The (screen-right, screen-up, towards-viewer) unit axes in the asset frame of a named view's camera."""
    rot = view_camera(view, np.zeros(3), 1.0, 2).frame()[0]
    return rot[0] + 0.0, -rot[1] + 0.0, -rot[2] + 0.0  # (+ 0.0: no negative zeros)


def render_view(mesh: trimesh.Trimesh, view: str, size_px: int = 384, finish: Finish | None = None,
                scale_bar: bool = False) -> np.ndarray:
    """RGB uint8 image (size_px, size_px, 3) of the mesh from a named view, object filling FILL of the frame.

    Without a finish: one Lambert light (the silhouettes the critics and tests compare). With one: the still a user
    sees, lit by key, fill and ambient light with the material's gloss, sheen, grain and mottle
    (tasks.render.finish); scale_bar draws a round length in the corner (tasks.render.scale_bar)."""
    centre = mesh.bounds.mean(axis=0)
    cam = view_camera(view, centre, 1.0, size_px)
    rot = cam.frame()[0]
    across = (np.asarray(mesh.vertices, np.float64) - centre) @ rot[:2].T  # (right, down) offsets [m]
    cam = replace(cam, ortho_height_m=float(np.abs(across).max()) * 2.0 / FILL)
    u, v, depth = project(cam, mesh.vertices)
    faces = np.asarray(mesh.faces)
    tri_px = np.stack([u, v], axis=1)[faces]
    tri_depth = depth[faces]
    normals = np.asarray(mesh.vertex_normals) @ rot.T  # camera frame (right, down, forward)
    vc = np.asarray(mesh.visual.vertex_colors, dtype=np.float64)[:, :3] / 255.0 if mesh.visual.kind == "vertex" \
        else np.full((len(mesh.vertices), 3), 0.75)
    zbuf = np.full(size_px * size_px, np.inf)
    color = np.full((size_px * size_px, 3), BACKGROUND)
    light = np.array([LIGHT[0], -LIGHT[1], -LIGHT[2]])  # in the camera frame
    light /= np.linalg.norm(light)
    verts = np.asarray(mesh.vertices, np.float64)
    world_normals = np.asarray(mesh.vertex_normals, np.float64)
    pixel_m = float(cam.ortho_height_m or 1.0) / size_px  # (always set just above)
    for t, ix, iy, w in triangle_column_pairs(tri_px, np.array([0.5, 0.5]), 1.0, (size_px, size_px)):
        z = np.einsum("ij,ij->i", w, tri_depth[t])
        pix = iy * size_px + ix  # row iy from the top
        order = np.lexsort((z, pix))
        pix_o, first = np.unique(pix[order], return_index=True)
        sel = order[first]  # the nearest triangle at each pixel of this batch
        better = z[sel] < zbuf[pix_o]
        sel, pix_o = sel[better], pix_o[better]
        f = faces[t[sel]]
        n = np.einsum("ij,ijk->ik", w[sel], normals[f])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        c = np.einsum("ij,ijk->ik", w[sel], vc[f])
        zbuf[pix_o] = z[sel]
        if finish is None:
            shade = 0.35 + 0.65 * np.clip(np.abs(n @ light), 0, 1)
            color[pix_o] = np.clip(c * shade[:, None], 0, 1)
        else:  # in the asset frame, where the grain's noise lives
            nw = np.einsum("ij,ijk->ik", w[sel], world_normals[f])
            nw /= np.maximum(np.linalg.norm(nw, axis=1, keepdims=True), 1e-12)
            color[pix_o] = shade_pixels(c, nw, np.einsum("ij,ijk->ik", w[sel], verts[f]), light @ rot,
                                        -rot[2], finish, pixel_m)
    img = (color.reshape(size_px, size_px, 3) * 255).round().astype(np.uint8)
    if scale_bar:
        draw_scale_bar(img, pixel_m)
    return img


def write_renders(mesh: trimesh.Trimesh, out_dir: Path, size_px: int = 384,
                  finish: Finish | None = None) -> dict[str, str]:
    """The stills a user sees (iso, front, side, top .png in out_dir) in the material's finish (MATTE when none is
    given) with a scale bar; returns view -> file name."""
    out_dir.mkdir(parents=True, exist_ok=True)
    files = {}
    for view in VIEWS:
        iio.imwrite(out_dir / f"{view}.png", render_view(mesh, view, size_px, finish or MATTE, scale_bar=True))
        files[view] = f"{view}.png"
    return files
