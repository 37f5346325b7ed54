"""The paper's drop protocol on film: two named views (the stills' front and side) at 30 fps, 1280 x 720, rendered
from recorded particle states with the Gaussians following the particles' deformation (their normals too: the discs
are lit, tasks.render.shading), encoded as H.264 MP4.

The clip is the motion, not 5 s of a body at rest (clip_states): the body held still for HOLD_BEFORE_S, the fall,
the impact and the settle in SLOW_MOTION x slow motion (states between the recorded ones linearly interpolated, the
recording being 30 per second), then HOLD_AFTER_S of the rest at real speed; a caption gives the simulated time and
says when the picture is slowed. The card's drop frames (CARD_TIMES_S) come from the recorded states themselves.

The view names are the stills' (tasks.render.views.VIEWS): "front" looks from +x with +y to the right, "side" from
-y with +x to the right, each a little above the table. One fixed camera per view frames the whole motion (the drop
height, the object and the table under it), so the fall and the contact are visible. Deterministic on the CPU.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from tasks.render.camera import Camera
from tasks.render.captions import caption
from tasks.render.discs import render
from tasks.render.binding import Binding, blended_gradients
from tasks.render.shading import lit_colors
from tasks.render.splats import render_gaussians
from tasks.render.views import view_axes as still_axes

VIDEO_WIDTH_PX, VIDEO_HEIGHT_PX = 1280, 720
VIEW_NAMES = ("front", "side")  # the stills of these names (renders/front.png, renders/side.png) show the same side
ELEVATION_DEG = 12.0  # low enough to see the gap under the object before it lands, high enough to see the table
FOV_DEG = 30.0  # vertical field of view
FILL = 0.8  # the motion's box fills at most this fraction of the frame's width and height
CARD_TIMES_S = (0.0, 0.3, 1.0, 5.0)  # the drop frames the asset card shows
STILL_PX = 0.25  # a frame whose Gaussians moved less than this [px] repeats the last drawn one
STILL_COV = 1e-3  # ... and whose covariances changed by less than this fraction of the largest
CRF = 20  # H.264 constant rate factor (lower: better, larger); a 5 s 720p drop video is well under 1 MB
STILL_SHRINK = 2  # the card's drop frames are stored at half the video's size (640 x 360)
SLOW_MOTION = 3  # the fall, the impact and the settle are shown this many times slower than they happened
HOLD_BEFORE_S = 0.3  # the body at its release height before it falls [s of video]
HOLD_AFTER_S = 1.0  # the body at rest after it settled [s, real speed]
SETTLE_MOTION = 0.002  # a state is settled when no particle moves more than this fraction of the body's size by the next


class GaussianRenderer(Protocol):
    """tasks.render.splats.render_gaussians's signature: an RGB frame (H, W, 3) uint8 of the Gaussians."""

    def __call__(self, cam: Camera, means_m: np.ndarray, covariances_m2: np.ndarray, colors_rgb: np.ndarray,
                 opacities: np.ndarray, *, sh_coeffs: np.ndarray | None = None, scene: str = "studio",
                 device: str = "cpu") -> np.ndarray: ...


class KeptPictures:
    """A renderer that keeps what it draws while `keeping` and, asked later to draw the very same Gaussians (equal
    arrays, the same camera and options), hands the kept picture back instead of drawing it again: drop_files draws
    the card's drop frames first, and the video's frames of the same recorded states reuse them."""

    def __init__(self, draw: GaussianRenderer) -> None:
        self.draw = draw
        self.keeping = True
        self.kept: list[tuple[Camera, tuple[np.ndarray, ...], tuple[Any, ...], np.ndarray]] = []
        self.reused = 0

    def __call__(self, cam: Camera, means_m: np.ndarray, covariances_m2: np.ndarray, colors_rgb: np.ndarray,
                 opacities: np.ndarray, *, sh_coeffs: np.ndarray | None = None, scene: str = "studio",
                 device: str = "cpu") -> np.ndarray:
        inputs = (means_m, covariances_m2, colors_rgb, opacities)
        options = (scene, device)
        if sh_coeffs is None:
            for c, arrays, opts, picture in self.kept:
                if c == cam and opts == options and all(np.array_equal(a, b) for a, b in zip(arrays, inputs)):
                    self.reused += 1
                    return picture
        picture = self.draw(cam, means_m, covariances_m2, colors_rgb, opacities, sh_coeffs=sh_coeffs, scene=scene,
                            device=device)
        if self.keeping and sh_coeffs is None:
            self.kept.append((cam, tuple(np.array(a) for a in inputs), options, picture))
        return picture


def _disc_renderer(cam: Camera, means_m: np.ndarray, covariances_m2: np.ndarray, colors_rgb: np.ndarray,
                   opacities: np.ndarray, *, sh_coeffs: np.ndarray | None = None, scene: str = "studio",
                   device: str = "cpu") -> np.ndarray:
    """The disc rasteriser behind the splatting renderer's signature: a cheap renderer for tests of the video plumbing."""
    return render(cam, means_m, covariances_m2, colors_rgb)


def gaussian_renderer() -> tuple[GaussianRenderer, list[Path]]:
    """The Gaussian splatting renderer (tasks.render.splats), with the source files whose bytes decide its pictures
    (the render cache key is made of them)."""
    root = Path(__file__).resolve().parent.parent
    sources = [p for p in (root / "render").glob("*.py") if not p.name.startswith(("card", "bench"))]
    return render_gaussians, sources


def view_axes(view: str) -> tuple[np.ndarray, np.ndarray]:
    """The still's (screen-right, towards-viewer) axes of a named view (a KeyError names an unknown view)."""
    right, _, toward = still_axes(view)
    return right, toward


def protocol_camera(points_m: np.ndarray, view: str, width: int, height: int) -> Camera:
    """A fixed camera for a named view that frames the points (every particle of every frame) and the table under
    them: looking at the box's centre from the view's side, ELEVATION_DEG above the horizon, as close as the box
    allows with FILL of the frame (exact for the box's corners under perspective)."""
    pts = np.asarray(points_m, np.float64).reshape(-1, 3)
    pts = pts[np.isfinite(pts).all(axis=1)]
    pts = pts if len(pts) else np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    lo[2] = min(lo[2], 0.0)  # the table (z = 0) is in the box: the contact is in frame
    centre = 0.5 * (lo + hi)
    _, toward = view_axes(view)
    e = np.radians(ELEVATION_DEG)
    back = np.cos(e) * toward + np.sin(e) * np.array([0.0, 0.0, 1.0])  # from the target towards the eye
    cam0 = Camera(tuple(centre + back), tuple(centre), FOV_DEG, width, height)
    rot, _, _ = cam0.frame()
    tan_v = np.tan(np.radians(FOV_DEG) / 2.0) * FILL
    tan_h = tan_v * width / height
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]) - centre
    c = corners @ rot.T  # (right, down, forward) offsets from the target
    # a corner at depth D + c_f fits when |c_r| <= tan_h (D + c_f) and |c_d| <= tan_v (D + c_f)
    distance = float(max(np.max(np.abs(c[:, 0]) / tan_h - c[:, 2]), np.max(np.abs(c[:, 1]) / tan_v - c[:, 2])))
    distance = max(distance, 1e-3 + float(np.max(-c[:, 2])))
    return Camera(tuple(centre + distance * back), tuple(centre), FOV_DEG, width, height)


def frame_count(n_states: int, fps: float, duration_s: float) -> int:
    """Frames of a video of duration_s at fps from n_states recorded states (state k at t = k / fps)."""
    return max(1, min(n_states, int(round(duration_s * fps))))


def iter_states(renderer: GaussianRenderer, cam: Camera, gaussians: dict[str, np.ndarray],
                rest_covariances_m2: np.ndarray, rest_particles_m: np.ndarray, x_frames: Iterable[np.ndarray],
                F_frames: Iterable[np.ndarray], device: str = "cpu") -> Iterator[np.ndarray]:
    """RGB frames of the Gaussians deformed by each recorded state (positions x, deformation gradients F), one at a
    time (a 5 s 720p video is 400 MB of frames). A state whose Gaussians lie within STILL_PX of the last drawn
    frame's (centres, and sizes to STILL_COV) repeats that frame: a body at rest is drawn once, not 100 times."""
    colors = np.clip(np.asarray(gaussians["colors"], np.float64)[:, :3], 0.0, 1.0)
    n = len(colors)
    opacities = np.asarray(gaussians.get("opacities", np.full(n, 0.95)), np.float64).reshape(n)
    normals = gaussians.get("normals")
    rot, eye, focal = cam.frame()
    binding = Binding.of(gaussians["positions_m"], rest_covariances_m2, gaussians["particle_index"],
                         gaussians["particle_weight"], rest_particles_m)  # set up once for every state
    drawn: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    for x, F in zip(x_frames, F_frames):
        state = binding.deform(x, F)
        centres, cov = state.centres_m, state.covariances_m2
        if drawn is not None and _same_picture(drawn[0], drawn[1], centres, cov, rot[2], eye, focal):
            yield drawn[2]
            continue
        ok = np.isfinite(centres).all(axis=1) & np.isfinite(cov).all(axis=(1, 2))  # an exploded state: what is left
        centres, cov = np.where(ok[:, None], centres, 0.0), np.where(ok[:, None, None], cov, 0.0)
        shown = colors
        if normals is not None:  # lit by the deformed normals (tasks.render.shading), a non-finite F taken as 0
            F_g = state.gradients if np.isfinite(F).all() else \
                blended_gradients(gaussians["particle_index"], gaussians["particle_weight"], np.nan_to_num(F))
            shown = lit_colors(colors, binding.normals(normals, F_g), cam)
        image = np.ascontiguousarray(renderer(cam, centres[ok], cov[ok], shown[ok], opacities[ok], scene="studio",
                                              device=device))
        drawn = (centres, cov, image)
        yield image


def _same_picture(centres0: np.ndarray, cov0: np.ndarray, centres: np.ndarray, cov: np.ndarray, forward: np.ndarray,
                  eye: np.ndarray, focal_px: float) -> bool:
    """True when no Gaussian centre moved STILL_PX on screen (bounded by its motion at the nearest depth) and no
    covariance changed by STILL_COV of the largest one."""
    depth = float(((centres - eye) @ forward).min())
    if not np.isfinite(depth) or depth <= 0.0:
        return False
    moved_px = float(np.sqrt(((centres - centres0) ** 2).sum(axis=1).max())) * focal_px / depth
    scale = float(np.abs(cov0).max())
    return moved_px < STILL_PX and float(np.abs(cov - cov0).max()) <= STILL_COV * scale


def render_protocol_frames(gaussians: dict[str, np.ndarray], rest_covariances_m2: np.ndarray,
                           rest_particles_m: np.ndarray, x_frames: np.ndarray, F_frames: np.ndarray, view: str,
                           width: int = VIDEO_WIDTH_PX, height: int = VIDEO_HEIGHT_PX,
                           renderer: GaussianRenderer | None = None) -> list[np.ndarray]:
    """RGB frames (H, W, 3) uint8 of the deformed Gaussians from one named view, one per recorded state (the camera
    frames the whole motion)."""
    cam = protocol_camera(np.asarray(x_frames), view, width, height)
    return list(iter_states(renderer or gaussian_renderer()[0], cam, gaussians, rest_covariances_m2, rest_particles_m,
                            x_frames, F_frames))


def write_mp4(frames: Iterable[np.ndarray], path: Path, fps: float, crf: int = CRF) -> Path:
    """Encode frames as H.264 MP4 (imageio-ffmpeg; yuv420p, fast start, no time stamps in the file): the same frames
    give the same bytes."""
    import imageio.v2 as imageio

    path.parent.mkdir(parents=True, exist_ok=True)
    params = ["-crf", str(crf), "-preset", "faster", "-threads", "2", "-movflags", "+faststart",
              "-map_metadata", "-1", "-fflags", "+bitexact", "-flags:v", "+bitexact"]
    with imageio.get_writer(path, fps=fps, codec="libx264", macro_block_size=8, quality=None,
                            ffmpeg_params=params, pixelformat="yuv420p") as writer:
        for frame in frames:
            writer.append_data(frame)  # type: ignore[attr-defined]  # typed as imageio's base reader/writer
    return path


def write_png(frame: np.ndarray, path: Path, shrink: int = 1) -> Path:
    """One frame as PNG, its size divided by shrink (each pixel the mean of a shrink x shrink block)."""
    import imageio.v3 as iio

    if shrink > 1:
        h, w = (frame.shape[0] // shrink) * shrink, (frame.shape[1] // shrink) * shrink
        total = np.zeros((h // shrink, w // shrink, *frame.shape[2:]), np.uint32)  # (integer sums: exact)
        for dy in range(shrink):
            for dx in range(shrink):
                total += frame[dy:h:shrink, dx:w:shrink]
        frame = np.rint(total / float(shrink * shrink)).astype(np.uint8)
    path.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(path, frame)
    return path


def card_still_name(view: str, t_s: float) -> str:
    """File name (under renders/) of the drop frame at t_s seconds from a view: drop_front_t0.3s.png."""
    return f"drop_{view}_t{t_s:.1f}s.png"


def clip_states(x_frames: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """The recorded state (a fractional index: between two states, interpolated) each video frame shows, and whether
    that frame is in slow motion: state 0 for HOLD_BEFORE_S, then every 1 / SLOW_MOTION of a state up to the settled
    one (the first after which no particle moves SETTLE_MOTION of the body's size from one state to the next, slowed),
    then HOLD_AFTER_S of states at real speed."""
    x = np.asarray(x_frames, np.float64)
    n = len(x)
    if n < 2:
        return np.zeros(max(n, 1)), np.zeros(max(n, 1), bool)
    first = x[0][np.isfinite(x[0]).all(axis=1)]
    size = float(np.ptp(first, axis=0).max()) if len(first) else 1.0
    step = np.nan_to_num(np.abs(np.diff(x, axis=0)), nan=np.inf).max(axis=(1, 2))  # (n - 1,)
    moving = np.flatnonzero(step > SETTLE_MOTION * max(size, 1e-6))
    settled = int(min(n - 1, moving[-1] + 1)) if len(moving) else 0
    before = np.zeros(int(round(HOLD_BEFORE_S * fps)))
    motion = np.arange(settled * SLOW_MOTION + 1) / SLOW_MOTION
    after = np.arange(settled + 1, min(n - 1, settled + int(round(HOLD_AFTER_S * fps))) + 1, dtype=np.float64)
    slowed = np.concatenate([np.zeros(len(before), bool), np.full(len(motion), SLOW_MOTION > 1),
                             np.zeros(len(after), bool)])
    return np.concatenate([before, motion, after]), slowed


def interpolated(frames: np.ndarray, k: float) -> np.ndarray:
    """A recorded array's state at a fractional index (linear between the two nearest states)."""
    i = int(np.floor(k))
    if k == i or i + 1 >= len(frames):
        return np.asarray(frames[min(i, len(frames) - 1)])
    a = k - i
    return ((1.0 - a) * np.asarray(frames[i], np.float64) + a * np.asarray(frames[i + 1], np.float64)).astype(np.float32)


def drop_caption(image: np.ndarray, t_s: float, slowed: bool) -> np.ndarray:
    """The simulated time in the top-left corner, and the slow motion while it lasts."""
    return caption(image, [f"t = {t_s:4.2f} s" + (f"   slow motion {SLOW_MOTION}x" if slowed else "")])


def drop_files(gaussians: dict[str, np.ndarray], rest_covariances_m2: np.ndarray, rest_particles_m: np.ndarray,
               x_frames: np.ndarray, F_frames: np.ndarray, folder: Path, fps: float, duration_s: float,
               width: int = VIDEO_WIDTH_PX, height: int = VIDEO_HEIGHT_PX,
               renderer: GaussianRenderer | None = None,
               progress: Callable[[str], Any] | None = None, device: str = "cpu") -> dict[str, Path]:
    """drop_<view>.mp4 for each named view (the clip of clip_states, at fps; state k was recorded at t = k / fps, the
    first duration_s of them are used) and the card's drop frames drop_<view>_t<t>s.png at CARD_TIMES_S (the nearest
    recorded state), written into folder; name -> path. device: where the Gaussians are drawn (cpu: the same bytes
    every time; cuda: within one colour level of them)."""
    n = min(len(x_frames), frame_count(len(x_frames), fps, duration_s) + 1)
    times, slowed = clip_states(x_frames[:n], fps)
    stills = {t: min(len(x_frames) - 1, int(round(t * fps))) for t in CARD_TIMES_S}  # time -> state
    out: dict[str, Path] = {}
    args = (gaussians, rest_covariances_m2, rest_particles_m)
    for view in VIEW_NAMES:
        cam = protocol_camera(np.asarray(x_frames), view, width, height)
        draw = KeptPictures(renderer or gaussian_renderer()[0])  # the stills first: the video reuses their pictures
        states = sorted(set(stills.values()))
        drawn = dict(zip(states, iter_states(draw, cam, *args, x_frames[states], F_frames[states], device)))
        draw.keeping = False
        xs = (interpolated(x_frames, k) for k in times)
        Fs = (interpolated(F_frames, k) for k in times)
        frames = iter_states(draw, cam, *args, xs, Fs, device)
        shown = (drop_caption(f, k / fps, bool(slow)) for k, slow, f in zip(times, slowed, frames))
        out[f"drop_{view}.mp4"] = write_mp4(shown, folder / f"drop_{view}.mp4", fps)
        for t, k in stills.items():
            shrink = STILL_SHRINK if min(width, height) >= 360 else 1
            out[card_still_name(view, t)] = write_png(drawn[k], folder / card_still_name(view, t), shrink)
        if progress:
            progress(view)
    return out
