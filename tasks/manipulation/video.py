"""A recorded pick-and-place attempt as video frames (renders/pick_and_place.mp4): the whole robot in a fixed wide
view, its gripper drawn link by link (tasks.render.gripper_model for the Robotiq 2F-85 / 2F-140; the URDF's meshes
for the Franka Hand), the object's Gaussians driven by the recorded particles and drawn by the same splatting renderer
as the drop videos (tasks.render.splats, lit by their deformed normals), and a close-up inset that follows the
fingers. The picture is composed in tasks.render.attempt_video; this module reads the attempt and poses the robot.

    video = PickPlaceVideo(arrays, attrs)          # tasks.manipulation.data.read_attempt's arrays and attributes
    for i in range(len(video)):
        frame = video.frame(i)                     # RGB (720, 1280, 3) uint8

Drawn on the run's device (`device`: cpu or cuda, as the drop videos are). Deterministic on the CPU: the same attempt
gives the same bytes; on a GPU, within a colour level of them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from tasks.manipulation.scene import VIDEO_FPS, VIDEO_SIZE, attempt_timeline, backdrop, object_gaussians, view_direction
from tasks.render import mesh_raster as raster
from tasks.render.attempt_video import (SplatSet, choose_corner, compose, inset_camera, inset_size, paste_inset,
                                        wide_camera)
from tasks.render.binding import Binding, blended_gradients
from tasks.render.camera import Camera
from tasks.render.captions import caption
from tasks.render.gripper_model import Part, gripper_parts, robotiq_links
from tasks.render.shading import normals_from_covariances
from tasks.robot import PHASES
from tasks.robot.visual import (FLANGE_LINK, HAND_LINKS, box_mesh, gripper_boxes, gripper_spec, link_poses,
                                panda_visual_meshes, shade, tcp_frame, uses_urdf_hand)

CAMERA_EVERY = 3  # the wide camera frames the robot at every 3rd video frame (and the first and last)
POINT_EVERY = 7  # ... through every 7th vertex of its meshes
OPACITY = 0.95  # the trial's Gaussians are recorded without opacities
INSET_RAISE = 0.3  # the close-up looks this many grasp radii above the pads' midpoint


class PickPlaceVideo:
    """The frames of one recorded attempt (the room and the cameras are set up once)."""

    def __init__(self, arrays: dict[str, np.ndarray], attrs: dict[str, Any] | None = None,
                 width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1], fps: float = VIDEO_FPS,
                 device: str = "cpu") -> None:
        self.arrays, self.attrs = arrays, attrs or {}
        self.device = device  # where the triangles and the splats are drawn
        plan = self.attrs.get("plan") or {}
        target = plan.get("target_xy_m")
        self.target = (float(target[0]), float(target[1])) if target else None
        self.spec = gripper_spec(plan)
        self.links = None if uses_urdf_hand(self.spec) else robotiq_links(str(getattr(self.spec, "name", "")))
        self.timeline = attempt_timeline(arrays, fps)
        self.poses = link_poses(np.array([f.q_rad for f in self.timeline]),
                                np.array([f.opening_m for f in self.timeline]))
        colors = np.asarray(arrays["gaussian_colors"], np.float64)[:, :3]
        self.albedo = np.clip(colors / 255.0 if colors.max() > 1.0 else colors, 0.0, 1.0)
        self.rest_normals = normals_from_covariances(arrays["gaussian_positions_m"], arrays["gaussian_covariances_m2"],
                                                     arrays["gaussian_particle_index"],
                                                     arrays["gaussian_particle_weight"], arrays["rest_particles_m"])
        self.binding = Binding.of(arrays["gaussian_positions_m"], arrays["gaussian_covariances_m2"],
                                  arrays["gaussian_particle_index"], arrays["gaussian_particle_weight"],
                                  arrays["rest_particles_m"])  # the Gaussians follow the recorded particles
        self.toward_eye = view_direction(arrays.get("closing_axis_world"))
        rest = np.asarray(arrays["rest_particles_m"], np.float64)
        self.object_radius_m = 0.5 * float(np.ptp(rest, axis=0).max())
        robot, path = self._framed_points(rest)
        self.cam = wide_camera(np.concatenate([robot, path]), self.toward_eye, width, height)
        self.room = backdrop(self.cam, self.target)
        self.inset_px = inset_size(width, height)
        self._close_room: tuple[Camera, Any] | None = None
        # the close-up goes where it hides least: the object's path and the pads count 50 times an arm point
        self.corner = choose_corner(self.cam, self.inset_px[::-1], np.concatenate([robot, path]),
                                    np.concatenate([np.ones(len(robot)), np.full(len(path), 50.0)]))

    def __len__(self) -> int:
        return len(self.timeline)

    def _framed_points(self, rest_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """What the wide camera must hold: the robot's mesh points over the attempt, and the object's path (its rest
        particles, its centre of mass over time, the pads over time) with the place target."""
        n = len(self.timeline)
        frames = sorted({*range(0, n, CAMERA_EVERY), n - 1})
        robot = np.concatenate([self.robot_points(i) for i in frames])
        com = np.asarray(self.arrays["object_com_m"], np.float64)
        pads = np.asarray([f.pad_position_m for f in self.timeline], np.float64).reshape(-1, 3)
        path = [rest_m[::POINT_EVERY], com[np.isfinite(com).all(axis=1)], pads]
        if self.target is not None:
            path.append(np.array([[self.target[0], self.target[1], 0.0]]))
        return robot, np.concatenate([p for p in path if len(p)])

    def robot_points(self, i: int) -> np.ndarray:
        """World points [m] on the robot's links and gripper at video frame i (every POINT_EVERY-th vertex)."""
        return np.concatenate([v[::POINT_EVERY] for v, _, _, _ in self._robot_parts(i)])

    def _robot_parts(self, i: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """World-posed parts of the robot at video frame i: (vertices [m], faces, unit normals, colour)."""
        pose, fr = self.poses[i], self.timeline[i]
        urdf_hand = uses_urdf_hand(self.spec)
        parts = []
        for link in panda_visual_meshes():
            if link.name not in pose or (not urdf_hand and link.name in HAND_LINKS):
                continue
            p, r = pose[link.name]
            parts.append((link.vertices_m @ r.T + p, link.faces, link.normals @ r.T, link.rgb))
        if urdf_hand:
            return parts
        half = np.asarray(self.arrays["finger_half_extents_m"], np.float64)
        approach = pose[FLANGE_LINK][1][:, 2] if FLANGE_LINK in pose else np.array([0.0, 0.0, -1.0])
        if self.links is not None and FLANGE_LINK in pose:
            origin, rot, opening = tcp_frame(fr.pad_position_m, half, approach)
            model: list[Part] = gripper_parts(self.links, pose[FLANGE_LINK][0], origin, rot, 0.5 * opening)
            parts += [(m.vertices_m, m.faces, m.normals, m.rgb) for m in model]
        else:  # a gripper this installation has no link model of: boxes round the recorded pads

            for c, r, h, rgb in gripper_boxes(fr.pad_position_m, half, approach, self.spec):
                v, f, nrm = box_mesh(c, r, h)
                parts.append((v, f, nrm, rgb))
        return parts

    def _object(self, i: int) -> SplatSet:
        """The object's Gaussians at video frame i, their normals carried by the recorded deformation."""
        fr, a = self.timeline[i], self.arrays
        normals = self.rest_normals
        if fr.particle_frame < 0:  # at rest, before the simulation
            centres, cov = object_gaussians(a, fr.particle_frame)
        else:
            F = a["particles_F"][fr.particle_frame]
            state = self.binding.deform(a["particles_x_m"][fr.particle_frame], F)
            centres, cov = state.centres_m, state.covariances_m2
            F_g = state.gradients if np.isfinite(F).all() else \
                blended_gradients(a["gaussian_particle_index"], a["gaussian_particle_weight"], np.nan_to_num(F))
            normals = self.binding.normals(self.rest_normals, F_g)
        ok = np.isfinite(centres).all(axis=1) & np.isfinite(cov).all(axis=(1, 2))
        return SplatSet(centres[ok], cov[ok], self.albedo[ok], np.full(int(ok.sum()), OPACITY), normals[ok])

    def _draw(self, cam: Camera, room: Any, parts: list, splats: SplatSet) -> np.ndarray:
        """The robot's triangles over the room, then the object's splats over both (one depth buffer)."""
        view = cam.frame()[0][2]
        meshes = [raster.Mesh(v, f, shade(n, rgb, view), raster.ROBOT) for v, f, n, rgb in parts]
        depth = np.empty((cam.height, cam.width), np.float32)
        rgb, _ = raster.draw(cam.frame(), cam.width, cam.height, room.rgb, room.depth, room.label, meshes,
                             depth_out=depth, device=self.device)
        return compose(cam, rgb, depth, splats, self.device)

    def inset_camera(self, i: int) -> Camera:
        """The close-up camera of video frame i: a little above the pads' midpoint, framing the grasp and the
        fingers."""
        pads = np.asarray(self.timeline[i].pad_position_m, np.float64)
        radius = max(self.object_radius_m, 0.5 * float(np.linalg.norm(pads[0] - pads[1])) + 0.03, 0.05)
        centre = pads.mean(axis=0) + np.array([0.0, 0.0, INSET_RAISE * radius])  # more finger, less table
        return inset_camera(centre, radius, self.toward_eye, *self.inset_px)

    def frame(self, i: int) -> np.ndarray:
        """RGB image (H, W, 3) uint8 of video frame i: the wide view, the caption and the fingers' close-up."""
        parts, splats = self._robot_parts(i), self._object(i)
        wide = self._draw(self.cam, self.room, parts, splats)
        close_cam = self.inset_camera(i)
        if self._close_room is None or self._close_room[0] != close_cam:  # the room ray-cast once per camera pose
            self._close_room = (close_cam, backdrop(close_cam, self.target))
        close = self._draw(close_cam, self._close_room[1], parts, splats)
        fr = self.timeline[i]
        phase = "approach" if fr.control_index < 0 else PHASES[int(self.arrays["phase"][fr.control_index])]
        lines = [f"t = {fr.t_s:5.2f} s   {phase}"]
        if fr.control_index >= 0:
            fk = np.linalg.norm(self.arrays["finger_force_n"][fr.control_index], axis=-1)
            if np.isfinite(fk).all():
                lines.append(f"finger forces {fk[0]:5.2f} N  {fk[1]:5.2f} N")
        title = getattr(self.spec, "title", None) or "Franka Hand"
        lines.append(str(title).split(" (")[0])
        return paste_inset(caption(wide, lines), close, "fingers, close-up", self.corner)

    def frames(self) -> list[np.ndarray]:
        """Every video frame, in order."""
        return [self.frame(i) for i in range(len(self))]
