"""Seconds per 1280 x 720 frame of the Gaussian splatting renderer (tasks.render.splats) on the CPU and a CUDA GPU.

    python benchmarks/render_bench.py [ASSET_DIR | file.ply] [--gaussians N] [--width 1280 --height 720]
                                      [--repeats 5] [--devices cpu,cuda] [--png frame.png]

Prints JSON (tasks.render.bench.run): the first call of the process (Warp loads its compiled module, from the kernel
cache when built before) and the steady state per device, the Gaussians per frame, the asset used, the 1-minute load
average before and after (a shared CPU's timings vary with what else runs), and where both devices ran, how far the
CUDA image is from the CPU one (8-bit levels). The same as `deformsmith bench render --json`.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def main() -> None:
    """Parse the options, run the benchmark, print JSON."""
    from tasks.render.bench import run

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("asset", nargs="?", type=Path, default=None)
    ap.add_argument("--gaussians", type=int, default=20_000, help="synthetic ball size when no asset is given")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--devices", default="cpu,cuda")
    ap.add_argument("--png", type=Path, default=None)
    a = ap.parse_args()
    data = run(a.asset, a.gaussians, a.width, a.height, a.repeats, tuple(a.devices.split(",")), a.png)
    print(json.dumps(data, indent=2, sort_keys=True))


if __name__ == "__main__":
    main()
