"""renders/pick_and_place.mp4: the video of the trial an L3 record shows, rendered by tasks.manipulation.replay and
cached as a file by what it shows (the recorded attempt's bytes) and the code and libraries that draw and encode it."""

from __future__ import annotations

import shutil
from pathlib import Path

from cache import content_key, scratch_dir
from cache.files import cached_file, source_digest
from contracts.manipulation import ManipulationRecord
from tasks.manipulation.data import cached_attempt_folder, read_attempt_folder
from tasks.manipulation.replay import draw_attempt, replay
from tasks.record.trials import reported_attempt

ROOT = Path(__file__).resolve().parents[2]  # the repository: the renderer's sources are named from it


def write_pick_and_place_video(work: Path, record: ManipulationRecord, device: str = "cpu") -> Path | None:
    """renders/pick_and_place.mp4 of the attempt the record shows, drawn on the run's device (cached by the attempt's
    bytes and the device); None, and an earlier L3's video removed, when the record shows no recorded trial (no grasp,
    or its interaction data is absent)."""
    n = reported_attempt(record)
    video = work / "renders" / "pick_and_place.mp4"
    if n is None or not (work / "interaction" / f"attempt_{n:03d}").is_dir():
        video.unlink(missing_ok=True)
        return None
    video.parent.mkdir(parents=True, exist_ok=True)
    # keyed by the full-rate states the cache holds (what replay draws when the asset keeps them thinned, and what
    # prerender_pick_and_place_video keys it by), else by the asset's folder
    cached = cached_attempt_folder(next((r.data_key for r in record.attempts if r.attempt == n), None))
    cached_file(pick_and_place_video_key(work, n, device, folder=cached), video,
                lambda path: replay(work, n, video=path, device=device))
    return video


def renderer_sources() -> list[Path]:
    """The code that renders and encodes the video: the replay and its scene, the render package (but the card's and
    the benchmarks' modules), the robot drawn, the Gaussians, the robot contract and the grippers."""
    renderer = [ROOT / "tasks" / "manipulation" / f"{m}.py" for m in
                ("replay", "scene", "data", "particle_frames", "video")]
    renderer += sorted(p for p in (ROOT / "tasks" / "render").glob("*.py") if not p.name.startswith(("card", "bench")))
    renderer += [ROOT / "tasks" / "robot" / f"{m}.py" for m in ("visual", "panda", "trajectory")]  # the robot drawn
    return [*renderer, ROOT / "tasks" / "geometry" / "gaussians.py", ROOT / "contracts" / "robot.py",
            ROOT / "contracts" / "grippers"]


def pick_and_place_video_key(work: Path, attempt: int, device: str = "cpu", folder: Path | None = None) -> str:
    """The video's cache key: the recorded attempt's bytes, the code and libraries that render and encode it and the
    device that draws it (a GPU's pictures are keyed apart: within a colour level, not the same bytes; rendering it
    takes ~10 s on the CPU; a warm rerun copies it). folder: the attempt's data elsewhere (its cache entry: the same
    bytes, the same key) instead of work/interaction/attempt_NNN."""
    return states_video_key(folder or work / "interaction" / f"attempt_{attempt:03d}", device)


def states_video_key(states: Path, device: str = "cpu") -> str:
    """The video's cache key from an attempt folder's bytes (pick_and_place_video_key's)."""
    code = source_digest(renderer_sources(), ("imageio", "imageio-ffmpeg", "numpy", "opencv-python-headless",
                                              "opencv-python", "pybullet", "scipy", "warp-lang"))
    return content_key("pick_and_place_video", code, states, device)


def prerender_pick_and_place_video(data_key: str, device: str = "cpu") -> bool:
    """Draw the video of a stored trial into the cache before L3 ends (generate: beside L3's later trials), from the
    trial's cache entry, which nothing changes while L3 goes on (L3 may thin or remove the asset's copy). It is stored
    under the key write_pick_and_place_video computes when that trial is the one reported, which then only copies it.
    True when the cache holds the video; False when it holds no entry `data_key`."""
    folder = cached_attempt_folder(data_key)
    if folder is None:
        return False
    scratch = scratch_dir(prefix="ds-pick-place-video-")
    try:
        cached_file(states_video_key(folder, device), scratch / "pick_and_place.mp4",
                    lambda path: draw_attempt(*read_attempt_folder(folder), video=path, device=device))
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return True
