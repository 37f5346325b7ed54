"""Wall time of renders/pick_and_place.mp4: `replay` of a stored L3 attempt to an MP4 (1280 x 720, 30 fps by default).

    python benchmarks/pick_and_place_video.py ASSET_DIR [--attempt N] [--width 1280 --height 720] [--repeat 2]
        [--device cpu|cuda] --json

Times, per run (wall clock; and the CPU seconds of the replay, in this process and in the ffmpeg encoder, which a
shared machine's load does not inflate): the renderer's set-up (camera, backdrop ray casting, forward kinematics of
every frame), the frames (robot triangles and object splats rasterised by Warp CPU kernels, the caption), the H.264
encoding (imageio-ffmpeg, its own process) and the whole `replay` call. The renderer is replay's
(tasks.manipulation.video.PickPlaceVideo: the whole robot, the object's splats, the fingers' close-up). The first run of a process also loads the
Panda's meshes and Warp's kernels (compiled once per machine into Warp's kernel cache); later runs (``--repeat``) are
warm. The 1-minute load average around each run is recorded: on a shared 2-core machine CPU timings vary with what
else runs.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import TypedDict

from tasks.manipulation.data import read_attempt
from tasks.manipulation.replay import replay, video_writer
from tasks.manipulation.video import PickPlaceVideo

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _cpu() -> tuple[float, float]:
    """CPU seconds used so far by this process and by its finished children (the ffmpeg encoder)."""
    import resource

    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time(), children.ru_utime + children.ru_stime


class VideoRun(TypedDict):
    """The figures of one run (seconds, MB, frames per second, pixels, load average)."""

    replay_wall_s: float
    replay_cpu_s: float
    encoder_cpu_s: float
    setup_s: float
    frames_s: float
    per_frame_s: float
    encode_s: float
    frames: int
    video_duration_s: float
    mp4_mb: float
    fps: float
    size: list[int]
    loadavg_1min_before: float
    loadavg_1min_after: float


def run_once(asset: Path, attempt: int | None, width: int, height: int, device: str = "cpu") -> VideoRun:
    """One timed replay to a temporary MP4, with its phases timed separately on the same data."""
    import imageio.v2 as imageio

    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="ds-bench-video-") as tmp:
        c0 = _cpu()
        t0 = time.perf_counter()
        out = replay(asset, attempt, video=Path(tmp) / "pick_and_place.mp4", width=width, height=height,
                     device=device)
        total = time.perf_counter() - t0
        c1 = _cpu()
        size_mb = (Path(tmp) / "pick_and_place.mp4").stat().st_size / 1e6
        meta = imageio.get_reader(Path(tmp) / "pick_and_place.mp4").get_meta_data()
        arrays, attrs = read_attempt(asset, attempt)
        t1 = time.perf_counter()
        renderer = PickPlaceVideo(arrays, attrs, width, height, device=device)
        t2 = time.perf_counter()
        frames = [renderer.frame(i) for i in range(len(renderer))]
        t3 = time.perf_counter()
        with video_writer(Path(tmp) / "again.mp4") as w:
            for im in frames:
                w.append_data(im)
        t4 = time.perf_counter()
    return {"replay_wall_s": total, "replay_cpu_s": c1[0] - c0[0], "encoder_cpu_s": c1[1] - c0[1],
            "setup_s": t2 - t1, "frames_s": t3 - t2, "per_frame_s": (t3 - t2) / len(frames),
            "encode_s": t4 - t3, "frames": out.n_frames, "video_duration_s": out.duration_s, "mp4_mb": size_mb,
            "fps": float(meta["fps"]), "size": list(meta["size"]), "loadavg_1min_before": load0,
            "loadavg_1min_after": os.getloadavg()[0]}


def main(argv: list[str] | None = None) -> int:
    """Parse the arguments, run, print."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("asset", type=Path, help="asset directory with interaction/ (e.g. a published default asset)")
    p.add_argument("--attempt", type=int, default=None, help="attempt index (default: the last one)")
    p.add_argument("--width", type=int, default=1280)
    p.add_argument("--height", type=int, default=720)
    p.add_argument("--repeat", type=int, default=2, help="runs in one process (the first is cold)")
    p.add_argument("--device", default="cpu", help="cpu | cuda: where the frames are drawn")
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    a = p.parse_args(argv)
    runs = [run_once(a.asset, a.attempt, a.width, a.height, a.device) for _ in range(max(1, a.repeat))]
    report = {"asset": str(a.asset), "attempt": a.attempt, "device": a.device, "runs": runs, "cpu_count": os.cpu_count(),
              "machine": platform.processor() or platform.machine(), "python": platform.python_version()}
    if a.json:
        print(json.dumps(report, indent=1))
    else:
        for i, r in enumerate(runs):
            print(f"run {i}: {r['frames']} frames ({r['video_duration_s']:.2f} s of video) in "
                  f"{r['replay_wall_s']:.2f} s "
                  f"(set-up {r['setup_s']:.2f} s, {1000 * r['per_frame_s']:.0f} ms per frame, encoding "
                  f"{r['encode_s']:.2f} s; load {r['loadavg_1min_before']:.1f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
