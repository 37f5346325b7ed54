"""Genesis export: a Python scene file with the asset as an MPM neo-Hookean elastic body on a rigid ground plane.

Genesis samples the MPM particles inside the asset's closed surface (the tet mesh's boundary, <slug>_surface.obj) at
DeformSmith's particle spacing; `gs.materials.MPM.Elastic(E=, nu=, rho=, model="neohooken")` (Genesis's spelling) takes
the validated material unchanged. Genesis's MPM elastic material has no damping parameter, so the velocity damping
rate is stated in the file and README and left out of the simulation (the crosscheck's rebound shows the gap).
The scene file needs only genesis-world (GENESIS_INSTALL: no pip extra, its trimesh>=5 clashes with the core's
trimesh<5); writing it needs nothing beyond the core.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from contracts.export import TargetManifest
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files
from tasks.export.tetmesh import surface_of

SCENE = "scene.py"
GENESIS_INSTALL = ("pip install torch==2.13.0 (a CPU build; else pip pulls a CUDA torch of several GB), then "
                   "pip install genesis-world==1.4.5, then pip install 'trimesh>=4.4,<5' (genesis-world asks for "
                   "trimesh>=5, the core pins <5; the scene runs with 4.12)")
MAPPING = ""  # neo-Hookean to neo-Hookean ('neohooken' in Genesis): identical
DAMPING = ("not exported: Genesis's MPM.Elastic has no damping parameter (our velocity damping rate "
           "{rate:.4g} 1/s is recorded in scene.py's PARAMS for reference)")
LOAD_HINT = "python scene.py  (or: import scene; scene.build_scene() -> (gs.Scene, MPM entity); needs genesis-world)"

SCENE_TEMPLATE = '''"""DeformSmith export of {name} for Genesis: an MPM neo-Hookean elastic body on a rigid ground plane (SI units).

    python scene.py [--steps N] [--cpu]     # builds the scene and steps it (1 s by default), prints the lowest z
"""

import argparse
import os

import genesis as gs

HERE = os.path.dirname(os.path.abspath(__file__))
PARAMS = {params}


def build_scene(show_viewer=False, young_pa=None, cpu=True, lift_m=None):
    """(scene, body): the asset with its lowest point lift_m above the ground (default {lift_mm:.1f} mm), as
    DeformSmith validated it; young_pa overrides E (calibration)."""
    if not gs._initialized:
        gs.init(backend=gs.cpu if cpu else gs.gpu, logging_level="warning")
    p = PARAMS
    lo, hi = p["domain_lower_m"], p["domain_upper_m"]
    scene = gs.Scene(
        sim_options=gs.options.SimOptions(dt=p["dt_s"], substeps=p["substeps"]),
        mpm_options=gs.options.MPMOptions(lower_bound=tuple(lo), upper_bound=tuple(hi),
                                          grid_density=p["grid_density_per_m"],
                                          particle_size=p["particle_size_m"]),
        show_viewer=show_viewer)
    scene.add_entity(gs.morphs.Plane(), material=gs.materials.Rigid(friction=p["ground_friction"]))
    body = scene.add_entity(
        gs.morphs.Mesh(file=os.path.join(HERE, p["surface_file"]),
                       pos=(0.0, 0.0, p["lift_m"] if lift_m is None else lift_m - p["surface_min_z_m"])),
        material=gs.materials.MPM.Elastic(E=young_pa or p["youngs_modulus_pa"], nu=p["poisson_ratio"],
                                          rho=p["density_kg_per_m3"], model="neohooken"))
    scene.build()
    return scene, body


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
        "damping_rate_per_s_not_simulated": m.damping_rate_per_s,
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
    from contracts.errors import InputError
    from tasks.asset_dir import AssetDir
    from tasks.export.mujoco_scene import mean_edge_m

    try:
        return float(AssetDir(Path(inputs.asset_dir)).physical_model().particle_spacing_m)
    except (InputError, OSError):
        return 0.5 * mean_edge_m(inputs.tet.nodes_m, inputs.tet.tets)


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """scene.py, <slug>_surface.obj (the tet mesh's boundary), params.json, the tet mesh files and a README."""
    out_dir.mkdir(parents=True, exist_ok=True)
    params = scene_params(inputs, particle_spacing_m(inputs))
    verts, faces = surface_of(inputs.tet)
    write_obj(out_dir / str(params["surface_file"]), verts, faces)
    (out_dir / SCENE).write_text(SCENE_TEMPLATE.format(name=inputs.slug, params=json.dumps(params, indent=4),
                                                       lift_mm=1.0), encoding="utf-8")
    (out_dir / "params.json").write_text(json.dumps(params, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    mesh_files = write_tet_files(inputs, out_dir)
    damping = DAMPING.format(rate=inputs.material.damping_rate_per_s)
    readme = write_readme(out_dir, "Genesis", LOAD_HINT, [
        f"{SCENE}: gs.materials.MPM.Elastic(E={inputs.material.youngs_modulus_pa:.6g}, "
        f"nu={inputs.material.poisson_ratio:.4g}, rho={inputs.material.density_kg_per_m3:.6g}, model='neohooken') "
        f"filling {params['surface_file']} (particle size {params['particle_size_m']} m, as DeformSmith's), "
        "on gs.morphs.Plane() (rigid, the ground friction).",
        f"Damping: {damping}.",
        "Genesis compiles its kernels on the first build (minutes on a CPU); later builds reuse its cache.",
        f"Install: {GENESIS_INSTALL}."])
    return TargetManifest(target="genesis", files=[SCENE, str(params["surface_file"]), "params.json", *mesh_files,
                                                   readme],
                          load_hint=LOAD_HINT, material=inputs.material, mapping=MAPPING, damping_mapping=damping)


__all__ = ["DAMPING", "GENESIS_INSTALL", "LOAD_HINT", "SCENE", "export", "scene_params", "write_obj"]
