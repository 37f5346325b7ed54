"""A pick-and-place attempt as video frames: the robot (tasks.robot.visual), the table on a floor before a
backdrop, the deforming object (its Gaussians driven by the recorded particles) and a caption, rasterised on the CPU
with one depth test (tasks.render.mesh_raster) from a fixed camera that sees the grasp, the lift and the place.

`attempt_timeline` resamples an attempt at the video rate from t = 0: the recorded approach (robot only, object at
rest), then the simulated frames. Deterministic: the same arrays give the same bytes. Lengths in metres, times in s.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from tasks.render import mesh_raster as raster
from tasks.render.camera import Camera
from tasks.render.splats import deform_gaussians
from tasks.robot import PHASES
from tasks.robot.visual import gripper_spec, link_poses, robot_meshes

VIDEO_FPS = 30.0
VIDEO_SIZE = (1280, 720)
TABLE_TOP = np.array([0.80, 0.70, 0.55])     # wood
TABLE_EDGE = np.array([0.55, 0.46, 0.34])
FLOOR = np.array([0.52, 0.56, 0.66])  # slate blue-grey: never the arm's grey
WALL_LOW, WALL_HIGH = np.array([0.72, 0.78, 0.86]), np.array([0.86, 0.90, 0.96])  # bluish: never the arm's grey
TARGET_RGB = np.array([0.20, 0.55, 0.30])
TABLE_LO_M = np.array([-0.80, -0.60, -0.04])  # the table slab: top at z = 0 (the MPM ground), the robot stands on it
TABLE_HI_M = np.array([0.50, 0.60, 0.0])
FLOOR_Z_M = -0.75
SHADOW_RGB = 0.72 * TABLE_TOP
SHADOW_Z_M = 0.0005                            # the shadow's height above the table top [m]
GRID_M = 0.05                                  # faint lines on the table top, for scale and motion
SPLAT_SIGMAS = 1.6             # a Gaussian's disc radius in standard deviations
MAX_SPLAT_PX = 10              # its largest radius on a 720-line frame [px]
VIEW_ELEVATION_DEG = 15.0     # camera above the horizontal
VIEW_TURN_DEG = 35.0          # ... and turned from square-on to the fingers, so the hand hides less of the object
HAND_ABOVE_PADS_M = 0.15      # the hand and the wrist above the pads, kept in view
MIN_VIEW_RADIUS_M = 0.2       # the smallest scene the camera frames (a small object still shows the hand and wrist)


@dataclass(frozen=True)
class Backdrop:
    """The static part of every frame from a fixed camera: RGB, camera depth [m] and labels per pixel."""

    rgb: np.ndarray
    depth: np.ndarray
    label: np.ndarray


def _rays(cam: Camera) -> tuple[np.ndarray, np.ndarray]:
    """Ray directions with unit camera depth (so a hit's ray parameter is its camera depth [m]) through every pixel
    centre, flat (H * W, 3) in the world frame (read-only: shared by the cameras of one orientation, as the close-up's
    that follows the fingers), and the eye [m]."""
    rot, eye, f = cam.frame()
    return _ray_directions(rot.tobytes(), f, cam.width, cam.height), eye


@lru_cache(maxsize=4)
def _ray_directions(rot_bytes: bytes, f: float, width: int, height: int) -> np.ndarray:
    """_rays' directions for a camera rotation (its float64 bytes), focal length [px] and size."""
    rot = np.frombuffer(rot_bytes, np.float64).reshape(3, 3)
    xs = ((np.arange(width) + 0.5 - width / 2) / f).astype(np.float32)
    ys = ((np.arange(height) + 0.5 - height / 2) / f).astype(np.float32)
    d = (xs[None, :, None] * rot[0].astype(np.float32) + ys[:, None, None] * rot[1].astype(np.float32)
         + rot[2].astype(np.float32))
    d = d.reshape(-1, 3)
    d.flags.writeable = False
    return d


def _plane_hit(origin: float, direction: np.ndarray) -> np.ndarray:
    """Ray parameter where origin + t * direction = 0 along one axis (inf where the ray runs away or parallel)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -origin / direction
    return np.where(np.isfinite(t) & (t > 0), t, np.inf).astype(np.float32)


def backdrop(cam: Camera, target_xy_m: tuple[float, float] | None = None, target_radius_m: float = 0.03) -> Backdrop:
    """Table slab (top z = 0, with a faint 5 cm grid and the place target's ring), floor and a wall behind, by ray
    casting every pixel; depth is the camera z of the hit."""
    d, eye = _rays(cam)
    h, w = cam.height, cam.width
    rot = cam.frame()[0]
    # wall: a vertical plane behind the scene, facing the camera; shaded from the floor up
    back = np.array([rot[2][0], rot[2][1], 0.0])
    back /= max(float(np.linalg.norm(back)), 1e-9)
    offset = float((np.asarray(cam.target) + 1.4 * back - eye) @ back)
    depth = _plane_hit(-offset, (d @ back.astype(np.float32)))
    rgb = np.empty((h * w, 3), np.float32)  # (the wall's colour is put last, where neither floor nor table is)
    label = np.zeros(h * w, np.uint8)
    # floor
    t_floor = _plane_hit(eye[2] - FLOOR_Z_M, d[:, 2])
    on_floor = t_floor < depth
    rgb[on_floor] = FLOOR * np.clip(1.05 - 0.12 * t_floor[on_floor], 0.75, 1.0)[:, None]
    depth[on_floor] = t_floor[on_floor]
    # table slab (ray-box, slab method); the face hit gives the colour
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (TABLE_LO_M - eye).astype(np.float32) / d, (TABLE_HI_M - eye).astype(np.float32) / d
    tn, tf = np.fmin(t0, t1), np.fmax(t0, t1)
    # (the slabs' entry and exit, column by column: the same values as max / min along the rows, a few times faster)
    t_in = np.maximum(np.maximum(tn[:, 0], tn[:, 1]), tn[:, 2])
    t_out = np.minimum(np.minimum(tf[:, 0], tf[:, 1]), tf[:, 2])
    on = np.nonzero((t_in <= t_out) & (t_in > 0) & (t_in < depth))[0]
    face = tn[on].argmax(axis=1)
    p = eye + t_in[on, None] * d[on]
    off_grid = np.abs(p[:, :2] / GRID_M - np.rint(p[:, :2] / GRID_M))
    g = np.minimum(off_grid[:, 0], off_grid[:, 1]) < 0.02
    col = np.where(g[:, None], 0.9 * TABLE_TOP, TABLE_TOP)
    if target_xy_m is not None:
        ring = np.abs(np.hypot(p[:, 0] - target_xy_m[0], p[:, 1] - target_xy_m[1]) - target_radius_m) < 0.0025
        col[ring] = TARGET_RGB
    col[face == 0] = 0.85 * TABLE_EDGE
    col[face == 1] = TABLE_EDGE
    rgb[on] = col
    depth[on] = t_in[on]
    label[on] = raster.TABLE
    wall = ~on_floor
    wall[on] = False
    s = np.clip((eye[2] + depth[wall] * d[wall, 2] - FLOOR_Z_M) / 2.0, 0.0, 1.0)[:, None]
    rgb[wall] = ((1 - s) * WALL_LOW + s * WALL_HIGH).astype(np.float32)
    return Backdrop(np.clip(rgb * 255.0 + 0.5, 0, 255).astype(np.uint8).reshape(h, w, 3),
                    depth.astype(np.float32).reshape(h, w), label.reshape(h, w))


def view_direction(closing_axis_world: np.ndarray | None) -> np.ndarray:
    """Unit vector from the scene towards the camera: horizontally across the closing axis (both fingers and the
    object between them in view), turned by VIEW_TURN_DEG away from the robot's base (at -x: the arm is seen from its
    side, the base at the back), raised by VIEW_ELEVATION_DEG."""
    c = np.zeros(3) if closing_axis_world is None else np.asarray(closing_axis_world, np.float64).copy()
    c[2] = 0.0
    if np.linalg.norm(c) < 1e-6:
        c = np.array([0.0, 1.0, 0.0])
    h = np.cross(c / np.linalg.norm(c), [0.0, 0.0, 1.0])
    a = np.radians(VIEW_TURN_DEG)
    turns = [np.array([[np.cos(s * a), -np.sin(s * a), 0.0], [np.sin(s * a), np.cos(s * a), 0.0], [0.0, 0.0, 1.0]])
             @ (sign * h) for sign in (1.0, -1.0) for s in (1.0, -1.0)]
    h = max(turns, key=lambda d: (round(d[0], 9), -d[1]))  # furthest from the base; then in front (-y)
    e = np.radians(VIEW_ELEVATION_DEG)
    return np.cos(e) * h + np.array([0.0, 0.0, np.sin(e)])


def attempt_camera(arrays: dict[str, np.ndarray], width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1],
                   target_xy_m: tuple[float, float] | None = None) -> Camera:
    """A fixed camera that frames the object's path (start, lift, place target) and the hand above it."""
    rest = arrays["rest_particles_m"].astype(np.float64)
    com = arrays["object_com_m"]
    parts = [rest, com[np.isfinite(com).all(axis=1)], arrays["finger_position_m"].reshape(-1, 3)]
    if target_xy_m is not None:
        parts.append(np.array([[target_xy_m[0], target_xy_m[1], 0.0]]))
    pts = np.concatenate([p for p in parts if len(p)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    lo[2] = min(lo[2], 0.0)
    hi[2] += HAND_ABOVE_PADS_M
    centre = 0.5 * (lo + hi)
    radius = max(MIN_VIEW_RADIUS_M, 0.5 * float(np.linalg.norm(hi - lo)))
    fov = 40.0
    distance = radius / np.sin(np.radians(0.5 * fov))
    direction = view_direction(arrays.get("closing_axis_world"))
    return Camera(tuple(centre + distance * direction), tuple(centre), fov, width, height)


@dataclass(frozen=True)
class TimelineFrame:
    """What one video frame shows: time [s], the recorded particle frame (-1: the object at rest, before the
    simulation), the robot state (arm [rad], opening [m], pads [m]) and the phase index (tasks.robot.PHASES)."""

    t_s: float
    particle_frame: int
    q_rad: np.ndarray
    opening_m: float
    pad_position_m: np.ndarray
    control_index: int


def attempt_timeline(arrays: dict[str, np.ndarray], fps: float = VIDEO_FPS) -> list[TimelineFrame]:
    """The attempt resampled at fps from t = 0 (or the first recorded frame when no approach was recorded) to its
    last recorded frame, in simulated time: each video frame shows the latest recorded particle frame at or before its
    time with the robot commanded at that frame's control interval."""
    frame_t = np.asarray(arrays["frame_t_s"], np.float64)  # simulated time (a skipped closure rest is not in it)
    k_frame = np.minimum(np.asarray(arrays["frame_control_index"]), len(arrays["control_t_s"]) - 1)
    a_t = np.asarray(arrays.get("approach_t_s", np.zeros(0)), np.float64)
    start = float(a_t[0]) if len(a_t) else float(frame_t[0])
    n = int(np.ceil((frame_t[-1] - start) * fps - 1e-6)) + 1  # the last video frame shows the last recorded one
    out = []
    for i in range(n):
        t = start + i / fps
        if len(a_t) and t < frame_t[0] - 1e-9:
            j = int(np.clip(np.searchsorted(a_t, t + 1e-9, side="right") - 1, 0, len(a_t) - 1))
            out.append(TimelineFrame(t, -1, arrays["approach_q_rad"][j], float(arrays["approach_opening_m"][j]),
                                     arrays["approach_finger_position_m"][j], -1))
            continue
        fi = int(np.clip(np.searchsorted(frame_t, t + 1e-9, side="right") - 1, 0, len(frame_t) - 1))
        k = int(k_frame[fi])
        out.append(TimelineFrame(t, fi, arrays["command_q_rad"][k], float(arrays["command_opening_m"][k, 0]),
                                 arrays["finger_position_m"][k], k))
    return out


def object_gaussians(arrays: dict[str, np.ndarray], particle_frame: int) -> tuple[np.ndarray, np.ndarray]:
    """Gaussian centres [m] and covariances [m^2] of the object at a recorded frame (-1: at rest)."""
    if particle_frame < 0:
        return (np.asarray(arrays["gaussian_positions_m"], np.float64),
                np.asarray(arrays["gaussian_covariances_m2"], np.float64))
    return deform_gaussians(arrays["gaussian_positions_m"], arrays["gaussian_covariances_m2"],
                            arrays["gaussian_particle_index"], arrays["gaussian_particle_weight"],
                            arrays["rest_particles_m"], arrays["particles_x_m"][particle_frame],
                            arrays["particles_F"][particle_frame])


def shadow(centers_m: np.ndarray) -> raster.Mesh | None:
    """The object's shadow under a light straight above: the convex hull of its footprint on the table, a flat dark
    patch just above the table top (a lifted object is seen apart from its shadow); None for a degenerate footprint."""
    from scipy.spatial import ConvexHull, QhullError

    xy = np.asarray(centers_m, np.float64)[:, :2]
    try:
        ring = xy[ConvexHull(xy).vertices]  # counter-clockwise seen from above
    except (QhullError, ValueError):
        return None
    c = ring.mean(axis=0)
    v = np.vstack([[*c, SHADOW_Z_M], np.column_stack([ring, np.full(len(ring), SHADOW_Z_M)])])
    f = np.array([[0, k, k % len(ring) + 1] for k in range(1, len(ring) + 1)])
    return raster.Mesh(v, f, np.tile(SHADOW_RGB, (len(v), 1)), raster.TABLE)


def caption(image: np.ndarray, lines: list[str]) -> np.ndarray:
    """Text in the top-left corner (OpenCV Hershey font, dark on the light backdrop)."""
    import cv2

    out = np.ascontiguousarray(image)
    scale = image.shape[0] / 720.0
    for i, text in enumerate(lines):
        org = (int(18 * scale), int((34 + 30 * i) * scale))
        cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, 0.75 * scale, (30, 30, 35), max(1, int(2 * scale)),
                    cv2.LINE_AA)
    return out


class AttemptRenderer:
    """Renders the frames of one recorded attempt from a fixed camera (the backdrop is computed once)."""

    def __init__(self, arrays: dict[str, np.ndarray], attrs: dict[str, Any] | None = None,
                 width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1], fps: float = VIDEO_FPS) -> None:
        self.arrays, self.attrs = arrays, attrs or {}
        plan = self.attrs.get("plan") or {}
        target = plan.get("target_xy_m")
        self.cam = attempt_camera(arrays, width, height, tuple(target) if target else None)
        self.cam_frame = self.cam.frame()
        self.backdrop = backdrop(self.cam, tuple(target) if target else None)
        self.spec = gripper_spec(plan)
        self.timeline = attempt_timeline(arrays, fps)
        self.poses = link_poses(np.array([f.q_rad for f in self.timeline]),
                                np.array([f.opening_m for f in self.timeline]))  # per video frame, every link
        colors = np.asarray(arrays["gaussian_colors"], np.float64)[:, :3]
        self.colors = colors / 255.0 if colors.max() > 1.0 else colors

    def __len__(self) -> int:
        return len(self.timeline)

    def frame(self, i: int) -> np.ndarray:
        """RGB image (H, W, 3) uint8 of video frame i, captioned."""
        return self.frame_with_labels(i)[0]

    def frame_with_labels(self, i: int, with_caption: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """RGB image (H, W, 3) uint8 of video frame i and what each pixel shows (raster's labels)."""
        fr, a = self.timeline[i], self.arrays
        w, h = self.cam.width, self.cam.height
        view = self.cam_frame[0][2]
        meshes = [raster.Mesh(v, f, rgb, raster.GRIPPER if is_gripper else raster.ROBOT)
                  for v, f, rgb, is_gripper in robot_meshes(self.poses[i], fr.pad_position_m,
                                                            a["finger_half_extents_m"], self.spec, view)]
        centers, cov = object_gaussians(a, fr.particle_frame)
        sigma = np.sqrt(np.clip(np.trace(cov, axis1=1, axis2=2) / 3.0, 0.0, None))
        discs = raster.Discs(centers, SPLAT_SIGMAS * sigma, self.colors, raster.OBJECT,
                             max(2, int(round(MAX_SPLAT_PX * h / 720))))
        meshes += [m for m in (shadow(centers),) if m is not None]
        rgb, labels = raster.draw(self.cam_frame, w, h, self.backdrop.rgb, self.backdrop.depth, self.backdrop.label,
                                  meshes, discs)
        if with_caption:
            lines = [f"t = {fr.t_s:5.2f} s   {self._phase(fr, PHASES)}"]
            if fr.control_index >= 0:
                fk = np.linalg.norm(a["finger_force_n"][fr.control_index], axis=-1)
                if np.isfinite(fk).all():
                    lines.append(f"finger forces {fk[0]:5.2f} N  {fk[1]:5.2f} N")
            rgb = caption(rgb, lines)
        return rgb, labels

    def _phase(self, fr: TimelineFrame, phases: tuple[str, ...]) -> str:
        """The phase name at a timeline frame (approach before the simulation)."""
        if fr.control_index < 0:
            return "approach"
        return phases[int(self.arrays["phase"][fr.control_index])]

    def frames(self) -> list[np.ndarray]:
        """Every video frame, in order."""
        return [self.frame(i) for i in range(len(self))]
