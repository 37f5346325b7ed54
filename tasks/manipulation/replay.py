"""Replay a recorded attempt WITHOUT re-simulating: video frames of the whole robot (the URDF's visual meshes at the
recorded joint states, the 2F-85 / 2F-140 link by link), the table and the object (Gaussians driven by the recorded
particles x and F, drawn by the splatting renderer) with a close-up of the fingers, from t = 0 to the end of the
attempt (tasks.manipulation.video), as PNG frames, an MP4 (H.264,
imageio-ffmpeg) or GIF at 30 fps, 1280 x 720 by default; and a Rerun .rrd with the robot's links, the finger pads,
particles, Gaussians and the per-finger force curves.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from cache import cache_root
from contracts.asset_dir import attempt_path
from contracts.errors import InputError
from tasks.asset_dir import AssetDir
from tasks.manipulation.data import cached_attempt_folder, read_attempt, read_attempt_folder
from tasks.manipulation.scene import VIDEO_FPS, VIDEO_SIZE
from tasks.manipulation.video import PickPlaceVideo
from tasks.record import ProbeRecording
from tasks.record.trials import attempt_of_trial, recorded_trials, reported_trial, trial_of_attempt
from tasks.render.splats import deform_gaussians
from tasks.robot import PHASES
from tasks.robot.visual import (HAND_LINKS, gripper_boxes, gripper_spec, link_poses, panda_visual_meshes,
                                uses_urdf_hand)

ROBOT = "world/robot"
RRD_MAX_GAUSSIANS = 20000  # a recording keeps at most this many Gaussians per frame (a deterministic stride)
RRD_MESH_CELL_M = 0.006  # the robot's visual meshes in a recording, coarsened to this cell (a smaller file)


@dataclass
class ReplayResult:
    """What a replay wrote: frame files, their SHA-256 digests (of the raw pixels), video and recording paths, the
    video's rate [1/s], size [px] and duration [s]."""

    frames: list[Path] = field(default_factory=list)
    digests: list[str] = field(default_factory=list)
    video: Path | None = None
    recording: Path | None = None
    n_frames: int = 0
    fps: float = VIDEO_FPS
    size: tuple[int, int] = VIDEO_SIZE
    duration_s: float = 0.0
    trial: int | None = None  # the replayed trial's one number (tasks.record.trials), when manipulation.json has it


def frame_gaussians(arrays: dict[str, np.ndarray], i: int) -> tuple[np.ndarray, np.ndarray]:
    """Gaussian centres [m] and covariances [m^2] at recorded frame i, from the recorded particle x and F."""
    return deform_gaussians(arrays["gaussian_positions_m"], arrays["gaussian_covariances_m2"],
                            arrays["gaussian_particle_index"], arrays["gaussian_particle_weight"],
                            arrays["rest_particles_m"], arrays["particles_x_m"][i], arrays["particles_F"][i])


def render_frames(arrays: dict[str, np.ndarray], width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1],
                  attrs: dict | None = None, device: str = "cpu") -> list[np.ndarray]:
    """Every video frame of an attempt (deterministic on the CPU)."""
    return PickPlaceVideo(arrays, attrs, width, height, device=device).frames()


def video_writer(path: Path, fps: float = VIDEO_FPS):
    """An imageio writer for .mp4 (H.264, yuv420p) or .gif at fps (InputError for another suffix)."""
    import imageio.v2 as imageio

    if path.suffix.lower() == ".gif":
        return imageio.get_writer(path, mode="I", duration=1000.0 / fps, loop=0)
    if path.suffix.lower() == ".mp4":
        return imageio.get_writer(path, fps=fps, codec="libx264", macro_block_size=8, quality=7,
                                  ffmpeg_params=["-preset", "veryfast"])
    raise InputError(f"--video must end in .mp4 or .gif, got {path.name}")


def replay(asset_dir: Path, attempt: int | None = None, frames_dir: Path | None = None, video: Path | None = None,
           rrd: Path | None = None, width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1],
           trial: int | None = None, device: str = "cpu") -> ReplayResult:
    """Replay a trial of an asset: PNG frames into frames_dir, an .mp4/.gif video, an .rrd (each optional), the
    frames drawn on `device` (cpu or cuda).
    trial: the trial's one number (from 1, tasks.record.trials; default: the trial manipulation.json reports);
    attempt: its interaction folder index instead. Frames are rendered one at a time and streamed to the files (a
    long attempt never sits in memory)."""
    attempt, trial = _which(Path(asset_dir), attempt, trial)
    arrays, attrs = _read(Path(asset_dir), attempt, trial)
    if trial is not None:
        attrs = {**attrs, "trial": trial}
    out = draw_attempt(arrays, attrs, frames_dir, video, rrd, width, height, device)
    out.trial = trial
    return out


def draw_attempt(arrays: dict[str, np.ndarray], attrs: dict, frames_dir: Path | None = None,
                 video: Path | None = None, rrd: Path | None = None, width: int = VIDEO_SIZE[0],
                 height: int = VIDEO_SIZE[1], device: str = "cpu") -> ReplayResult:
    """replay's drawing of one attempt's arrays and attributes (as tasks.manipulation.data reads them): PNG frames, a
    video and a recording, each optional."""
    import imageio.v2 as imageio

    writer = None
    if video is not None:
        video = Path(video)
        if video.suffix.lower() not in (".mp4", ".gif"):  # before any rendering
            raise InputError(f"--video must end in .mp4 or .gif, got {video.name}")
        video.parent.mkdir(parents=True, exist_ok=True)
        tmp = video.with_name(f".{video.stem}.tmp{video.suffix}")
        writer = video_writer(tmp)
    if frames_dir is not None:
        Path(frames_dir).mkdir(parents=True, exist_ok=True)
    try:
        renderer = PickPlaceVideo(arrays, attrs, width, height, device=device)
        out = ReplayResult(n_frames=len(renderer), size=(width, height), duration_s=len(renderer) / VIDEO_FPS)
        for i in range(len(renderer)):
            im = renderer.frame(i)
            out.digests.append(hashlib.sha256(im.tobytes()).hexdigest())
            if frames_dir is not None:
                p = Path(frames_dir) / f"frame_{i:04d}.png"
                imageio.imwrite(p, im)
                out.frames.append(p)
            if writer is not None:
                writer.append_data(im)
    except BaseException:
        if writer is not None:
            writer.close()
            tmp.unlink(missing_ok=True)
        raise
    if writer is not None:
        writer.close()
        assert video is not None  # a writer is opened only for a video
        tmp.replace(video)
        out.video = video
    if rrd is not None:
        out.recording = write_rrd(arrays, attrs, Path(rrd))
    return out


def _read(asset_dir: Path, attempt: int | None, trial: int | None) -> tuple[dict[str, np.ndarray], dict]:
    """The trial's arrays and attributes: from the asset's interaction folder (every frame from the cache when the
    asset keeps them thinned: tasks.manipulation.keep, while the cache holds them), else (a trial a default asset
    leaves in the cache) from the cache entry its row names; InputError, one line, when neither holds them."""
    if attempt is None or (asset_dir / attempt_path(attempt)).is_dir():
        arrays, attrs = read_attempt(asset_dir, attempt)
        if int(attrs.get("frame_stride", 1)) > 1:
            key, folder = _cached_attempt(asset_dir, int(attrs.get("attempt", attempt or 0)))
            if folder is not None:
                return read_attempt_folder(folder)
        return arrays, attrs
    key, folder = _cached_attempt(asset_dir, attempt)
    if key is None:
        return read_attempt(asset_dir, attempt)  # (its error names the stored attempts)
    if folder is None:
        what = f"trial {trial}" if trial is not None else f"attempt {attempt}"
        raise InputError(f"{what}'s states are not in {asset_dir} and the cache {cache_root()} no longer holds them "
                         f"(key {key}); `deformsmith manipulate {asset_dir} --record all` simulates them again")
    return read_attempt_folder(folder)


def _cached_attempt(asset_dir: Path, attempt: int) -> tuple[str | None, Path | None]:
    """(the cache key manipulation.json names for an attempt's states, that entry's folder while the cache holds
    it); (None, None) when no row names a key."""
    adir = AssetDir(asset_dir)
    record = adir.manipulation() if adir.has("manipulation") else None
    row = next((r for r in record.attempts if r.attempt == attempt), None) if record is not None else None
    if row is None or not row.data_key:
        return None, None
    return row.data_key, cached_attempt_folder(row.data_key)


def _which(asset_dir: Path, attempt: int | None, trial: int | None) -> tuple[int | None, int | None]:
    """(interaction folder index, trial number) of the trial to replay: the one asked for, else the one
    manipulation.json reports, else the last stored folder (its trial number when manipulation.json names it)."""
    adir = AssetDir(asset_dir)
    record = adir.manipulation() if adir.has("manipulation") else None  # InputError when it is not a valid record
    if trial is not None:
        found = attempt_of_trial(record, trial) if record is not None else None
        if found is None:
            numbers = recorded_trials(record) if record is not None else []
            raise InputError(f"{asset_dir} has no recorded trial {trial}; recorded trials: {numbers}")
        return found, trial
    if record is None:
        return attempt, None
    if attempt is None:
        n = reported_trial(record)
        if n is not None and attempt_of_trial(record, n) is not None:
            return attempt_of_trial(record, n), n
    return attempt, trial_of_attempt(record, attempt) if attempt is not None else None


def _stride(n: int, cap: int | None) -> slice:
    """A deterministic subsample of n items to at most cap (every k-th)."""
    return slice(None, None, max(1, -(-n // cap)) if cap else 1)


def write_rrd(arrays: dict[str, np.ndarray], attrs: dict, path: Path, max_particles: int | None = None,
              max_gaussians: int | None = RRD_MAX_GAUSSIANS, gaussian_every: int = 1,
              max_object_frames: int | None = None) -> Path:
    """The attempt as a Rerun recording (written atomically: the file appears when complete).

    world/robot/<link>: the URDF's visual meshes (static) with their FK pose per frame, or world/robot/gripper: a
    box gripper; world/colliders/finger_<k>: the pad boxes; world/object/particles and world/object/gaussians (at most
    max_particles / max_gaussians, a deterministic stride; the Gaussians at every gaussian_every-th frame and the
    last; the object at most at max_object_frames evenly strided frames, the last included: a long trial's recording
    keeps its size, the robot moving at every frame); metrics/finger_<k>_force_n (|force| on each finger [N]),
    metrics/object_com_height_m and metrics/grip_opening_m at the control rate; harness/log: the labels. Timelines:
    ``frame`` (the recorded particle frames) and ``sim_time`` [s]; the approach before the simulation (the object at
    rest) is on ``sim_time`` only.
    """
    import rerun as rr
    from scipy.spatial.transform import Rotation

    spec = gripper_spec(attrs.get("plan"))
    urdf_hand = uses_urdf_hand(spec)
    meshes = {m.name: m for m in panda_visual_meshes(RRD_MESH_CELL_M) if urdf_hand or m.name not in HAND_LINKS}
    t_c = np.asarray(arrays.get("control_sim_t_s", arrays["control_t_s"]))  # simulated time of each interval
    k_frames = np.minimum(arrays["frame_control_index"], len(t_c) - 1)
    a_t = np.asarray(arrays.get("approach_t_s", np.zeros(0)))

    def track(name: str, recorded: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
        """The approach's values (when recorded) followed by the recorded frames' ones."""
        before = np.asarray(arrays.get(name, np.zeros((0, *shape)))).reshape(-1, *shape)
        return np.concatenate([before, recorded])

    q = track("approach_q_rad", arrays["command_q_rad"][k_frames], (7,))
    pads = track("approach_finger_position_m", arrays["finger_position_m"][k_frames], (2, 3))
    quats = track("approach_finger_quat_xyzw", arrays["finger_quat_xyzw"][k_frames], (2, 4))
    poses = link_poses(q, track("approach_opening_m", arrays["command_opening_m"][k_frames, 0], ()))
    half = arrays["finger_half_extents_m"]
    ps = _stride(arrays["particles_x_m"].shape[1], max_particles)
    gs = _stride(len(arrays["gaussian_positions_m"]), max_gaussians)
    colors = np.asarray(arrays["gaussian_colors"])[gs]

    def robot(rec: ProbeRecording, j: int) -> None:
        for name, (p, r) in poses[j].items():
            if name in meshes:
                rec.rec.log(f"{ROBOT}/{name}", rr.Transform3D(translation=p.astype(np.float32),
                                                               mat3x3=r.astype(np.float32)))
        if not urdf_hand:
            flange = poses[j].get("panda_link8")
            boxes = gripper_boxes(pads[j], half, flange[1][:, 2] if flange else np.array([0.0, 0.0, -1.0]), spec)
            rec.rec.log(f"{ROBOT}/gripper", rr.Boxes3D(
                centers=np.array([b[0] for b in boxes], np.float32),
                half_sizes=np.array([b[2] for b in boxes], np.float32),
                quaternions=[rr.Quaternion(xyzw=Rotation.from_matrix(b[1]).as_quat()) for b in boxes],
                colors=np.array([np.rint(255 * b[3]) for b in boxes], np.uint8), fill_mode="solid"))
        for f in range(2):
            rec.box_collider(f"finger_{f}", pads[j, f], half, quats[j, f])

    def obj(rec: ProbeRecording, centers: np.ndarray | None, cov: np.ndarray | None, particles: np.ndarray) -> None:
        rec.particles(particles[ps], radius_m=0.001)
        if centers is None or cov is None:
            return
        ev, vecs = np.linalg.eigh(cov[gs])
        vecs = vecs * np.where(np.linalg.det(vecs) < 0, -1.0, 1.0)[:, None, None]
        rec.gaussians(centers[gs], np.sqrt(np.clip(ev, 1e-14, None)), Rotation.from_matrix(vecs).as_quat(), colors)

    name = f"trial {attrs['trial']}" if attrs.get("trial") else f"attempt {attrs.get('attempt')}"
    with ProbeRecording(path, recording_id=f"L3-{name.replace(' ', '-')}") as rec:
        for name, m in meshes.items():
            rgba = np.rint(255 * np.append(m.rgb, 1.0)).astype(np.uint8)
            rec.rec.log(f"{ROBOT}/{name}", rr.Mesh3D(vertex_positions=m.vertices_m.astype(np.float32),
                                                     triangle_indices=m.faces.astype(np.uint32),
                                                     vertex_normals=m.normals.astype(np.float32), albedo_factor=rgba),
                        static=True)
        rec.rec.disable_timeline("frame")  # the approach: sim_time only
        for j, t in enumerate(a_t):
            rec.rec.set_time("sim_time", duration=float(t))
            robot(rec, j)
            if j == 0:
                obj(rec, np.asarray(arrays["gaussian_positions_m"]), np.asarray(arrays["gaussian_covariances_m2"]),
                    arrays["rest_particles_m"])
        frame_k = 0
        n_frames = len(arrays["frame_t_s"])
        every = max(1, -(-n_frames // max_object_frames)) if max_object_frames else 1
        for i, t in enumerate(arrays["frame_t_s"]):
            rec.set_time(i, float(t))
            robot(rec, len(a_t) + i)
            last = i == len(k_frames) - 1
            if i % every == 0 or last:
                shown = (i // every) % max(1, gaussian_every) == 0 or last
                centers: np.ndarray | None = None
                cov: np.ndarray | None = None
                if shown:
                    centers, cov = frame_gaussians(arrays, i)
                obj(rec, centers, cov, arrays["particles_x_m"][i])
            k_next = int(arrays["frame_control_index"][i + 1]) if i + 1 < len(k_frames) else len(t_c)
            for kk in range(frame_k, min(k_next, len(t_c))):  # curves at the control rate
                rec.set_sim_time(float(t_c[kk]))
                for f in range(2):
                    rec.scalar(f"finger_{f}_force_n", float(np.linalg.norm(arrays["finger_force_n"][kk, f])))
                rec.scalar("object_com_height_m", float(arrays["object_com_m"][kk, 2]))
                rec.scalar("grip_opening_m", float(arrays["command_opening_m"][kk, 0]))
            frame_k = max(frame_k, k_next)
        labels = attrs.get("labels", {})
        rec.log(f"L3 {name} ({attrs.get('role', '')}): " + ", ".join(
            f"{k}={v:.4g}" for k, v in sorted(labels.items()) if isinstance(v, (int, float))))
        rec.log("phases: " + ", ".join(PHASES))
    return path


def rrd_particle_frames(path: Path) -> list[np.ndarray]:
    """Particle positions [m] per frame read back from an .rrd (for checking a replay against the Zarr data)."""
    from rerun.chunk import RrdReader

    frames: dict[int, np.ndarray] = {}
    for chunk in RrdReader(str(path)).stream():
        if str(chunk.entity_path).lstrip("/") != "world/object/particles":
            continue
        table = chunk.to_record_batch() if hasattr(chunk, "to_record_batch") else None
        if table is None:
            raise InputError("this rerun version cannot read chunks back")
        cols = {name: table.column(i) for i, name in enumerate(table.schema.names)}
        frame_col = next((c for n, c in cols.items() if n.endswith("frame") or n == "frame"), None)
        if frame_col is None:  # the object at rest before the simulation (sim_time only)
            continue
        pos_col = next(c for n, c in cols.items() if "Points3D:positions" in n or n.endswith("positions"))
        for fr, pos in zip(frame_col.to_pylist(), pos_col.to_pylist()):
            if pos is not None:
                frames[int(fr)] = np.asarray(pos, dtype=np.float32).reshape(-1, 3)
    return [frames[k] for k in sorted(frames)]
