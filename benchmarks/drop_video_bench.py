"""Wall time and sharpness of an asset's drop videos (renders/drop_front.mp4, drop_side.mp4): the protocol's states
from the cache (simulated when absent), then `drop_files` (deform, light and splat every frame, H.264) timed alone.

    python benchmarks/drop_video_bench.py ASSET_DIR --cache CACHE_DIR [--json]

Figures: Gaussians, video frames and the frames really drawn (a state at rest repeats the last picture), wall and
CPU seconds of drop_files, and the sharpness (tasks.render.quality: variance of the Laplacian over the pixels the
Gaussians cover) of the 1280 x 720 frame at release (state 0) and at rest (state 30) per view; the 1-minute load
average before and after (a shared CPU's timings vary with what else runs).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

from cache import use_cache_root
from contracts.manifest import AssetManifest
from contracts.sim import SimConfig
from flows.renders import protocol_states
from tasks.geometry.outputs import load_l0
from tasks.probes.protocol import PROTOCOL_DURATION_S, PROTOCOL_FPS
from tasks.render import protocol_video as pv
from tasks.render.quality import coverage_mask, sharpness
from tasks.render.splats import deform_gaussians, render_gaussians

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def run(asset: Path, cache_dir: Path) -> dict:
    """Time drop_files on the asset's cached protocol states; measure the frames' sharpness."""
    import numpy as np

    use_cache_root(str(cache_dir))

    manifest = AssetManifest.model_validate_json((asset / "asset.json").read_text(encoding="utf-8"))
    l0 = load_l0(asset)
    if manifest.physical_model is None or manifest.material is None:
        raise SystemExit(f"{asset}: no physical model or material (L1 / L2 did not pass)")
    arrays, _ = protocol_states(l0.particles_m, l0.volumes_m3, manifest.physical_model, manifest.material,
                                SimConfig())
    x, F = arrays["x_m"], arrays["F"]
    g: dict[str, np.ndarray] = {k: l0.gaussians[k] for k in ("positions_m", "colors", "opacities", "normals",
                                                          "particle_index", "particle_weight") if k in l0.gaussians}
    cov = l0.gaussian_covariances()
    drawn = [0]

    def counting(*args: object, **kw: object) -> np.ndarray:
        drawn[0] += 1
        return render_gaussians(*args, **kw)  # type: ignore[arg-type]

    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="ds-bench-drop-") as tmp:
        c0, t0 = time.process_time(), time.perf_counter()
        files = pv.drop_files(g, cov, l0.particles_m, x, F, Path(tmp), PROTOCOL_FPS, PROTOCOL_DURATION_S,
                              renderer=counting)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        import imageio.v2 as imageio

        reader = imageio.get_reader(files["drop_front.mp4"])
        frames = reader.count_frames()  # type: ignore[attr-defined]  # the ffmpeg reader's
        reader.close()
    sharp = {}
    for view in pv.VIEW_NAMES:
        cam = pv.protocol_camera(x, view, pv.VIDEO_WIDTH_PX, pv.VIDEO_HEIGHT_PX)
        for k in (0, 30):
            image = next(pv.iter_states(render_gaussians, cam, g, cov, l0.particles_m, x[k:k + 1], F[k:k + 1]))
            c, cv = deform_gaussians(g["positions_m"], cov, g["particle_index"], g["particle_weight"],
                                     l0.particles_m, x[k], F[k])
            sharp[f"{view}_state{k}"] = round(sharpness(image, coverage_mask(cam, c, cv, np.asarray(g["opacities"]))),
                                              2)
    return {"asset": str(asset), "gaussians": len(g["positions_m"]), "video_frames_per_view": frames,
            "frames_drawn_both_views": drawn[0], "drop_files_wall_s": round(wall, 2),
            "drop_files_cpu_s": round(cpu, 2), "sharpness": sharp, "loadavg_1min_before": load0,
            "loadavg_1min_after": os.getloadavg()[0]}


def main(argv: list[str] | None = None) -> int:
    """Parse the arguments, run, print."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("asset", type=Path)
    p.add_argument("--cache", type=Path, required=True, help="the cache the asset was generated with")
    p.add_argument("--json", action="store_true")
    a = p.parse_args(argv)
    report = run(a.asset, a.cache)
    print(json.dumps(report, indent=1) if a.json else report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
