"""Replay a recorded attempt WITHOUT re-simulating: Gaussians driven by the recorded particles (x, F), PNG frames,
an MP4 (imageio-ffmpeg) or GIF, and a Rerun .rrd with the Panda's links (pybullet_data meshes posed by FK from the
recorded joint states), the finger pads, particles, Gaussians and the per-finger force curves.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from contracts.errors import InputError
from tasks.geometry.gaussians import deform_gaussians
from tasks.manipulation.data import read_attempt
from tasks.manipulation.render import Camera, box_samples, camera_for, render

ROBOT = "world/robot"


@dataclass
class ReplayResult:
    """What a replay wrote: frame files, their SHA-256 digests (of the raw pixels), video and recording paths."""

    frames: list[Path] = field(default_factory=list)
    digests: list[str] = field(default_factory=list)
    video: Path | None = None
    recording: Path | None = None
    n_frames: int = 0


def frame_gaussians(arrays: dict[str, np.ndarray], i: int) -> tuple[np.ndarray, np.ndarray]:
    """Gaussian centres [m] and covariances [m^2] at recorded frame i, from the recorded particle x and F."""
    return deform_gaussians(arrays["gaussian_positions_m"], arrays["gaussian_covariances_m2"],
                            arrays["gaussian_particle_index"], arrays["gaussian_particle_weight"],
                            arrays["rest_particles_m"], arrays["particles_x_m"][i], arrays["particles_F"][i])


def attempt_camera(arrays: dict[str, np.ndarray], width: int = 320, height: int = 240) -> Camera:
    """A fixed camera for the whole attempt, framing the object's path."""
    com = arrays["object_com_m"]
    pts = np.concatenate([com[np.isfinite(com).all(axis=1)], arrays["rest_particles_m"].astype(np.float64)])
    return camera_for(pts, width, height)


def render_frame(arrays: dict[str, np.ndarray], i: int, cam: Camera) -> np.ndarray:
    """RGB image of recorded frame i: the deformed Gaussians and both finger pads."""
    centers, cov = frame_gaussians(arrays, i)
    k = int(min(arrays["frame_control_index"][i], len(arrays["control_t_s"]) - 1))
    pads = np.concatenate([box_samples(arrays["finger_position_m"][k, f], arrays["finger_quat_xyzw"][k, f],
                                       arrays["finger_half_extents_m"]) for f in range(2)])
    return render(cam, centers, cov, arrays["gaussian_colors"], pads)


def render_frames(arrays: dict[str, np.ndarray], width: int = 320, height: int = 240) -> list[np.ndarray]:
    """Every recorded frame rendered (deterministic)."""
    cam = attempt_camera(arrays, width, height)
    return [render_frame(arrays, i, cam) for i in range(len(arrays["frame_t_s"]))]


def replay(asset_dir: Path, attempt: int | None = None, frames_dir: Path | None = None, video: Path | None = None,
           rrd: Path | None = None, width: int = 320, height: int = 240) -> ReplayResult:
    """Replay an attempt of an asset: PNG frames into frames_dir, an .mp4/.gif video, an .rrd (each optional)."""
    import imageio.v2 as imageio

    arrays, attrs = read_attempt(Path(asset_dir), attempt)
    images = render_frames(arrays, width, height)
    out = ReplayResult(n_frames=len(images), digests=[hashlib.sha256(im.tobytes()).hexdigest() for im in images])
    if frames_dir is not None:
        frames_dir = Path(frames_dir)
        frames_dir.mkdir(parents=True, exist_ok=True)
        for i, im in enumerate(images):
            p = frames_dir / f"frame_{i:04d}.png"
            imageio.imwrite(p, im)
            out.frames.append(p)
    if video is not None:
        video = Path(video)
        video.parent.mkdir(parents=True, exist_ok=True)
        fps = float(1.0 / np.median(np.diff(arrays["frame_t_s"]))) if len(images) > 1 else 30.0
        if video.suffix.lower() == ".gif":
            imageio.mimsave(video, images, duration=1.0 / fps, loop=0)
        elif video.suffix.lower() == ".mp4":
            with imageio.get_writer(video, fps=fps, codec="libx264", macro_block_size=8, quality=7) as w:
                for im in images:
                    w.append_data(im)
        else:
            raise InputError(f"--video must end in .mp4 or .gif, got {video.name}")
        out.video = video
    if rrd is not None:
        out.recording = write_rrd(arrays, attrs, Path(rrd))
    return out


# --- the Panda's links for the recording ------------------------------------------------------------------------
def _rpy_matrix(rpy: list[float]) -> np.ndarray:
    """URDF roll-pitch-yaw -> rotation matrix."""
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


@lru_cache(maxsize=1)
def panda_link_meshes() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Visual meshes of the Panda's links from pybullet_data, in each link's URDF frame: name -> (vertices, faces)."""
    import pybullet_data
    import trimesh

    root = Path(pybullet_data.getDataPath()) / "franka_panda"
    tree = ET.parse(root / "panda.urdf")
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for link in tree.getroot().iter("link"):
        vis = link.find("visual")
        if vis is None or vis.find("geometry/mesh") is None:
            continue
        fname = vis.find("geometry/mesh").get("filename").replace("package://", "")  # type: ignore[union-attr]
        origin = vis.find("origin")
        xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        mesh = trimesh.load(root / fname, force="mesh")
        v = np.asarray(mesh.vertices) @ _rpy_matrix(rpy).T + np.asarray(xyz)
        out[link.get("name")] = (v.astype(np.float32), np.asarray(mesh.faces, dtype=np.uint32))  # type: ignore[index]
    return out


def robot_link_poses(q: np.ndarray, opening: np.ndarray) -> list[dict[str, tuple[np.ndarray, np.ndarray]]]:
    """Per recorded state, the world pose (position [m], rotation) of each Panda link by FK (pybullet DIRECT)."""
    import pybullet as pb

    from tasks.robot import Panda

    poses = []
    with Panda() as panda:
        names = {pb.getJointInfo(panda.body, j, physicsClientId=panda.cid)[12].decode(): j
                 for j in range(pb.getNumJoints(panda.body, physicsClientId=panda.cid))}
        base = pb.getBodyInfo(panda.body, physicsClientId=panda.cid)[0].decode()
        base_pos, base_orn = pb.getBasePositionAndOrientation(panda.body, physicsClientId=panda.cid)
        base_rot = np.asarray(pb.getMatrixFromQuaternion(base_orn)).reshape(3, 3)
        for qk, wk in zip(q, opening):
            panda.set_joints(np.asarray(qk), float(wk))
            frame = {base: (np.asarray(base_pos), base_rot)}
            frame.update({n: panda.link_pose(j) for n, j in names.items()})
            poses.append(frame)
    return poses


def write_rrd(arrays: dict[str, np.ndarray], attrs: dict, path: Path) -> Path:
    """The attempt as a Rerun recording: robot links, pads, particles, Gaussians (per frame), forces (per interval)."""
    import rerun as rr

    from tasks.record import ProbeRecording
    from tasks.robot import PHASES

    meshes = panda_link_meshes()
    k_frames = np.minimum(arrays["frame_control_index"], len(arrays["control_t_s"]) - 1)
    poses = robot_link_poses(arrays["command_q_rad"][k_frames], arrays["command_opening_m"][k_frames, 0])
    t_c = arrays["control_t_s"]
    with ProbeRecording(path, recording_id=f"L3-attempt-{attrs.get('attempt', 0)}") as rec:
        for name, (v, f) in meshes.items():
            rec.rec.log(f"{ROBOT}/{name}", rr.Mesh3D(vertex_positions=v, triangle_indices=f,
                                                     albedo_factor=[235, 235, 240, 255]), static=True)
        frame_k = 0
        for i, t in enumerate(arrays["frame_t_s"]):
            rec.set_time(i, float(t))
            for name, (p, R) in poses[i].items():
                if name in meshes:
                    rec.rec.log(f"{ROBOT}/{name}", rr.Transform3D(translation=p.astype(np.float32),
                                                                   mat3x3=R.astype(np.float32)))
            rec.particles(arrays["particles_x_m"][i], radius_m=0.001)
            centers, cov = frame_gaussians(arrays, i)
            w, vecs = np.linalg.eigh(cov)
            vecs = vecs * np.where(np.linalg.det(vecs) < 0, -1.0, 1.0)[:, None, None]
            from scipy.spatial.transform import Rotation
            rec.gaussians(centers, np.sqrt(np.clip(w, 1e-14, None)), Rotation.from_matrix(vecs).as_quat(),
                          arrays["gaussian_colors"])
            k = int(k_frames[i])
            for f in range(2):
                rec.box_collider(f"finger_{f}", arrays["finger_position_m"][k, f], arrays["finger_half_extents_m"],
                                 arrays["finger_quat_xyzw"][k, f])
            k_next = int(arrays["frame_control_index"][i + 1]) if i + 1 < len(k_frames) else len(t_c)
            for kk in range(frame_k, min(k_next, len(t_c))):  # force curves at the control rate
                rec.rec.set_time("sim_time", duration=float(t_c[kk]))
                for f in range(2):
                    rec.scalar(f"finger_{f}_force_n", float(np.linalg.norm(arrays["finger_force_n"][kk, f])))
                rec.scalar("object_com_height_m", float(arrays["object_com_m"][kk, 2]))
            frame_k = max(frame_k, k_next)
        labels = attrs.get("labels", {})
        rec.log("L3 attempt %s (%s): " % (attrs.get("attempt"), attrs.get("role", "")) + ", ".join(
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
        frame_col = next(c for n, c in cols.items() if n.endswith("frame") or n == "frame")
        pos_col = next(c for n, c in cols.items() if "Points3D:positions" in n or n.endswith("positions"))
        for fr, pos in zip(frame_col.to_pylist(), pos_col.to_pylist()):
            if pos is not None:
                frames[int(fr)] = np.asarray(pos, dtype=np.float32).reshape(-1, 3)
    return [frames[k] for k in sorted(frames)]
