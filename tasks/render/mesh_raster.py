"""A deterministic CPU z-buffer rasteriser: triangle meshes and splatted discs over a static backdrop, composed by
one depth test per pixel.

A robot link, a Gaussian of the object and the table occlude each other correctly: each pixel shows the nearest of
the backdrop (its own depth map), the triangles covering its centre (depth from 1/z interpolated in screen space,
Gouraud colours interpolated perspective-correctly, back faces culled: meshes wound outward) and the discs covering it
(each a sphere-like bulge towards the camera). Triangles and discs are drawn by Warp CPU kernels
(tasks.render.mesh_raster_kernels); the backdrop is the caller's. The same inputs always give the same bytes.
Lengths in metres; the camera frame is ``tasks.render.camera.Camera.frame()``: rows right, down, forward; eye
[m]; focal length [px].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NEAR_M = 0.02  # triangles and discs nearer than this to the camera plane are dropped

# what won a pixel
BACKGROUND, TABLE, ROBOT, GRIPPER, OBJECT = 0, 1, 2, 3, 4

CamFrame = tuple[np.ndarray, np.ndarray, float]


@dataclass
class Discs:
    """Discs facing the camera: centres [m] (N, 3), world radii [m] (N,), colours in [0, 1] (N, 3), a label and the
    largest radius drawn [px]; each is a sphere-like bulge towards the camera, darker towards its rim."""

    centers_m: np.ndarray
    radius_m: np.ndarray
    rgb: np.ndarray
    label: int = OBJECT
    max_radius_px: int = 8
    rim_shade: float = 0.25


@dataclass
class Mesh:
    """Triangles in the world: vertices [m] (V, 3), faces (F, 3) wound outward, vertex colours in [0, 1], a label."""

    vertices_m: np.ndarray
    faces: np.ndarray
    vertex_rgb: np.ndarray
    label: int


def project(cam: CamFrame, width: int, height: int, points_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Screen coordinates (u, v) [px, pixel centres at i + 0.5] and camera depth z [m] of world points."""
    rot, eye, f = cam
    c = (np.asarray(points_m, np.float64) - eye) @ rot.T
    z = c[:, 2]
    zs = np.where(z > 1e-9, z, 1e-9)
    return f * c[:, 0] / zs + 0.5 * width, f * c[:, 1] / zs + 0.5 * height, z


def draw(cam: CamFrame, width: int, height: int, background_rgb: np.ndarray, background_depth: np.ndarray,
         background_label: np.ndarray, meshes: list[Mesh], discs: Discs | None = None,
         depth_out: np.ndarray | None = None, device: str = "cpu") -> tuple[np.ndarray, np.ndarray]:
    """The nearest of backdrop, triangles and discs at every pixel: RGB image (H, W, 3) uint8 and label map (H, W).
    Depth passes first (triangles, discs), then colour passes: a disc wins an exact tie with a triangle. depth_out
    (H, W) float32, when given, receives each pixel's camera depth [m] (for splats composited over the picture).
    device: where the kernels run (cpu: the same bytes every time; cuda: two triangles at exactly the same depth may
    take a pixel in either order)."""
    import warp as wp

    from tasks.render import mesh_raster_kernels as k  # lazy: Warp kernels (warp 1.3 s), only when rasterising

    dev = device
    h, w = background_depth.shape
    zbuf = np.ascontiguousarray(background_depth, np.float32).ravel().copy()
    rgb = np.ascontiguousarray(background_rgb, np.uint8).reshape(-1, 3).copy()
    label = np.ascontiguousarray(background_label, np.uint8).ravel().copy()
    # the kernels update these three in place (CPU arrays share the numpy memory; a GPU's are copied back below)
    zb: wp.array = wp.array(zbuf, dtype=float, device=dev, copy=False)
    out: list[wp.array] = [wp.array(rgb, dtype=wp.uint8, device=dev, copy=False),
                           wp.array(label, dtype=wp.uint8, device=dev, copy=False)]
    common: list[object]  # a pass's kernel arguments: arrays and scalars
    colour: list[object]
    passes = []
    if meshes:
        offsets = np.cumsum([0] + [len(m.vertices_m) for m in meshes])
        u, v, z = project(cam, width, height, np.concatenate([m.vertices_m for m in meshes]))
        inv_z = np.where(z > NEAR_M, 1.0 / np.maximum(z, NEAR_M), 1e30)
        faces = np.concatenate([np.asarray(m.faces, np.int32) + o for m, o in zip(meshes, offsets)])
        common = [*(wp.array(np.asarray(a, np.float32), dtype=float, device=dev) for a in (u, v, inv_z)),
                  wp.array(faces, dtype=int, device=dev), width, height, float(1.0 / NEAR_M), zb]
        colour = [wp.array(np.concatenate([np.asarray(m.vertex_rgb, np.float32) for m in meshes]), dtype=wp.vec3,
                           device=dev),
                  wp.array(np.concatenate([np.full(len(m.faces), m.label, np.uint8) for m in meshes]),
                           dtype=wp.uint8, device=dev), *out]
        passes.append((k.triangle_depth, k.triangle_color, len(faces), common, colour))
    if discs is not None and len(discs.centers_m):
        rot, eye, f = cam
        u, v, z = project(cam, width, height, discs.centers_m)
        r_px = np.clip(np.rint(f * np.asarray(discs.radius_m) / np.maximum(z, NEAR_M)), 1, discs.max_radius_px)
        keep = np.nonzero(z > NEAR_M)[0]
        common = [wp.array(np.floor(u[keep]).astype(np.int32), dtype=int, device=dev),
                  wp.array(np.floor(v[keep]).astype(np.int32), dtype=int, device=dev),
                  wp.array(z[keep].astype(np.float32), dtype=float, device=dev),
                  wp.array(np.asarray(discs.radius_m, np.float32)[keep], dtype=float, device=dev),
                  wp.array(r_px[keep].astype(np.int32), dtype=int, device=dev), width, height, zb]
        colour = [wp.array(np.asarray(discs.rgb, np.float32)[keep, :3], dtype=wp.vec3, device=dev),
                  float(discs.rim_shade), wp.uint8(discs.label), *out]
        passes.append((k.disc_depth, k.disc_color, len(keep), common, colour))
    for depth_kernel, _, n, common, _ in passes:
        if n:
            wp.launch(depth_kernel, dim=n, inputs=common, device=dev)
    for _, colour_kernel, n, common, colour in passes:
        if n:
            wp.launch(colour_kernel, dim=n, inputs=[*common, *colour], device=dev)
    wp.synchronize_device(dev)
    if wp.get_device(dev).is_cuda:
        zbuf, rgb, label = zb.numpy(), out[0].numpy(), out[1].numpy()
    if depth_out is not None:
        depth_out[...] = zbuf.reshape(h, w)
    return rgb.reshape(h, w, 3), label.reshape(h, w)
