"""Round trip of `deformsmith calibrate` (issue #39): drop videos of a small solid sphere with a known E and viscosity
(soft, medium, stiff), simulated in full by the MPM (the fall, the impacts, the rebounds), drawn from the side
(tasks.calibrate.synthetic: each particle a disc, a textured scene, camera noise) and written as MJPEG video (JPEG
compression); then the command's own path (flows.calibrate.calibrate_asset) tracks the video and fits E and the
viscosity to it, starting from a prior material (E 100 kPa, no viscosity) on an asset of the same sphere.

    python -m benchmarks.calibrate_roundtrip [--cases soft,medium,stiff] [--json]

Per case: the true and fitted E and viscosity, E's error, the rebound ratio of the true material and of the fitted
one (the same simulated drop) and its error, the video's rebound and impact strain as tracked beside the true
rollout's own (from its particles), the tracking figures and the wall time. Passes: E within 15 %, rebound within 10 %.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from contracts.agents import TargetBehaviour
from contracts.asset_dir import HeldOutSummary, MaterialRecord, PhysicalRecord, SelectionSummary
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from flows.calibrate import calibrate_asset
from flows.l0_geometry import L0Result, write_l0
from tasks.asset_dir import AssetDir
from tasks.calibrate.sim import drop_impact
from tasks.calibrate.synthetic import Camera, mpm_drop_positions, particle_video
from tasks.calibrate.video import write_video
from tasks.geometry import pipeline
from tasks.mpm.scene import box_particles

RADIUS_M, DENSITY = 0.02, 1000.0
PRIOR = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3)
E_TOLERANCE, REBOUND_TOLERANCE = 0.15, 0.10


@dataclass(frozen=True)
class Case:
    """A sphere's true material and how its video is taken."""

    name: str
    youngs_modulus_pa: float
    viscosity_pa_s: float
    px_per_m: float = 1000.0  # a stiff ball's compression (3-4 %) needs a closer camera and a higher drop
    drop_height_m: float = 0.15
    fps: float = 1000.0
    duration_s: float = 0.4


CASES = {"soft": Case("soft", 5e4, 8.0), "medium": Case("medium", 2e5, 30.0),
         "stiff": Case("stiff", 1e6, 60.0, px_per_m=1500.0, drop_height_m=0.3, duration_s=0.55)}


def sphere(spacing_m: float) -> tuple[np.ndarray, np.ndarray, PhysicalModel]:
    """A solid sphere of RADIUS_M resting on z = 0 and its physical model."""
    r = RADIUS_M
    pos, vol = box_particles((-r, -r, -r), (r, r, r), spacing_m)
    keep = np.linalg.norm(pos, axis=1) <= r
    pos, vol = pos[keep] + np.array([0.0, 0.0, r]), vol[keep]
    phys = PhysicalModel(density_kg_per_m3=DENSITY, volume_m3=float(vol.sum()), mass_kg=float(vol.sum() * DENSITY),
                         particle_count=len(pos), particle_spacing_m=spacing_m, ground_friction=0.5,
                         gripper_friction=0.8, center_of_mass_m=(0.0, 0.0, r), extents_m=(2 * r, 2 * r, 2 * r),
                         category="ball")
    return pos, vol, phys


def write_sphere_l0(path: Path, pos: np.ndarray, vol: np.ndarray, spacing_m: float) -> None:
    """L0 of the sphere (flows.l0_geometry.write_l0): an icosphere mesh, itself its one convex collision part, the
    given lattice as its particles and Gaussians bound to them: what L2's probes (the calibration's held-out tests)
    read of an asset."""
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=RADIUS_M)
    mesh.apply_translation((0.0, 0.0, RADIUS_M))
    arrays = pipeline.mesh_to_arrays(mesh)
    proxy: dict[str, np.ndarray] = {
        "vertices": arrays["vertices"], "faces": arrays["faces"], "part_vertex_count": np.array([len(mesh.vertices)]),
        "part_face_count": np.array([len(mesh.faces)]), "union_volume_m3": np.array(mesh.volume)}
    particles: dict[str, np.ndarray] = {
        "positions_m": pos, "volumes_m3": vol, "colors": np.tile(np.array([200, 40, 30], np.uint8), (len(pos), 1)),
        "spacing_m": np.array(spacing_m), "lattice_fill_ratio": np.array(1.0),
        "body_volume_m3": np.array(vol.sum())}  # L1's volume (sphere())
    settings = pipeline.settings_from_contract("draft")
    gaussians = pipeline.build_gaussians(arrays, particles, settings)
    info = pipeline.BuildInfo(source="text", name="ball", category="ball")
    write_l0(L0Result(arrays, proxy, particles, gaussians, info,
                      pipeline.check_geometry(arrays, proxy, particles, gaussians)), path)


def write_sphere_asset(path: Path, spacing_m: float, prior: Material = PRIOR) -> Path:
    """An asset directory holding what `calibrate` reads: L0 (write_sphere_l0: the particles), L1's model and L2's
    material."""
    pos, vol, phys = sphere(spacing_m)
    write_sphere_l0(path, pos, vol, spacing_m)
    adir = AssetDir(path)
    adir.write_physical(PhysicalRecord(passed=True, status="accepted", message="a test sphere", material_class="rubber",
                                       intent="", mass_check={}, targets=TargetBehaviour(), physical_model=phys,
                                       metrics={}, sim_calls=0, attempts=1, recordings=[]))
    adir.write_material(MaterialRecord(
        passed=True, status="accepted", message="the prior", intent="", targets=TargetBehaviour(), material=prior,
        physical_model=phys, metrics={}, held_out=HeldOutSummary(metrics={}, targets_met=None, score=None, bands=[],
                                                                 probes=[]),
        selection=SelectionSummary(status="accepted", score=None, targets_met=True, best_iteration=0, attempts=1,
                                   sim_calls=0, screening={"sim_calls": 0}, ranking=[]),
        sim_calls=0, recordings={}))
    return path


def true_rebound(x: np.ndarray, drop_height_m: float) -> float:
    """The rollout's own rebound ratio from its particles, as the tracker defines it: the COM's rise above touchdown
    (the lowest bottom, in the flight shape) over its fall to there."""
    com, bottom = x[:, :, 2].mean(axis=1), x[:, :, 2].min(axis=1)
    low = int(np.argmin(bottom))
    td = bottom[low] + (com[0] - bottom[0])
    apex = float(com[low:].max())
    moving = np.flatnonzero(np.abs(com - com[0]) > 1e-9)
    return (apex - td) / (com[moving[0] - 1] - td)


def write_case_video(case: Case, spacing_m: float, path: Path, sim: SimConfig, noise_grey: float = 3.0,
                     quality: int = 80) -> np.ndarray:
    """The case's drop video (MJPEG at `quality`); returns the rollout's particles per frame."""
    pos, vol, phys = sphere(spacing_m)
    mat = PRIOR.model_copy(update={"youngs_modulus_pa": case.youngs_modulus_pa, "viscosity_pa_s": case.viscosity_pa_s})
    x = mpm_drop_positions(pos, vol, phys, mat, case.drop_height_m, case.fps, case.duration_s, sim)
    k = case.px_per_m
    drop_px = (case.drop_height_m + 4 * RADIUS_M) * k
    cam = Camera(width_px=int(5 * RADIUS_M * k) // 2 * 2, height_px=int(drop_px + 0.03 * k) // 2 * 2,
                 px_per_m=k, floor_y_px=drop_px, centre_x_px=2.5 * RADIUS_M * k)
    frames = particle_video(cam, x, spacing_m, noise_grey=noise_grey, jpeg_quality=None)
    write_video(path, frames, case.fps, quality=quality)
    return x


def roundtrip(case: Case, spacing_m: float = 0.0035, workdir: Path | None = None) -> dict[str, Any]:
    """One case end to end; the figures (see the module docstring)."""
    t0 = time.perf_counter()
    sim = SimConfig(cpu_threads=1)
    with tempfile.TemporaryDirectory(prefix="calibrate-rt-", dir=workdir) as tmp:
        root = Path(tmp)
        video = root / f"{case.name}.avi"
        x = write_case_video(case, spacing_m, video, sim)
        asset = write_sphere_asset(root / "asset", spacing_m)
        t1 = time.perf_counter()
        rec = calibrate_asset(asset, video, drop_height_m=case.drop_height_m, size_m=2 * RADIUS_M, sim=sim,
                              write=False)
    pos, vol, phys = sphere(spacing_m)
    truth = PRIOR.model_copy(update={"youngs_modulus_pa": case.youngs_modulus_pa,
                                     "viscosity_pa_s": case.viscosity_pa_s})
    at_truth = drop_impact(pos, vol, phys, truth, case.drop_height_m, sim)
    e_err = rec.fitted.youngs_modulus_pa / case.youngs_modulus_pa - 1.0
    r_fit = rec.simulated.get("rebound_ratio", float("nan"))
    r_err = r_fit / at_truth["rebound_ratio"] - 1.0
    return {
        "case": case.name, "particles": len(pos), "fps": case.fps, "px_per_m": case.px_per_m,
        "drop_height_m": case.drop_height_m,
        "true_youngs_modulus_pa": case.youngs_modulus_pa, "fitted_youngs_modulus_pa": rec.fitted.youngs_modulus_pa,
        "youngs_modulus_error": e_err, "youngs_modulus_source": rec.youngs_modulus_source,
        "true_viscosity_pa_s": case.viscosity_pa_s, "fitted_viscosity_pa_s": rec.fitted.viscosity_pa_s,
        "viscosity_error": rec.fitted.viscosity_pa_s / case.viscosity_pa_s - 1.0,
        "rebound_true_material": at_truth["rebound_ratio"], "rebound_fitted_material": r_fit,
        "rebound_error": r_err, "rebound_video": rec.metrics.rebound_ratio,
        "rebound_rollout": true_rebound(x, case.drop_height_m),
        "impact_strain_video": rec.metrics.impact_strain, "impact_strain_true_material": at_truth.get("impact_strain"),
        "residuals": rec.residuals, "scale_source": rec.scale.source, "gravity_check_m_per_s2": rec.scale.gravity_check,
        "tracking_confidence": rec.track.tracking_confidence, "frames": rec.track.frames,
        "frames_dropped": rec.track.frames_dropped, "sim_calls": rec.sim_calls, "converged": rec.converged,
        "passed": bool(abs(e_err) <= E_TOLERANCE and abs(r_err) <= REBOUND_TOLERANCE),
        "video_s": t1 - t0, "fit_s": time.perf_counter() - t1,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default="soft,medium,stiff", help="comma-separated: " + ", ".join(CASES))
    ap.add_argument("--spacing", type=float, default=0.0035, help="particle spacing [m] (0.0035: 739 particles)")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = ap.parse_args(argv)
    names = [c.strip() for c in args.cases.split(",") if c.strip()]
    bad = [n for n in names if n not in CASES]
    if bad:
        ap.error(f"unknown case(s): {', '.join(bad)}")
    rows = [roundtrip(CASES[n], args.spacing) for n in names]
    out = {"cases": rows, "passed": sum(r["passed"] for r in rows), "of": len(rows),
           "tolerances": {"youngs_modulus": E_TOLERANCE, "rebound": REBOUND_TOLERANCE},
           "load_average": os.getloadavg()[0]}
    if args.json:
        sys.stdout.write(json.dumps(out, indent=2) + "\n")
    else:
        for r in rows:
            print(f"{r['case']}: E {r['true_youngs_modulus_pa']:.3g} -> {r['fitted_youngs_modulus_pa']:.3g} Pa "
                  f"({r['youngs_modulus_error']:+.1%}), rebound {r['rebound_true_material']:.3f} -> "
                  f"{r['rebound_fitted_material']:.3f} ({r['rebound_error']:+.1%}), "
                  f"{'ok' if r['passed'] else 'MISS'}")
    return 0 if out["passed"] == out["of"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
