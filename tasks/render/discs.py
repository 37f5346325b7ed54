"""A small deterministic CPU disc rasteriser (the drop videos' plumbing tests stand it in for the splatting renderer):
Gaussians (and any extra points) as depth-sorted discs over a table, numpy only.

Each Gaussian becomes a disc whose pixel radius is the projected 1.5-sigma size (clamped to ``MAX_RADIUS_PX``); each
pixel takes the colour of the nearest disc covering it (stable sort on depth, ties by index): the same inputs always give
the same bytes. Lengths in metres, the camera looks from ``eye`` at ``target``. The pick-and-place video (robot, table,
object) is tasks.manipulation.scene's.
"""

from __future__ import annotations

import numpy as np

from tasks.render.camera import Camera

__all__ = ["Camera", "render"]

MAX_RADIUS_PX = 4
BACKGROUND = np.array([236, 232, 224], dtype=np.uint8)
TABLE = np.array([196, 178, 150], dtype=np.uint8)
PAD = np.array([70, 70, 78], dtype=np.float64) / 255.0


def _background(cam: Camera) -> np.ndarray:
    """Sky above the horizon, the table (z = 0) below it, shaded by distance."""
    rot, eye, f = cam.frame()
    ys, xs = np.mgrid[0:cam.height, 0:cam.width]
    rays = ((xs - cam.width / 2 + 0.5) / f)[..., None] * rot[0] + ((ys - cam.height / 2 + 0.5) / f)[..., None] * rot[1]
    rays = rays + rot[2]
    t = np.where(rays[..., 2] < -1e-9, -eye[2] / np.minimum(rays[..., 2], -1e-9), np.inf)
    img = np.empty((cam.height, cam.width, 3), dtype=np.uint8)
    img[:] = BACKGROUND
    hit = np.isfinite(t)
    shade = np.clip(1.15 - 0.6 * t / (4.0 * np.linalg.norm(eye)), 0.6, 1.0)
    img[hit] = (TABLE[None, :] * shade[hit][:, None]).astype(np.uint8)
    return img


def render(cam: Camera, centers_m: np.ndarray, covariances_m2: np.ndarray, colors: np.ndarray,
           extra_points_m: np.ndarray | None = None, extra_color: np.ndarray = PAD) -> np.ndarray:
    """RGB image (H, W, 3) uint8 of the splats (+ extra points, e.g. the pads); deterministic."""
    rot, eye, f = cam.frame()
    pts = np.asarray(centers_m, dtype=np.float64)
    col = np.asarray(colors, dtype=np.float64)[:, :3]
    sigma = np.sqrt(np.clip(np.trace(np.asarray(covariances_m2, dtype=np.float64), axis1=1, axis2=2) / 3.0, 0, None))
    if extra_points_m is not None and len(extra_points_m):
        pts = np.concatenate([pts, extra_points_m])
        col = np.concatenate([col, np.tile(extra_color, (len(extra_points_m), 1))])
        sigma = np.concatenate([sigma, np.full(len(extra_points_m), 0.0012)])
    cam_pts = (pts - eye) @ rot.T
    z = cam_pts[:, 2]
    ok = z > 1e-3
    u = f * cam_pts[:, 0] / np.where(ok, z, 1.0) + cam.width / 2
    v = f * cam_pts[:, 1] / np.where(ok, z, 1.0) + cam.height / 2
    r = np.clip(np.rint(1.5 * f * sigma / np.where(ok, z, 1.0)), 1, MAX_RADIUS_PX).astype(np.int64)
    img = _background(cam)
    keep = np.nonzero(ok)[0]
    order = keep[np.argsort(z[keep], kind="stable")]
    R = MAX_RADIUS_PX
    oy, ox = np.mgrid[-R:R + 1, -R:R + 1]
    od = np.sqrt(ox**2 + oy**2).ravel()
    ox, oy = ox.ravel(), oy.ravel()
    ui, vi = np.rint(u[order]).astype(np.int64), np.rint(v[order]).astype(np.int64)
    px = ui[:, None] + ox[None, :]
    py = vi[:, None] + oy[None, :]
    inside = (od[None, :] <= r[order][:, None]) & (px >= 0) & (px < cam.width) & (py >= 0) & (py < cam.height)
    rank = np.broadcast_to(np.arange(len(order))[:, None], px.shape)[inside]
    flat = (py * cam.width + px)[inside]
    first = np.unique(flat, return_index=True)  # the nearest splat (smallest rank) wins each pixel
    pix, idx = first[0], rank[first[1]]
    # light: a little darker towards the disc rim for depth cues
    rim = (od[None, :].repeat(len(order), 0)[inside][first[1]] / np.maximum(r[order][idx], 1))
    shade = 1.0 - 0.25 * np.clip(rim, 0, 1)
    rgb = np.clip(col[order][idx] * shade[:, None] * 255.0, 0, 255).astype(np.uint8)
    out = img.reshape(-1, 3)
    out[pix] = rgb
    return out.reshape(cam.height, cam.width, 3)
