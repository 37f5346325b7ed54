"""The paper's drop protocol for an asset: a cached 5 s MPM drop at 30 fps, its two-view videos, and the asset card."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

from cache import cached_task, scratch_dir
from cache.files import source_digest
from contracts.manifest import AssetManifest
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.geometry.outputs import load_l0
from tasks.probes.protocol import PROTOCOL_DURATION_S, PROTOCOL_FPS, drop_protocol, plausibility_metrics
from tasks.probes.rollout import DeformableBody
from tasks.render.card import build_card
from tasks.render.protocol_video import VIDEO_HEIGHT_PX, VIDEO_WIDTH_PX, drop_files, gaussian_renderer

TASK_VERSION = "1"  # the protocol's rollout
VIDEO_TASK_VERSION = "3"  # 2: 1280 x 720 splats, views named as the stills, framed on the fall; the card's drop frames;
# 3: the Gaussians lit by their normals, the clip trimmed to the motion in slow motion (#36)


@cached_task(version=TASK_VERSION, name="renders.drop_protocol")
def drop_protocol_task(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                       sim: SimConfig) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """5 s drop from a quarter of the height at 30 fps: particle states and plausibility metrics (as computed when the
    entry was made: read them through protocol_states, which derives them from the cached states)."""
    return drop_protocol(DeformableBody.from_physical(positions_m, volumes_m3, physical), material, sim)


def protocol_states(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                    sim: SimConfig) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """The cached protocol rollout with its plausibility metrics derived now from its states (a change to a metric's
    definition needs no new 5 s simulation)."""
    arrays, stored = drop_protocol_task(positions_m, volumes_m3, physical, material, sim)
    metrics = dict(stored)
    metrics.update(plausibility_metrics(positions_m, volumes_m3, arrays["x_m"], arrays["F"],
                                        bool(stored.get("healthy", 1.0) == 1.0)))
    return arrays, metrics


@cached_task(version=VIDEO_TASK_VERSION, name="renders.drop_videos")
def drop_videos_task(gaussians: dict[str, np.ndarray], rest_covariances_m2: np.ndarray, rest_particles_m: np.ndarray,
                     x_frames: np.ndarray, F_frames: np.ndarray, renderer_code: str = "",
                     width: int = VIDEO_WIDTH_PX, height: int = VIDEO_HEIGHT_PX, device: str = "cpu") -> dict[str, Path]:
    """Front and side MP4s (1280 x 720, 30 fps, the motion in slow motion) of the deformed, lit Gaussians and the card's drop frames (PNG),
    file name -> the cache's copy (the scratch folder they are written to is removed once they are stored).

    renderer_code: the renderer's source digest (renderer_code(); render_drop_protocol passes it), so a new renderer
    makes new pictures. device: cpu or cuda (the GPU's pictures are keyed apart: within a colour level, not the same
    bytes)."""
    folder = scratch_dir(prefix="ds-drop-video-")
    try:
        return drop_files(gaussians, rest_covariances_m2, rest_particles_m, x_frames, F_frames, folder, PROTOCOL_FPS,
                          PROTOCOL_DURATION_S, width, height, device=device)
    except BaseException:
        shutil.rmtree(folder, ignore_errors=True)
        raise


def renderer_code() -> str:
    """Digest of the code and libraries that draw and encode the drop videos."""
    _, sources = gaussian_renderer()
    here = Path(__file__).resolve().parent.parent
    return source_digest([*sources, here / "tasks" / "render" / "protocol_video.py",
                          here / "tasks" / "geometry" / "gaussians.py"],
                         ("imageio", "imageio-ffmpeg", "numpy", "warp-lang"))


def render_drop_protocol(asset_dir: Path, physical: PhysicalModel, material: Material, sim: SimConfig | None = None,
                         width: int = VIDEO_WIDTH_PX, height: int = VIDEO_HEIGHT_PX) -> dict[str, float]:
    """Run (or reuse) the protocol for an asset directory; write renders/drop_<view>.mp4 and the card's drop frames
    renders/drop_<view>_t<t>s.png; return its metrics."""
    asset = load_l0(asset_dir)
    arrays, metrics = protocol_states(asset.particles_m, asset.volumes_m3, physical, material, sim or SimConfig())
    gaussians = {k: asset.gaussians[k] for k in ("positions_m", "colors", "opacities", "normals", "particle_index",
                                                 "particle_weight")}
    files = drop_videos_task(gaussians, asset.gaussian_covariances(), asset.particles_m, arrays["x_m"], arrays["F"],
                             renderer_code(), width, height, (sim or SimConfig()).device)
    for name, src in files.items():
        dest = Path(asset_dir) / "renders" / name
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src, dest)
    return metrics


def write_card(asset_dir: Path, manifest: AssetManifest | None = None) -> tuple[Path, Path]:
    """renders/card.png and renders/card.html of an asset directory (manifest: the one about to be written, when
    asset.json is not there yet, as in generate's working directory)."""
    return build_card(asset_dir, manifest)
