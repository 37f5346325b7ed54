"""Genesis export: a Python scene file with the asset as an MPM neo-Hookean elastic body on a rigid ground plane.

Genesis samples the MPM particles inside the asset's closed surface (the tet mesh's boundary, <slug>_surface.obj) at
DeformSmith's particle spacing; `gs.materials.MPM.Elastic(E=, nu=, rho=, model="neohooken")` (Genesis's spelling) takes
the validated material unchanged. Genesis's MPM materials and MPMOptions have no damping parameter; DeformSmith's
velocity damping (v *= exp(-rate dt) on its grid velocities, every substep, after gravity) is Genesis's public
`gs.force_fields.Drag(linear=rate)` added to the scene: Genesis's MPM grid update applies scene force fields to the
grid velocities every substep right after gravity (acceleration -rate v, i.e. v *= 1 - rate dt_sub), the same scheme
to O((rate dt_sub)^2) (< 1e-5 on the benchmark assets), and a plain scene.step() runs it. Genesis compiles the rate
into its grid kernel, so each new rate costs a kernel compile (~10-30 s on a CPU; a calibration tries a handful). The
ground plane's MPM coupling friction (coup_friction) is the asset's ground friction.
The scene file needs only genesis-world (GENESIS_INSTALL: no pip extra, its trimesh>=5 clashes with the core's
trimesh<5); writing it needs nothing beyond the core.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from contracts.errors import InputError
from contracts.export import TargetManifest
from tasks.asset_dir import AssetDir
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files
from tasks.export.mujoco_scene import mean_edge_m
from tasks.export.tetmesh import surface_of

SCENE = "scene.py"
CALIBRATED_SCENE = "scene_calibrated.py"
GENESIS_INSTALL = ("pip install torch==2.13.0 (a CPU build; else pip pulls a CUDA torch of several GB), then "
                   "pip install genesis-world==1.4.5, then pip install 'trimesh>=4.4,<5' (genesis-world asks for "
                   "trimesh>=5, the core pins <5; the scene runs with 4.12)")
MAPPING = ""  # neo-Hookean to neo-Hookean ('neohooken' in Genesis): identical
DAMPING = ("velocity damping rate {rate:.4g} 1/s (PARAMS['damping_rate_per_s']) as gs.force_fields.Drag(linear=rate) "
           "on the MPM grid, every substep after gravity, as DeformSmith's grid damping v *= exp(-rate dt) (Genesis's "
           "MPM materials have no damping parameter)")
LOAD_HINT = "python scene.py  (or: import scene; scene.build_scene() -> (gs.Scene, MPM entity); needs genesis-world)"

SCENE_TEMPLATE = '''"""DeformSmith export of {name} for Genesis: an MPM neo-Hookean elastic body on a rigid ground plane (SI units).
{note}
    python {file} [--steps N] [--gpu]     # builds the scene and steps it (1 s by default), prints the lowest z

Damping: Genesis's MPM materials have none; DeformSmith's velocity damping (v *= exp(-rate dt) on its grid velocities,
every substep after gravity) is gs.force_fields.Drag(linear=PARAMS["damping_rate_per_s"]), which Genesis applies to
the MPM grid velocities every substep right after gravity (v *= 1 - rate dt_sub). It acts on every MPM entity of the
scene.
"""

import argparse
import math
import os

import genesis as gs

HERE = os.path.dirname(os.path.abspath(__file__))
PARAMS = {params}


def _init(cpu):
    if not gs._initialized:
        gs.init(backend=gs.cpu if cpu else gs.gpu, logging_level="warning")


def _scene(young_pa, cpu, lift_m, ground_friction, show_viewer, damping_rate_per_s):
    _init(cpu)
    p = PARAMS
    lo, hi = p["domain_lower_m"], p["domain_upper_m"]
    young = young_pa or p["youngs_modulus_pa"]
    # a stiffer E than exported needs more substeps for the same CFL number (wave speed ~ sqrt(E))
    substeps = max(p["substeps"], math.ceil(p["substeps"] * math.sqrt(young / p["youngs_modulus_pa"]) - 1e-9))
    scene = gs.Scene(
        sim_options=gs.options.SimOptions(dt=p["dt_s"], substeps=substeps),
        mpm_options=gs.options.MPMOptions(lower_bound=tuple(lo), upper_bound=tuple(hi),
                                          grid_density=p["grid_density_per_m"],
                                          particle_size=p["particle_size_m"]),
        show_viewer=show_viewer)
    mu = p["ground_friction"] if ground_friction is None else ground_friction
    # coup_friction: the friction of the MPM grid against the plane (friction is for rigid-rigid contacts)
    scene.add_entity(gs.morphs.Plane(), material=gs.materials.Rigid(friction=max(mu, 0.01), coup_friction=mu))
    body = scene.add_entity(
        gs.morphs.Mesh(file=os.path.join(HERE, p["surface_file"]),
                       pos=(0.0, 0.0, p["lift_m"] if lift_m is None else lift_m - p["surface_min_z_m"])),
        material=gs.materials.MPM.Elastic(E=young, nu=p["poisson_ratio"],
                                          rho=p["density_kg_per_m3"], model="neohooken"))
    rate = p["damping_rate_per_s"] if damping_rate_per_s is None else damping_rate_per_s
    if rate > 0.0:
        scene.add_force_field(gs.force_fields.Drag(linear=rate)).activate()
    return scene, body


def build_scene(show_viewer=False, young_pa=None, cpu=True, lift_m=None, ground_friction=None,
                damping_rate_per_s=None):
    """(scene, body): the asset with its lowest point lift_m above the ground (default {lift_mm:.1f} mm), as
    DeformSmith validated it; young_pa / ground_friction / damping_rate_per_s override PARAMS (calibration)."""
    scene, body = _scene(young_pa, cpu, lift_m, ground_friction, show_viewer, damping_rate_per_s)
    scene.build()
    return scene, body


def build_plate_scene(plate_half_m, plate_pos_m, young_pa=None, cpu=True, lift_m=None, damping_rate_per_s=None):
    """(scene, body, plate): the asset on a frictionless ground under a frictionless rigid box plate (a free body,
    gravity compensated, 10^6 kg/m^3, a hard MPM contact: move it with move_plate before each step), for the
    compression probe."""
    scene, body = _scene(young_pa, cpu, lift_m, 0.0, False, damping_rate_per_s)
    plate = scene.add_entity(
        gs.morphs.Box(pos=tuple(plate_pos_m), size=tuple(2.0 * h for h in plate_half_m)),
        material=gs.materials.Rigid(rho=1.0e6, friction=0.01, coup_friction=0.0, coup_softness=1e-4,
                                    gravity_compensation=1.0))
    scene.build()
    return scene, body, plate


def move_plate(plate, z_m, vz_m_per_s):
    """Put the plate's centre at height z_m with vertical velocity vz_m_per_s (the MPM coupling sees that velocity)."""
    x, y = (float(c) for c in plate.get_pos()[:2])
    plate.set_pos((x, y, z_m), zero_velocity=True)
    plate.set_dofs_velocity((0.0, 0.0, vz_m_per_s, 0.0, 0.0, 0.0))


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=int(round(1.0 / PARAMS["dt_s"])))
    ap.add_argument("--gpu", action="store_true")
    a = ap.parse_args()
    scene, body = build_scene(cpu=not a.gpu)
    for _ in range(a.steps):
        scene.step()
    z = body.get_particles_pos()[..., 2]
    print("lowest particle z [m]:", float(z.min()))
'''


def scene_params(inputs: ExportInputs, spacing_m: float) -> dict[str, object]:
    """The numbers scene.py uses (SI): material, particle size, MPM domain and grid, step."""
    m = inputs.material
    nodes = inputs.tet.nodes_m
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    size = float(np.max(hi - lo))
    pad = max(0.5 * size, 0.05)
    lift = 1e-3 - float(lo[2])
    dx = 2.0 * spacing_m  # DeformSmith's grid cell: twice the particle spacing
    nu = m.poisson_ratio
    p_modulus = m.youngs_modulus_pa * (1 - nu) / ((1 + nu) * (1 - 2 * nu))  # the P-wave modulus lambda + 2 mu
    c = float(np.sqrt(p_modulus / m.density_kg_per_m3))  # (3 x the bar speed at nu = 0.48: a rubber ball)
    dt = 2e-3
    substeps = int(max(10, np.ceil(dt / (0.4 * dx / c))))  # CFL 0.4 per substep
    return {
        "youngs_modulus_pa": m.youngs_modulus_pa, "poisson_ratio": m.poisson_ratio,
        "density_kg_per_m3": m.density_kg_per_m3, "mass_kg": m.mass_kg, "ground_friction": m.ground_friction,
        "damping_rate_per_s": m.damping_rate_per_s,
        "viscosity_pa_s": m.viscosity_pa_s,  # recorded, not applied: Genesis's elastic MPM has no viscous stress
        "particle_size_m": spacing_m, "grid_density_per_m": round(1.0 / dx, 6),
        # Genesis keeps its MPM particles 3 grid cells inside the domain: the floor of that box sits half a cell
        # under the ground plane, which is the contact
        "domain_lower_m": [float(lo[0] - pad - 3 * dx), float(lo[1] - pad - 3 * dx), -3.5 * dx],
        "domain_upper_m": [float(hi[0] + pad + 3 * dx), float(hi[1] + pad + 3 * dx),
                           float(hi[2] - lo[2] + pad + lift + 3 * dx)],
        "dt_s": dt, "substeps": substeps, "lift_m": lift, "surface_file": f"{inputs.slug}_surface.obj",
        "surface_min_z_m": float(lo[2]), "height_m": float(hi[2] - lo[2]),
    }


def write_obj(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    """A triangle mesh as Wavefront OBJ (1-based indices)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in np.asarray(vertices, np.float64)]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces, np.int64)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def particle_spacing_m(inputs: ExportInputs) -> float:
    """DeformSmith's particle spacing (physical.json), Genesis's particle size; half the mean tet edge without L1."""
    try:
        return float(AssetDir(Path(inputs.asset_dir)).physical_model().particle_spacing_m)
    except (InputError, OSError):
        return 0.5 * mean_edge_m(inputs.tet.nodes_m, inputs.tet.tets)


def write_scene(path: Path, params: Mapping[str, Any], name: str, note: str = "") -> None:
    """scene.py (or a calibrated copy) for the given PARAMS; the surface mesh must lie beside it."""
    path.write_text(SCENE_TEMPLATE.format(name=name, params=json.dumps(params, indent=4), lift_mm=1.0,
                                          file=path.name, note=f"\n{note}\n" if note else ""), encoding="utf-8")


def calibrated_params(params: Mapping[str, Any], young_pa: float, damping_rate_per_s: float) -> dict[str, Any]:
    """PARAMS with the calibrated Young's modulus and damping rate; a stiffer E gets more substeps (same CFL)."""
    e0, n0 = float(params["youngs_modulus_pa"]), int(params["substeps"])
    substeps = max(n0, math.ceil(n0 * math.sqrt(young_pa / e0) - 1e-9))
    return {**params, "youngs_modulus_pa": float(young_pa), "damping_rate_per_s": float(damping_rate_per_s),
            "substeps": substeps}


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """scene.py, <slug>_surface.obj (the tet mesh's boundary), params.json, the tet mesh files and a README."""
    out_dir.mkdir(parents=True, exist_ok=True)
    params = scene_params(inputs, particle_spacing_m(inputs))
    verts, faces = surface_of(inputs.tet)
    write_obj(out_dir / str(params["surface_file"]), verts, faces)
    write_scene(out_dir / SCENE, params, inputs.slug)
    (out_dir / "params.json").write_text(json.dumps(params, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    mesh_files = write_tet_files(inputs, out_dir)
    damping = DAMPING.format(rate=inputs.material.damping_rate_per_s)
    readme = write_readme(out_dir, "Genesis", LOAD_HINT, [
        f"{SCENE}: gs.materials.MPM.Elastic(E={inputs.material.youngs_modulus_pa:.6g}, "
        f"nu={inputs.material.poisson_ratio:.4g}, rho={inputs.material.density_kg_per_m3:.6g}, model='neohooken') "
        f"filling {params['surface_file']} (particle size {params['particle_size_m']} m, as DeformSmith's), "
        "on gs.morphs.Plane() (rigid; its MPM coupling friction is the ground friction).",
        f"Damping: {damping}.",
        "Genesis compiles its kernels on the first build (minutes on a CPU); later builds reuse its cache.",
        f"Install: {GENESIS_INSTALL}."], material=inputs.material)
    return TargetManifest(target="genesis", files=[SCENE, str(params["surface_file"]), "params.json", *mesh_files,
                                                   readme],
                          load_hint=LOAD_HINT, material=inputs.material, mapping=MAPPING, damping_mapping=damping)


__all__ = ["CALIBRATED_SCENE", "DAMPING", "GENESIS_INSTALL", "LOAD_HINT", "SCENE", "calibrated_params", "export",
           "scene_params", "write_obj", "write_scene"]
