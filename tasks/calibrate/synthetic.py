"""Synthetic drop videos with a known answer: a side view (orthographic, x right, z up) of discs drawn anti-aliased
on a textured scene with a floor, with camera noise and JPEG compression. The tracker's unit tests draw one disc
along a known path; the round trip draws an MPM rollout's particles (each a disc of half the particle spacing)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import cv2
import numpy as np

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.mpm import SceneSpec
from tasks.probes.rollout import DeformableBody, Rollout, dx_of

SHIFT = 4  # cv2's fixed-point sub-pixel bits (1/16 px)


@dataclass(frozen=True)
class Camera:
    """A static side camera: frame size, pixels per metre, where the world's z = floor_z_m and x = 0 land."""

    width_px: int = 160
    height_px: int = 240
    px_per_m: float = 1000.0
    floor_z_m: float = 0.0
    floor_y_px: float = 220.0
    centre_x_px: float = 80.0

    def project(self, x_m: np.ndarray, z_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World (x, z) to image (x, y) [px]."""
        return (self.centre_x_px + self.px_per_m * np.asarray(x_m),
                self.floor_y_px - self.px_per_m * (np.asarray(z_m) - self.floor_z_m))


def scene(cam: Camera, seed: int = 0) -> np.ndarray:
    """A textured background: a wall with a soft gradient and blotches, a darker floor below the floor line."""
    rng = np.random.default_rng(seed)
    h, w = cam.height_px, cam.width_px
    y = np.linspace(0.0, 1.0, h)[:, None, None]
    img = np.broadcast_to(np.array([150.0, 160.0, 175.0]) - 40.0 * y, (h, w, 3)).copy()
    blotch = cv2.GaussianBlur(rng.normal(0.0, 40.0, (h, w)).astype(np.float32), (0, 0), 6.0)
    img += blotch[..., None]
    img[int(round(cam.floor_y_px)):] = np.array([95.0, 80.0, 60.0]) + 0.5 * blotch[int(round(cam.floor_y_px)):, :, None]
    return np.clip(img, 0, 255)


def draw(bg: np.ndarray, xy_px: np.ndarray, radius_px: float, colour: tuple[int, int, int] = (200, 40, 30)
         ) -> np.ndarray:
    """The background with filled anti-aliased discs of `radius_px` at the image points `xy_px` (N, 2)."""
    cover = np.zeros(bg.shape[:2], np.uint8)
    scale = 1 << SHIFT
    r = max(1, int(round(radius_px * scale)))
    for x, y in np.rint(np.asarray(xy_px) * scale).astype(int).tolist():
        cv2.circle(cover, (x, y), r, 255, -1, cv2.LINE_AA, SHIFT)
    out = np.array(bg, dtype=np.result_type(bg.dtype, np.float32))  # (the disc blended where it covers: the same
    rows, cols = np.nonzero(cover.any(axis=1))[0], np.nonzero(cover.any(axis=0))[0]  # values as over the whole
    if rows.size == 0:  # frame, a small disc on a long clip's frames ~10x faster)
        return out
    win = np.s_[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
    a = cover[win].astype(np.float32)[..., None] / 255.0
    out[win] = out[win] * (1.0 - a) + np.asarray(colour, np.float32) * a
    return out


def degrade(frames: Iterable[np.ndarray], noise_grey: float, jpeg_quality: int | None, seed: int = 0) -> np.ndarray:
    """Camera noise (Gaussian, sigma in grey levels) and a JPEG round trip of every frame (None: none; a video
    writer compresses them): uint8 RGB frames. `frames` may be drawn one at a time (a generator): a long clip's float
    frames are never all held (640 float64 frames are 370 MB, and allocating them took seconds)."""
    rng = np.random.default_rng(seed)
    out = []
    for f in frames:
        g = np.clip(f + rng.normal(0.0, noise_grey, f.shape), 0, 255).astype(np.uint8)
        if jpeg_quality is None:
            out.append(g)
            continue
        ok, buf = cv2.imencode(".jpg", cv2.cvtColor(g, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, jpeg_quality])
        out.append(cv2.cvtColor(cv2.imdecode(buf, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB))
    return np.stack(out)


def disc_video(cam: Camera, centres_xz_m: np.ndarray, radius_m: float, noise_grey: float = 3.0,
               jpeg_quality: int | None = 80, seed: int = 0) -> np.ndarray:
    """One disc of `radius_m` per frame at the given world centres (F, 2)."""
    bg = scene(cam, seed)
    xs, ys = cam.project(centres_xz_m[:, 0], centres_xz_m[:, 1])
    frames = (draw(bg, np.array([[x, y]]), radius_m * cam.px_per_m) for x, y in zip(xs, ys))
    return degrade(frames, noise_grey, jpeg_quality, seed)


def particle_video(cam: Camera, positions_m: np.ndarray, spacing_m: float, noise_grey: float = 3.0,
                   jpeg_quality: int | None = 80, seed: int = 0) -> np.ndarray:
    """Each frame's particles (F, N, 3) seen from the side (y is depth), each a disc of half the spacing."""
    bg = scene(cam, seed)

    def frames() -> Iterator[np.ndarray]:
        for x in positions_m:
            px, py = cam.project(x[:, 0], x[:, 2])
            yield draw(bg, np.stack([px, py], axis=1), 0.5 * spacing_m * cam.px_per_m)

    return degrade(frames(), noise_grey, jpeg_quality, seed)


def bouncing_centres(drop_m: float, radius_m: float, restitution: float, fps: float, hold_s: float = 0.05,
                     rest_s: float = 0.3) -> np.ndarray:
    """A rigid disc's centre (F, 2) [m] held at `drop_m` (bottom above the floor), released, bouncing with the given
    restitution until its bounces are shorter than a frame, then at rest."""
    g = 9.81
    t_hold = int(round(hold_s * fps))
    pts = [(0.0, drop_m + radius_m)] * t_hold
    t, z, v = 0.0, drop_m, 0.0
    dt = 1.0 / fps
    while True:
        t += dt
        z_new = z + v * dt - 0.5 * g * dt * dt
        v_new = v - g * dt
        if z_new <= 0.0:  # the impact inside this frame: back along the flight to touchdown and out again
            disc = v * v + 2.0 * g * z
            v_td = -np.sqrt(disc)
            tau = (v - v_td) / g  # time from the frame start to touchdown
            v_out = -restitution * v_td
            rem = dt - tau
            if v_out * 2.0 / g < dt:
                break
            z_new = v_out * rem - 0.5 * g * rem * rem
            v_new = v_out - g * rem
        z, v = z_new, v_new
        pts.append((0.0, z + radius_m))
    pts += [(0.0, radius_m)] * int(round(rest_s * fps))
    return np.array(pts)




def mpm_drop_positions(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                       drop_height_m: float, fps: float, duration_s: float, sim: SimConfig,
                       hold_s: float = 0.03) -> np.ndarray:
    """The particles (F, N, 3) of an MPM drop sampled at `fps`: held still for `hold_s`, then released with the bottom
    `drop_height_m` above the engine's contact layer (a free fall of drop_height_m before first contact, as L2's drop
    probe releases it), for `duration_s` after the release."""
    body = DeformableBody.from_physical(positions_m, volumes_m3, physical)
    x0 = body.positions_m
    layer = max(0.0, 1.5 * dx_of(body, sim) - (x0[:, 2].min() - sim.ground_height_m))
    start = x0 + np.array([0.0, 0.0, drop_height_m + layer])
    scene = SceneSpec(start, body.volumes_m3, body.density_kg_per_m3, material, ground_friction=body.ground_friction)
    frames = [start] * int(round(hold_s * fps))
    run = Rollout([scene], sim, None, "video", int(duration_s * fps))
    while run.ok and run.time_s < duration_s - 0.5 / fps:
        _, st = run.advance(1.0 / fps)
        frames.append(st[0]["x"].astype(np.float64))
    run.close(["synthetic drop video"])
    return np.stack(frames)


__all__ = ["Camera", "bouncing_centres", "degrade", "disc_video", "draw", "mpm_drop_positions", "particle_video",
           "scene"]
