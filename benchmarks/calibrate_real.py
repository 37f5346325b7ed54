"""`deformsmith calibrate` on real clips from public repositories (issue #39): each clip cut to the drop and scaled
down, tracked and fitted against an asset of the object at its stated size and mass; the rebound and the settle time
the video shows beside the calibrated simulation's (docs/calibration/real/README.md).

    python -m benchmarks.calibrate_real --prepare --mirror DIR      # cut the clips from the snapshots
    python -m benchmarks.calibrate_real --asset ping_pong=DIR --asset green_ball=DIR [--clips ...] [--json]

The clips are not in this repository (their authors state no licence): --prepare cuts them from a snapshot of each
source repository (git show of the stated commit and path, as `fetch` brings it) into shared/calibration/real/. An
asset for a clip is either an asset directory (--asset NAME=DIR: its particles, L1's model and L2's material, e.g.
built by `deformsmith geometry`/`physical`/`material`; one built to L1 only gets L2's prior material for its class,
as `bench realworld --priors-only` takes it) or, by default, a sphere of the stated diameter at the stated mass whose
prior material is the one given (--prior-from NAME=DIR, an asset's adopted material) or a rubber prior: a hollow ball's
shell (particles only in its wall, at the density that gives the mass: the green ball) or, with --solid or for a clip
with no wall, a solid sphere at an effective density (the shell's mass over the enclosed volume, as L1 models a hollow
ball). Passes: the calibrated simulation's rebound and settle time within 10 % of the clip's.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import zarr

from contracts.agents import TargetBehaviour
from contracts.asset_dir import PARTICLES_ZARR, HeldOutSummary, MaterialRecord, PhysicalRecord, SelectionSummary
from contracts.material import Material
from contracts.physical import PhysicalModel
from flows.l2_material import l2_targets
from tasks.asset_dir import AssetDir
from tasks.geometry.outputs import load_l0
from contracts.sim import SimConfig
from contracts.video_fit import VideoFitRecord
from flows.calibrate import calibrate_asset, load_asset
from tasks.mpm.scene import ball_particles

ROOT = Path(__file__).resolve().parents[1]
CLIP_DIR = ROOT / "shared" / "calibration" / "real"
RECORD_DIR = ROOT / "docs" / "calibration" / "real"
TOLERANCE = 0.10
RUBBER_PRIOR = Material(youngs_modulus_pa=1e6, poisson_ratio=0.45)


@dataclass(frozen=True)
class Clip:
    """A real clip: where it is, how it is cut, and what the author (or the object's rules) state about the object."""

    name: str
    repo: str
    commit: str
    path: str
    licence: str
    first_frame: int  # the cut: frames [first_frame, last_frame) of the file
    last_frame: int
    width_px: int  # scaled to this width
    object: str
    size_m: float
    size_source: str
    mass_kg: float
    mass_source: str
    cut_why: str
    spacing_m: float = 0.004  # the default sphere asset's particle spacing (a solid sphere)
    wall_m: float | None = None  # a hollow ball: the default asset is a shell of this wall (None: a solid sphere)
    wall_spacing_m: float = 0.0015  # ... its particle spacing (a wall of two particle layers or more)
    wall_why: str = ""  # where the wall comes from


CLIPS = {
    "green_ball": Clip(
        name="green_ball", repo="arzafiruddin/BouncingBall", commit="a7c94f599eef561848296a690cd3191e44d774cd",
        path="bounceAmeen.avi", licence="none stated (all rights reserved by default): not redistributed here",
        first_frame=30, last_frame=188, width_px=640, object="a hollow green ball, dropped by hand onto a wooden floor",
        size_m=8.50 / math.pi * 0.0254,
        size_source="the author's PA8part2_Zafiruddin.m: ballDIn = 8.50 / pi (a circumference of 8.5 in)",
        mass_kg=0.026, mass_source="the author's PA8part2_Zafiruddin.m: ballMass = 0.026 kg",
        cut_why="from a second before the release (the hand holds the ball at the top) to before the hand comes back "
                "for it (the ball rolls out of the bottom of the picture first: those frames are left out)",
        spacing_m=0.003, wall_m=0.003, wall_spacing_m=0.0015,
        wall_why="the real wall, 26 g of rubber (~1100 kg/m^3) over the 6.87 cm sphere, is ~1.7 mm; 3 mm is two particle "
                 "layers at 1.5 mm (one grid cell), the thinnest wall a calibration can afford on a CPU core (1.7 mm "
                 "takes 39000 particles and ~100 s an impact), at the density that keeps 26 g (630 kg/m^3)"),
    "ping_pong": Clip(
        name="ping_pong", repo="zakilyawatsonjarrett/PTV-restitution-coefficient-home-experiment",
        commit="84f1d7ec8ab4a864228ab0fecb5828061a4ab743", path="pingpongvid2.mov",
        licence="none stated (all rights reserved by default): not redistributed here", first_frame=14,
        last_frame=188, width_px=432, object="a table tennis ball dropped onto a wooden worktop",
        size_m=0.040, size_source="ITTF Handbook, Laws of Table Tennis 2.3: a 40 mm ball (the author: 'ping-pong ball')",
        mass_kg=0.0027, mass_source="ITTF Handbook, Laws of Table Tennis 2.3: 2.7 g",
        cut_why="from just before the apex of the first bounce: the hand releases the ball at the top edge of the "
                "picture, so the fall from the apex (at rest there, as from a hand) is the drop",
        spacing_m=0.0028),
}


def prepare(clip: Clip, mirror: Path, out_dir: Path = CLIP_DIR) -> Path:
    """Cut the clip from the snapshot of its repository (`mirror`/<owner>+<name>/repo, as `fetch` brings it) and
    write it as H.264 at the clip's width and the file's own frame rate: out_dir/<name>.mp4."""
    git_dir = mirror / clip.repo.replace("/", "+") / "repo"
    raw = subprocess.run(["git", "--git-dir", str(git_dir), "show", f"{clip.commit}:{clip.path}"], check=True,
                         capture_output=True).stdout
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / Path(clip.path).name
        src.write_bytes(raw)
        cap = cv2.VideoCapture(str(src))
        fps = float(cap.get(cv2.CAP_PROP_FPS))
        frames, i = [], 0
        while True:
            ok, bgr = cap.read()
            if not ok:
                break
            if clip.first_frame <= i < clip.last_frame:
                h, w = bgr.shape[:2]
                size = (clip.width_px, int(round(h * clip.width_px / w / 2)) * 2)
                frames.append(cv2.cvtColor(cv2.resize(bgr, size, interpolation=cv2.INTER_AREA), cv2.COLOR_BGR2RGB))
            i += 1
        cap.release()
    import imageio.v3 as iio  # ffmpeg

    path = out_dir / f"{clip.name}.mp4"
    iio.imwrite(path, np.stack(frames), fps=fps, codec="libx264", quality=7, macro_block_size=1)
    return path


def write_prior_material(path: Path, prior: Material, physical: PhysicalModel, message: str) -> None:
    """L2's record holding `prior` as the adopted material (what `calibrate` starts from)."""

    AssetDir(path).write_material(MaterialRecord(
        passed=True, status="accepted", message=message, intent="", targets=TargetBehaviour(), material=prior,
        physical_model=physical, metrics={}, held_out=HeldOutSummary(metrics={}, targets_met=None, score=None,
                                                                     bands=[], probes=[]),
        selection=SelectionSummary(status="accepted", score=None, targets_met=True, best_iteration=0, attempts=1,
                                   sim_calls=0, screening={"sim_calls": 0}, ranking=[]),
        sim_calls=0, recordings={}))


def l2_prior(asset_dir: Path) -> Material:
    """L2's prior material for the asset's class (its first proposal, before any probe)."""

    p = l2_targets(load_l0(asset_dir), None).priors
    return Material(youngs_modulus_pa=p["youngs_modulus_pa"], poisson_ratio=p["poisson_ratio"],
                    damping_rate_per_s=p.get("damping_rate_per_s", 0.0))


def sphere_asset(path: Path, clip: Clip, prior: Material, solid: bool = False) -> Path:
    """A sphere of the clip's stated diameter at its stated mass, resting on z = 0, with `prior` as L2's material:
    the files `calibrate` reads. A hollow ball (clip.wall_m, unless `solid`) is its shell: particles only within the
    wall of the surface, at the density that gives the stated mass; otherwise a solid sphere at an effective density
    (the shell's mass over the enclosed volume, as L1 models a hollow ball)."""
    r = 0.5 * clip.size_m
    shell = clip.wall_m is not None and not solid
    spacing = clip.wall_spacing_m if shell else clip.spacing_m
    pos, vol = ball_particles(r, spacing, clip.wall_m if shell else None)
    pos = pos + np.array([0.0, 0.0, r])
    density = clip.mass_kg / float(vol.sum())
    phys = PhysicalModel(density_kg_per_m3=density, volume_m3=float(vol.sum()), mass_kg=clip.mass_kg,
                         particle_count=len(pos), particle_spacing_m=spacing, ground_friction=0.5,
                         gripper_friction=0.8, center_of_mass_m=(0.0, 0.0, r), extents_m=(2 * r, 2 * r, 2 * r),
                         category="ball")
    what = (f"{clip.object}: stated size and mass, a {clip.wall_m * 1e3:g} mm shell" if shell and clip.wall_m
            else f"{clip.object}: stated size and mass")
    path.mkdir(parents=True, exist_ok=True)
    g = zarr.open_group(str(path / PARTICLES_ZARR), mode="w")
    g.create_array("positions_m", data=pos.astype(np.float32))
    g.create_array("volumes_m3", data=vol.astype(np.float32))

    adir = AssetDir(path)
    adir.write_physical(PhysicalRecord(passed=True, status="accepted", message=what,
                                       material_class="rubber", intent="", mass_check={}, targets=TargetBehaviour(),
                                       physical_model=phys, metrics={}, sim_calls=0, attempts=1, recordings=[]))
    write_prior_material(path, prior, phys, "the prior")
    return path


def rel(a: float | None, b: float | None) -> float | None:
    return None if a is None or b is None or not b else a / b - 1.0


def summary(clip: Clip, rec: VideoFitRecord, asset: str, wall_s: float) -> dict[str, Any]:
    """The clip's row: the rebound and the settle time, seen and simulated, their errors, and the fit's figures."""
    r_seen, r_sim = rec.metrics.rebound_ratio, rec.simulated.get("rebound_ratio")
    s_seen, s_sim = rec.metrics.settle_time_s, rec.simulated.get("settle_time_s")
    r_err, s_err = rel(r_sim, r_seen), rel(s_sim, s_seen)
    return {
        "clip": clip.name, "source": f"https://github.com/{clip.repo}/blob/{clip.commit}/{clip.path}",
        "licence": clip.licence, "object": clip.object, "asset": asset,
        "size_m": clip.size_m, "size_source": clip.size_source, "mass_kg": clip.mass_kg,
        "mass_source": clip.mass_source, "cut": [clip.first_frame, clip.last_frame], "cut_why": clip.cut_why,
        "scale": rec.scale.model_dump(mode="json"), "drop_height_m": rec.drop_height_m,
        "fps": rec.track.fps, "frames": rec.track.frames, "frames_tracked": rec.track.frames_tracked,
        "frames_dropped": rec.track.frames_dropped, "frames_at_edge": rec.track.frames_at_edge,
        "frames_repeated": rec.track.frames_repeated, "tracking_confidence": rec.track.tracking_confidence,
        "rebound_seen": r_seen, "rebound_simulated": r_sim, "rebound_error": r_err,
        "restitution_seen": rec.metrics.restitution_from_velocities,
        "settle_time_seen_s": s_seen, "settle_time_simulated_s": s_sim, "settle_time_error": s_err,
        "settle_time_simulated_continuous_s": rec.simulated.get("settle_time_continuous_s"),
        "settle_tolerance_m": rec.metrics.settle_tolerance_m,
        "fitted_youngs_modulus_pa": rec.fitted.youngs_modulus_pa, "youngs_modulus_source": rec.youngs_modulus_source,
        "fitted_viscosity_pa_s": rec.fitted.viscosity_pa_s, "viscosity_source": rec.viscosity_source,
        "fitted_damping_rate_per_s": rec.fitted.damping_rate_per_s, "converged": rec.converged,
        "undetermined": rec.undetermined, "notes": rec.notes, "sim_calls": rec.sim_calls, "wall_s": wall_s,
        "rebound_within_10pct": r_err is not None and abs(r_err) <= TOLERANCE,
        "settle_within_10pct": s_err is not None and abs(s_err) <= TOLERANCE,
        "passed": bool(r_err is not None and abs(r_err) <= TOLERANCE and s_err is not None and abs(s_err) <= TOLERANCE),
    }


def run(clip: Clip, video: Path, asset_dir: Path | None, prior_dir: Path | None, sim: SimConfig,
        record_dir: Path | None = RECORD_DIR, solid: bool = False) -> dict[str, Any]:
    """Calibrate a copy of the asset (never the one given) to the clip; the record goes to record_dir/<name>.json."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="calibrate-real-") as tmp:
        work = Path(tmp) / "asset"
        if asset_dir is not None:
            shutil.copytree(asset_dir, work)
            label = f"{asset_dir.name} (an asset directory)"
            if not (work / "material.json").is_file():
            
                prior = l2_prior(work)
                write_prior_material(work, prior, AssetDir(work).physical_model(), "L2's prior for the class")
                label = (f"{asset_dir.name} (built to L1 by the CLI at draft; L2's prior material for its class: "
                         f"E {prior.youngs_modulus_pa:.3g} Pa, nu {prior.poisson_ratio:g})")
        else:
            prior = load_asset(prior_dir).material if prior_dir is not None else RUBBER_PRIOR
            sphere_asset(work, clip, prior, solid)
            shell = clip.wall_m is not None and not solid
            label = ((f"a hollow sphere at the stated size and mass: a {clip.wall_m * 1e3:g} mm shell, "
                      f"{clip.wall_spacing_m * 1e3:g} mm particle spacing ({clip.wall_why}), prior material "
                      if shell and clip.wall_m is not None else
                      "a solid sphere at the stated size and mass (an effective density), prior material ")
                     + (f"{prior_dir.name}'s adopted L2 material (E {prior.youngs_modulus_pa:.3g} Pa, nu "
                        f"{prior.poisson_ratio:g})" if prior_dir is not None else "rubber (1 MPa)"))
        rec = calibrate_asset(work, video, size_m=clip.size_m, sim=sim, write=False)
    row = summary(clip, rec, label, time.perf_counter() - t0)
    if record_dir is not None:
        record_dir.mkdir(parents=True, exist_ok=True)
        doc = rec.model_dump(mode="json")
        doc["video"] = f"shared/calibration/real/{clip.name}.mp4 (cut from {row['source']})"
        (record_dir / f"{clip.name}.video_fit.json").write_text(json.dumps(doc, indent=1) + "\n")
    return row


def pairs(values: list[str], what: str) -> dict[str, Path]:
    out = {}
    for v in values:
        name, _, path = v.partition("=")
        if name not in CLIPS or not path:
            raise SystemExit(f"error: {what} {v!r}: give CLIP=DIR with CLIP one of {', '.join(CLIPS)}")
        out[name] = Path(path)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--clips", default=",".join(CLIPS), help="comma-separated: " + ", ".join(CLIPS))
    ap.add_argument("--prepare", action="store_true", help="cut the clips from the repositories' snapshots first")
    ap.add_argument("--mirror", type=Path, default=None, help="where the repositories' snapshots are (each as "
                    "<owner>+<name>/repo, a bare git directory); needed with --prepare")
    ap.add_argument("--videos", type=Path, default=CLIP_DIR, help="where the cut clips are")
    ap.add_argument("--asset", action="append", default=[], help="CLIP=DIR: fit this asset directory (a copy)")
    ap.add_argument("--prior-from", action="append", default=[], help="CLIP=DIR: the sphere's prior is DIR's material")
    ap.add_argument("--solid", action="store_true", help="a hollow ball's default asset is a solid sphere at an "
                    "effective density (as L1 models it), not its shell")
    ap.add_argument("--cpu-threads", type=int, default=1)
    ap.add_argument("--no-records", action="store_true", help="do not write docs/calibration/real/<clip>.video_fit.json")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = ap.parse_args(argv)
    names = [c.strip() for c in args.clips.split(",") if c.strip()]
    bad = [n for n in names if n not in CLIPS]
    if bad:
        ap.error(f"unknown clip(s): {', '.join(bad)}")
    if args.prepare and args.mirror is None:
        ap.error("--prepare needs --mirror DIR: the folder holding the source repositories' snapshots")
    assets, priors = pairs(args.asset, "--asset"), pairs(args.prior_from, "--prior-from")
    sim = SimConfig(cpu_threads=args.cpu_threads)
    rows = []
    for n in names:
        video = prepare(CLIPS[n], args.mirror, args.videos) if args.prepare else args.videos / f"{n}.mp4"
        if not video.is_file():
            ap.error(f"{video}: no such clip; cut it first with --prepare")
        rows.append(run(CLIPS[n], video, assets.get(n), priors.get(n), sim, None if args.no_records else RECORD_DIR,
                        args.solid))
    out = {"clips": rows, "passed": sum(r["passed"] for r in rows), "of": len(rows), "tolerance": TOLERANCE,
           "load_average": os.getloadavg()[0]}
    if args.json:
        sys.stdout.write(json.dumps(out, indent=2) + "\n")
    else:
        def f(v: float | None, fmt: str) -> str:
            return "-" if v is None else format(v, fmt)

        for r in rows:
            print(f"{r['clip']}: rebound {f(r['rebound_seen'], '.3f')} seen, {f(r['rebound_simulated'], '.3f')} "
                  f"simulated ({f(r['rebound_error'], '+.1%')}); settle {f(r['settle_time_seen_s'], '.2f')} s seen, "
                  f"{f(r['settle_time_simulated_s'], '.2f')} s simulated ({f(r['settle_time_error'], '+.1%')}); "
                  f"{'ok' if r['passed'] else 'MISS'}")
    return 0 if out["passed"] == out["of"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
