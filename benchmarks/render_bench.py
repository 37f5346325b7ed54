"""Seconds per frame of the Gaussian splatting renderer (tasks.render.splats) on the CPU and, when Warp sees one, on
a CUDA GPU: the first call of the process (Warp's module load, from its kernel cache when compiled before) and the
steady state (median of repeats: wall seconds, and the process's CPU seconds, which a shared machine's load does not
inflate), for an asset's gaussians.ply or a synthetic ball of N Gaussians.

    python -m benchmarks.render_bench [ASSET_DIR | file.ply] [--gaussians N] [--width 1280 --height 720]
                                      [--repeats 5] [--devices cpu,cuda] [--png frame.png] [--json]

With --json it prints the figures (run()): per device the first call and the steady state, the Gaussians per frame,
the asset used, the 1-minute load average before and after (a shared CPU's timings vary with what else runs), and
where both devices ran, how far the CUDA image is from the CPU one (8-bit levels); else a table.
"""

from __future__ import annotations

import os
import platform
import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.table import Table

from contracts.errors import InputError
from flows.cli.apps import console, emit_json, fail, results
from tasks.geometry.gaussians import read_3dgs_ply, rest_covariances
from tasks.native_output import init_warp_quietly
from tasks.render import splats
from tasks.render.camera import Camera
from tasks.render.sh import read_sh_rest
from tasks.render.splats import render_gaussians


def load_splats(asset_dir: Path | None, synthetic: int) -> tuple[dict[str, np.ndarray], str]:
    """Centres, covariances, colours, opacities (and SH when the file has them) of an asset, or a synthetic ball of
    `synthetic` Gaussians (radius 8 cm, resting on the table) when asset_dir is None; and a name for the report."""
    if asset_dir is not None:
        ply = asset_dir / "gaussians.ply" if asset_dir.is_dir() else asset_dir
        if not ply.is_file():
            raise InputError(f"{asset_dir}: no gaussians.ply (give an asset directory or a .ply file)")
        g = read_3dgs_ply(ply)
        splats = {"means_m": g["positions_m"], "colors_rgb": np.clip(g["colors"], 0, 1), "opacities": g["opacities"],
                  "covariances_m2": rest_covariances(g["scales_m"], g["rotations_wxyz"])}
        sh = read_sh_rest(ply)
        if sh is not None:
            splats["sh_coeffs"] = sh
        return splats, str(ply)
    rng = np.random.default_rng(0)
    n = int(synthetic)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    means = 0.08 * d * rng.uniform(0.6, 1.0, (n, 1)) ** (1 / 3) + [0.0, 0.0, 0.08]
    sigma = 0.08 * np.sqrt(4.0 / n) * 1.5
    a = rng.normal(0.0, sigma, (n, 3, 3))
    covs = a @ a.transpose(0, 2, 1) / 3.0 + np.eye(3) * (0.2 * sigma) ** 2
    colors = 0.5 + 0.4 * d * [1.0, 0.6, 0.3]
    return ({"means_m": means, "covariances_m2": covs, "colors_rgb": colors, "opacities": np.full(n, 0.9)},
            f"synthetic ball of {n} Gaussians")


def framing_camera(means_m: np.ndarray, width: int, height: int) -> Camera:
    """A three-quarter view from the front, slightly above, that frames the Gaussians' bounding box."""
    lo, hi = means_m.min(axis=0), means_m.max(axis=0)
    centre = 0.5 * (lo + hi)
    radius = max(0.02, 0.5 * float(np.linalg.norm(hi - lo)))
    d = np.array([0.35, -1.0, 0.6])
    d /= np.linalg.norm(d)
    return Camera(tuple(centre + 1.25 * radius / np.tan(np.radians(20.0)) * d), tuple(centre), 40.0, width, height)


def _time_device(splats: dict[str, np.ndarray], cam: Camera, device: str, repeats: int) -> dict[str, Any]:
    """First call and steady-state seconds per frame on one device, and a digest of the image."""
    import hashlib

    t0 = time.perf_counter()
    img = render_gaussians(cam, device=device, **splats)  # type: ignore[arg-type]
    first = time.perf_counter() - t0
    times, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        again = render_gaussians(cam, device=device, **splats)  # type: ignore[arg-type]
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return {"first_call_s": round(first, 4), "steady_s": round(statistics.median(times), 4),
            "steady_min_s": round(min(times), 4), "steady_cpu_s": round(statistics.median(cpu), 4),
            "threads": splats_threads(device), "repeats": repeats,
            "deterministic": bool(np.array_equal(img, again)), "image_sha256": hashlib.sha256(img.tobytes()).hexdigest(),
            "image": img}


def splats_threads(device: str) -> int:
    """Threads that draw a frame's pixels on this device (CPU bands; 1 launch on CUDA)."""
    return splats.CPU_BANDS if device == "cpu" else 1


def run(asset_dir: Path | None = None, synthetic: int = 100_000, width: int = 1280, height: int = 720,
        repeats: int = 5, devices: tuple[str, ...] = ("cpu", "cuda"), png: Path | None = None) -> dict[str, Any]:
    """The figures as a JSON-ready dict; cuda is skipped (with a reason) where Warp sees no CUDA device."""
    init_warp_quietly()
    import warp as wp

    splats, name = load_splats(asset_dir, synthetic)
    cam = framing_camera(np.asarray(splats["means_m"]), width, height)
    out: dict[str, Any] = {"asset": name, "gaussians_per_frame": len(splats["means_m"]), "width": width,
                           "height": height, "sh_degree_rest_coeffs": int(splats["sh_coeffs"].shape[1])
                           if "sh_coeffs" in splats else 0, "scene": "studio", "warp": wp.config.version,
                           "cpu_model": platform.processor() or platform.machine(), "cpu_count": os.cpu_count(),
                           "loadavg_1min_before": round(os.getloadavg()[0], 2)}
    images = {}
    for device in devices:
        if device.startswith("cuda") and not wp.is_cuda_available():
            out[device] = {"skipped": "no CUDA device visible to Warp"}
            continue
        res = _time_device(splats, cam, device, repeats)
        images[device] = res.pop("image")
        if device.startswith("cuda"):
            res["gpu"] = wp.get_device(device).name
        out[device] = res
    if "cpu" in images and "cuda" in images:
        diff = np.abs(images["cpu"].astype(int) - images["cuda"].astype(int))
        out["cpu_vs_cuda"] = {"max_abs_diff_levels": int(diff.max()), "mean_abs_diff_levels": round(float(diff.mean()), 5),
                              "pixels_differing_over_2_levels": int((diff.max(axis=-1) > 2).sum())}
    if png is not None and images:
        from PIL import Image

        Image.fromarray(next(iter(images.values()))).save(png)
        out["png"] = str(png)
    out["loadavg_1min_after"] = round(os.getloadavg()[0], 2)
    return out


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.command()
def bench_render(
    asset: Path | None = typer.Argument(None, help="asset directory (its gaussians.ply) or a .ply; default: a "
                                        "synthetic ball of --gaussians Gaussians"),
    gaussians: int = typer.Option(20_000, "--gaussians", min=1, help="Gaussians of the synthetic ball"),
    width: int = typer.Option(1280, "--width", min=16, max=8192, help="image width [px]"),
    height: int = typer.Option(720, "--height", min=16, max=8192, help="image height [px]"),
    repeats: int = typer.Option(5, "--repeats", min=1, help="steady-state frames timed (median reported)"),
    devices: str = typer.Option("cpu,cuda", "--devices", help="comma-separated Warp devices to time"),
    png: Path | None = typer.Option(None, "--png", help="also write the frame to this PNG"),
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
) -> None:
    """Seconds per frame on the CPU and (where Warp sees one) a CUDA GPU: first call and steady state; Gaussians
    per frame; the asset used."""
    if asset is not None and not asset.exists():
        fail(f"{asset} does not exist")
    try:
        with console.status("timing the splat renderer ..."):
            data = run(asset.absolute() if asset else None, gaussians, width, height, repeats,
                       tuple(devices.split(",")), png)
    except InputError as e:
        fail(str(e))
    if as_json:
        emit_json(data)
        return
    table = Table(title=f"splat render {width} x {height}, {data['gaussians_per_frame']} Gaussians ({data['asset']})")
    table.add_column("device")
    table.add_column("first call", justify="right")
    table.add_column("steady", justify="right")
    for dev in ("cpu", "cuda"):
        res = data.get(dev, {})
        if "steady_s" in res:
            table.add_row(dev, f"{res['first_call_s']:.3f} s", f"{res['steady_s']:.3f} s")
        elif res:
            table.add_row(dev, res.get("skipped", "-"), "")
    results.print(table)


if __name__ == "__main__":
    app()
