"""3D Gaussian splatting (Kerbl et al. 2023) of Gaussians given by centres and covariances, over a studio or a flat
background: RGB uint8 images, the same Warp kernels on the CPU and on CUDA.

    from tasks.render.camera import Camera
    from tasks.render.splats import render_gaussians

    img = render_gaussians(Camera(eye, target, 40.0, 1280, 720), means_m, covariances_m2, colors_rgb, opacities)

The algorithm (tasks.render.splat_kernels): EWA projection of each covariance with 0.3 px² low-pass, 16 x 16 tiles
(or a caller's edge: the same picture), a stable radix sort of (tile, depth) keys, and per pixel front-to-back alpha
compositing with transmittance, alpha clamped to 0.99, nothing beyond 3 sigma or below 1/255, early termination at
T < 1e-4. ``scene="studio"``: a neutral backdrop, a table at z = 0 that hides what lies below it, a soft shadow under
the object (tasks.render.studio); ``"none"``: a flat light grey. On the CPU the same inputs give the same bytes on any
machine (the tiles are split into bands drawn by up to 8 threads, one per core; no pixel's sum depends on the split),
and only the tiles a Gaussian or its shadow reaches are drawn, the rest showing the background unchanged
(tasks.render.splat_tiles). Gaussians deformed by particles: deform_gaussians (covariances F Σ Fᵀ; the binding to
particles is tasks.geometry.gaussians's; a video of many states: tasks.render.binding).
"""

from __future__ import annotations

import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from contracts.errors import InputError
from tasks.render.binding import Binding
from tasks.render.camera import Camera
from tasks.render.sh import COEFFS_OF_DEGREE, view_colors
from tasks.render.splat_tiles import EMPTY_SCENES, busy_tiles, shadow_tiles
from tasks.render.studio import (FLAT_RGB, HORIZON_RGB, SPOT_FALLOFF, TABLE_RGB, TOP_RGB, ShadowMap, no_shadow,
                                 shadow_map)

SCENES = ("studio", "none")
NEAR_M = 0.01  # Gaussians nearer to the camera plane than this are dropped
# threads that draw bands of tiles on the CPU (a Warp CPU launch runs on one core); the image does not depend on them
CPU_BANDS = min(os.cpu_count() or 1, 8)


class _Bands:
    """The CPU's band threads, started once per process (a forked child starts its own)."""

    pool: ThreadPoolExecutor | None = None
    lock = threading.Lock()

    @classmethod
    def executor(cls) -> ThreadPoolExecutor:
        with cls.lock:
            if cls.pool is None:
                cls.pool = ThreadPoolExecutor(CPU_BANDS, thread_name_prefix="splat-band")
            return cls.pool

    @classmethod
    def forget(cls) -> None:  # (in a forked child: the parent's threads are not there)
        cls.pool, cls.lock = None, threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_Bands.forget)


def deform_gaussians(
    rest_positions_m: np.ndarray, rest_covariances_m2: np.ndarray, particle_index: np.ndarray,
    particle_weight: np.ndarray, rest_particles_m: np.ndarray, particles_m: np.ndarray, deformation_gradients: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Deformed Gaussian centres x_g = sum_j w_j (x_j + F_j (X_g - X_j)) and covariances F_g S F_g^T, F_g = sum_j w_j F_j
    (one state; a video of many: tasks.render.binding.Binding, which sets the binding up once)."""
    state = Binding.of(rest_positions_m, rest_covariances_m2, particle_index, particle_weight,
                       rest_particles_m).deform(particles_m, deformation_gradients)
    return state.centres_m, state.covariances_m2


def render_gaussians(cam: Camera, means_m: np.ndarray, covariances_m2: np.ndarray, colors_rgb: np.ndarray,
                     opacities: np.ndarray, *, sh_coeffs: np.ndarray | None = None, scene: str = "studio",
                     device: str = "cpu", background: tuple[np.ndarray, np.ndarray] | None = None,
                     tile_px: int | None = None) -> np.ndarray:
    """RGB uint8 image (cam.height, cam.width, 3). background: an image (H, W, 3) uint8 and its camera depth (H, W)
    [m] drawn by another renderer from the same camera (a robot's triangles, a room): the Gaussians are composited
    over it, each pixel's stopping at its depth (what lies in front hides them); scene is then not drawn. tile_px:
    the tiles' edge (default 16; the picture is the same, only the work differs: smaller tiles give each pixel a
    shorter list where many small Gaussians crowd a few tiles, and cost more binning elsewhere)."""
    means, covs, colors, opac = _checked(means_m, covariances_m2, colors_rgb, opacities, sh_coeffs, scene, device)
    rot, eye, focal = cam.frame()
    if sh_coeffs is not None and len(means):
        colors = view_colors(colors, np.asarray(sh_coeffs, np.float64), means, eye)
    if background is not None:
        image = _background(cam, background)
        return _rasterise(cam, rot, eye, focal, means, covs, np.clip(colors, 0.0, 1.0), opac, "image", no_shadow(),
                          device, image, _bytes_of(background[0]), tile_px=tile_px)
    shadow = shadow_map(means, covs, opac) if scene == "studio" and len(means) else no_shadow()
    return _rasterise(cam, rot, eye, focal, means, covs, np.clip(colors, 0.0, 1.0), opac, scene, shadow, device,
                      tile_px=tile_px)


def _background(cam: Camera, background: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The background's colours (H * W, 3) float32 in 0..1 and depths (H * W,) float32, checked against the camera."""
    rgb, depth = np.asarray(background[0]), np.asarray(background[1])
    if rgb.shape != (cam.height, cam.width, 3) or depth.shape != (cam.height, cam.width):
        raise InputError(f"render_gaussians: background must be ({cam.height}, {cam.width}, 3) and "
                         f"({cam.height}, {cam.width}), got {rgb.shape} and {depth.shape}")
    colours = (rgb.reshape(-1, 3).astype(np.float32) / np.float32(255.0)) if rgb.dtype == np.uint8 \
        else np.clip(rgb.reshape(-1, 3), 0.0, 1.0).astype(np.float32)
    return colours, np.nan_to_num(depth.reshape(-1).astype(np.float32), nan=1e30, posinf=1e30)


def _bytes_of(rgb: np.ndarray) -> np.ndarray | None:
    """An 8-bit background's pixels flat (H * W * 3,): what the kernel writes where no Gaussian is; None for a
    background in floats (the kernel's rounding decides those pixels)."""
    rgb = np.asarray(rgb)
    return np.ascontiguousarray(rgb).reshape(-1) if rgb.dtype == np.uint8 else None


def _checked(means_m: np.ndarray, covariances_m2: np.ndarray, colors_rgb: np.ndarray, opacities: np.ndarray,
             sh_coeffs: np.ndarray | None, scene: str, device: str
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The inputs as float64 arrays of matching shapes, or an InputError naming what is off."""
    means = np.asarray(means_m, np.float64)
    n = len(means)
    covs = np.asarray(covariances_m2, np.float64)
    colors = np.asarray(colors_rgb, np.float64)
    opac = np.asarray(opacities, np.float64)
    if means.shape != (n, 3) or covs.shape != (n, 3, 3) or colors.shape != (n, 3) or opac.shape != (n,):
        raise InputError(f"render_gaussians: expected means (N, 3), covariances (N, 3, 3), colours (N, 3), "
                         f"opacities (N,); got {means.shape}, {covs.shape}, {colors.shape}, {opac.shape}")
    if sh_coeffs is not None:
        shape = np.shape(sh_coeffs)
        if len(shape) != 3 or shape[0] != n or shape[1] not in COEFFS_OF_DEGREE or shape[2] != 3:
            raise InputError(f"render_gaussians: sh_coeffs must be (N, 3|8|15, 3) for SH degree 1..3, got {shape}")
    if scene not in SCENES:
        raise InputError(f"render_gaussians: scene must be one of {', '.join(SCENES)}, got '{scene}'")
    if not (device == "cpu" or device.startswith("cuda")):
        raise InputError(f"render_gaussians: device must be cpu or cuda, got '{device}'")
    if not (np.all(np.isfinite(means)) and np.all(np.isfinite(covs)) and np.all(np.isfinite(opac))):
        raise InputError("render_gaussians: non-finite centres, covariances or opacities")
    return means, covs, colors, np.clip(opac, 0.0, 1.0)


def _rasterise(cam: Camera, rot: np.ndarray, eye: np.ndarray, focal: float, means: np.ndarray, covs: np.ndarray,
               colors: np.ndarray, opac: np.ndarray, scene: str, shadow: ShadowMap, device: str,
               image: tuple[np.ndarray, np.ndarray] | None = None, image_bytes: np.ndarray | None = None,
               every_tile: bool = False, tile_px: int | None = None) -> np.ndarray:
    """Project, bin, sort and composite on `device` over the scene (or, scene "image", over the given colours and
    depths per pixel, image_bytes their 8-bit pixels when they are 8-bit); the image as a numpy array. On the CPU,
    unless every_tile, only the tiles a Gaussian or the shadow reaches are drawn over the background's pixels."""
    import warp as wp

    from tasks.render import splat_kernels as k  # lazy: Warp kernels (warp 1.3 s), only when rasterising

    w, h = int(cam.width), int(cam.height)
    tile = tile_px or k.TILE_EDGE_PX
    tiles_x, tiles_y = -(-w // tile), -(-h // tile)
    n_tiles = tiles_x * tiles_y
    ty, tx = np.divmod(np.arange(n_tiles, dtype=np.int32), np.int32(tiles_x))
    tile_origin: wp.array = wp.array(np.stack([tx, ty], axis=1) * np.int32(tile), dtype=wp.vec2i, device=device)
    n = max(len(means), 1)  # zero Gaussians: one dummy slot, never touched

    def arr(a: np.ndarray, dtype: object) -> wp.array:
        return wp.array(np.ascontiguousarray(a, np.float32), dtype=dtype, device=device)

    if not len(means):
        means, covs, opac, colors = np.zeros((1, 3)), np.zeros((1, 3, 3)), np.zeros(1), np.zeros((1, 3))
    g_means, g_covs = arr(means, wp.vec3), arr(covs, wp.mat33)
    g_opac, g_color = arr(opac, float), arr(colors, wp.vec3)
    xy = wp.zeros(n, dtype=wp.vec2, device=device)
    conic_o = wp.zeros(n, dtype=wp.vec4, device=device)
    depth = wp.zeros(n, dtype=float, device=device)
    rect = wp.zeros(n, dtype=wp.vec4i, device=device)
    touched = wp.zeros(n, dtype=int, device=device)
    w_rot, w_eye = wp.mat33(*rot.astype(np.float32).ravel()), wp.vec3(*eye.astype(np.float32))
    wp.launch(k.preprocess, dim=n, device=device,
              inputs=[g_means, g_covs, g_opac, w_rot, w_eye, focal, w, h, tile, tiles_x, tiles_y, NEAR_M],
              outputs=[xy, conic_o, depth, rect, touched])
    ends = wp.empty(n, dtype=int, device=device)
    wp.utils.array_scan(touched, ends, inclusive=True)
    total = int(ends[n - 1:n].numpy()[0])
    keys = wp.empty(max(2 * total, 2), dtype=wp.int64, device=device)
    values = wp.empty(max(2 * total, 2), dtype=int, device=device)
    start = wp.zeros(n_tiles, dtype=int, device=device)
    end = wp.zeros(n_tiles, dtype=int, device=device)
    m = max(total, 1)
    s_xy = wp.zeros(m, dtype=wp.vec2, device=device)
    s_conic_o = wp.zeros(m, dtype=wp.vec4, device=device)
    s_color = wp.zeros(m, dtype=wp.vec3, device=device)
    s_depth = wp.zeros(m, dtype=float, device=device)
    if total:
        starts = wp.empty(n, dtype=int, device=device)
        wp.utils.array_scan(touched, starts, inclusive=False)
        wp.launch(k.duplicate, dim=n, device=device,
                  inputs=[touched, starts, rect, xy, conic_o, depth, tile, tiles_x, n_tiles], outputs=[keys, values])
        wp.utils.radix_sort_pairs(keys, values, total, end_bit=32 + max(1, math.ceil(math.log2(n_tiles + 1))))
        wp.launch(k.tile_ranges, dim=total, device=device, inputs=[keys, total, n_tiles], outputs=[start, end])
        wp.launch(k.gather, dim=total, device=device, inputs=[values, xy, conic_o, g_color, depth],
                  outputs=[s_xy, s_conic_o, s_color, s_depth])
    listed = np.arange(n_tiles, dtype=np.int32)
    base = None if every_tile or device != "cpu" else _base(cam, scene, image_bytes)
    if base is not None:  # what the other tiles show: the background, untouched by the kernel
        busy = busy_tiles(start.numpy(), end.numpy())
        if scene == "studio":
            busy |= shadow_tiles(shadow, rot, eye, focal, w, h, tile, tiles_x, tiles_y)
        listed = np.flatnonzero(busy).astype(np.int32)
    out = wp.array(base.copy(), dtype=wp.uint8, device=device) if base is not None \
        else wp.empty(w * h * 3, dtype=wp.uint8, device=device)
    g_tiles: wp.array = wp.array(listed if len(listed) else np.zeros(1, np.int32), dtype=int, device=device)
    dark = np.ascontiguousarray(shadow.darkening, np.float32)
    target = np.asarray(cam.target, np.float32)
    dist = float(np.linalg.norm(np.asarray(cam.target) - eye))
    common = [start, end, s_xy, s_conic_o, s_color, s_depth, w, h, tile, tile_origin, g_tiles]
    mode = {"none": 0, "studio": 1, "image": 2}[scene]
    bg_rgb, bg_depth = image if image is not None else (np.zeros((1, 3), np.float32), np.zeros(1, np.float32))
    scene_args = [w_rot, w_eye, focal, mode, wp.vec3(*FLAT_RGB), wp.vec3(*TABLE_RGB),
                  wp.vec3(*HORIZON_RGB), wp.vec3(*TOP_RGB), wp.vec2(target[0], target[1]), 0.9 * dist, SPOT_FALLOFF,
                  3.0 * dist,
                  wp.array(dark.ravel(), dtype=float, device=device), wp.vec2(*shadow.origin_m), shadow.cell_m,
                  dark.shape[1], dark.shape[0], wp.array(bg_rgb, dtype=wp.vec3, device=device),
                  wp.array(bg_depth, dtype=float, device=device), out]

    def band(first: int, tiles: int) -> None:
        wp.launch(k.render_pixels, dim=tiles * tile * tile, device=device, inputs=[*common, first, *scene_args])

    n_listed = len(listed)
    threads = max(1, min(CPU_BANDS, n_listed)) if device == "cpu" else 1
    if threads == 1:
        if n_listed:
            band(0, n_listed)
    else:  # 4 bands a thread, taken in turn as threads come free: the object's tiles cost more than the backdrop's
        bands = min(4 * threads, n_listed)
        cuts = [n_listed * b // bands for b in range(bands + 1)]
        for f in [_Bands.executor().submit(band, a, b - a) for a, b in zip(cuts[:-1], cuts[1:])]:
            f.result()
    return out.numpy().reshape(h, w, 3)


def _base(cam: Camera, scene: str, image_bytes: np.ndarray | None) -> np.ndarray | None:
    """The pixels (H * W * 3,) uint8 of the frame without its Gaussians (and their shadow) on the CPU: an 8-bit
    background's own, or the empty studio or flat scene's (drawn once per camera); None when there are none."""
    if scene == "image":
        return image_bytes
    rot, eye, focal = cam.frame()

    def empty() -> np.ndarray:
        nothing = np.zeros((0, 3))
        return _rasterise(cam, rot, eye, focal, nothing, np.zeros((0, 3, 3)), nothing, np.zeros(0), scene,
                          no_shadow(), "cpu", every_tile=True)

    return EMPTY_SCENES.get(("cpu", cam, scene), empty)
