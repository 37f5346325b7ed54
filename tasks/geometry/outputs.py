"""Write an L0 result into a directory, and load it back (the API later layers use)."""

from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
import zarr

from cache.tempfiles import dead_partials, owner_tag, remove_paths
from contracts.errors import InputError
from tasks.geometry.checks import GeometryChecks
from tasks.geometry.collision import write_collision
from tasks.geometry.gaussians import read_3dgs_ply, rest_covariances, write_3dgs_ply
from tasks.geometry.glb import write_glb
from tasks.geometry.pipeline import Arrays, BuildInfo, arrays_to_mesh, proxy_parts
from contracts.asset_dir import GEOMETRY_JSON, GeometryRecord, ParticleBody
from tasks.asset_dir import AssetDir, document_json
from tasks.publish import replace_directory
from tasks.render.finish import finish_for
from tasks.render.views import write_renders

PARTICLES = "particles.zarr"


def write_outputs(
    out_dir: Path, mesh: Arrays, proxy: Arrays, particles: Arrays, gaussians: Arrays, info: BuildInfo,
    checks: GeometryChecks, extra: dict | None = None,
) -> dict[str, str]:
    """mesh.glb, collision/, particles.zarr, gaussians.ply, renders/*.png and geometry.json into out_dir."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    m = arrays_to_mesh(mesh)
    write_glb(m, out_dir / "mesh.glb")
    urdf = write_collision(proxy_parts(proxy), m, out_dir / "collision", info.name)
    g = zarr.open_group(str(out_dir / PARTICLES), mode="w")
    for k in ("positions_m", "volumes_m3", "colors"):
        g.create_array(k, data=np.ascontiguousarray(particles[k]))
    g.attrs.update({"spacing_m": float(particles["spacing_m"]), "units": "SI: metres, cubic metres",
                    "frame": "z up, resting on z = 0, centred in x, y"})
    b = g.create_group("gaussian_binding")  # the Gaussians themselves (positions, scales, rotations) are gaussians.ply's
    for k in ("particle_index", "particle_weight"):
        b.create_array(k, data=np.ascontiguousarray(gaussians[k]))
    s = g.create_group("surface_mesh")  # the aligned mesh in the asset frame (z up), for code that needs it exactly
    for k in ("vertices", "faces", "colors"):
        s.create_array(k, data=np.ascontiguousarray(mesh[k]))
    write_3dgs_ply(gaussians, out_dir / "gaussians.ply")  # type: ignore[arg-type]
    material = info.concept.default_material if info.concept else None
    look = info.concept.finish if info.concept else None
    renders = write_renders(m, out_dir / "renders", finish=finish_for(material, info.category, look))
    files = {"mesh": "mesh.glb", "urdf": f"collision/{urdf.name}", "particles": PARTICLES, "gaussians": "gaussians.ply",
             **{f"render_{k}": f"renders/{v}" for k, v in renders.items()}}
    record = {"schema_version": 1, "info": info.model_dump(mode="json", exclude={"design_attempts"}),  # -> evidence/
              "metrics": checks.metrics,
              "gates": [gr.model_dump(mode="json") for gr in checks.gates], "passed": checks.passed,
              "failed_gates": checks.failed, "warnings": info.warnings, "files": files, **(extra or {})}
    AssetDir(out_dir).write_geometry(GeometryRecord.model_validate(record))
    return files


def publish_dir(build, out_dir: Path) -> None:
    """Run build(tmp_dir) and rename tmp_dir into out_dir; on any error nothing is left behind."""
    out_dir = Path(out_dir).resolve()
    if out_dir.exists() and any(out_dir.iterdir()) and not (out_dir / GEOMETRY_JSON).exists():
        raise InputError(f"{out_dir} exists and is not an L0 output directory; choose an empty or new directory")
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    remove_paths(dead_partials(out_dir.parent, out_dir.name))  # what a killed run of this output left
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.tmp-{owner_tag()}", dir=out_dir.parent))
    try:
        build(tmp)
        replace_directory(tmp, out_dir)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


@dataclass(frozen=True)
class L0Asset:
    """An L0 output loaded back, in the asset frame (z up, resting on z = 0, metres)."""

    mesh: trimesh.Trimesh                 # watertight, vertex colours
    particles_m: np.ndarray               # (N, 3) rest positions [m]
    volumes_m3: np.ndarray                # (N,), sums to mesh.volume (a hollow object's shell: the shell's) [m^3]
    particle_colors: np.ndarray           # (N, 3) uint8
    spacing_m: float                      # lattice spacing [m]
    urdf: Path                            # convex collision proxy for pybullet
    proxy_parts: list[trimesh.Trimesh]    # convex parts
    gaussians: dict[str, np.ndarray]      # rest Gaussians from gaussians.ply (+ binding arrays)
    record: dict                          # geometry.json

    @property
    def body(self) -> ParticleBody | None:
        """What the particles fill (geometry.json `particles`): the solid or a hollow object's shell; None in records
        written before session 32 (solid)."""
        rec = self.record.get("particles")
        return ParticleBody.model_validate(rec) if rec else None

    @property
    def shell(self) -> bool:
        """True when the particles are a hollow object's wall alone (their volumes sum to the shell's)."""
        return self.body is not None and self.body.shell

    def gaussian_covariances(self) -> np.ndarray:
        """Rest covariances (G, 3, 3) [m^2] of the Gaussians."""
        return rest_covariances(self.gaussians["scales_m"], self.gaussians["rotations_wxyz"])


def load_l0(out_dir: Path) -> L0Asset:
    """Load an L0 directory written by write_outputs."""
    d = Path(out_dir)
    record = document_json(AssetDir(d).geometry())  # validated; InputError naming geometry.json
    g = zarr.open_group(str(d / PARTICLES), mode="r")
    s = g["surface_mesh"]
    mesh = arrays_to_mesh({k: np.asarray(s[k][...]) for k in ("vertices", "faces", "colors")})
    gs = dict(read_3dgs_ply(d / "gaussians.ply"))
    for k in ("particle_index", "particle_weight"):
        gs[k] = np.asarray(g["gaussian_binding"][k][...])
    urdf = d / record["files"]["urdf"]
    parts = [trimesh.load(p, force="mesh") for p in sorted((d / "collision").glob("part_*.obj"))]
    return L0Asset(mesh=mesh, particles_m=np.asarray(g["positions_m"][...]), volumes_m3=np.asarray(g["volumes_m3"][...]),
                   particle_colors=np.asarray(g["colors"][...]), spacing_m=float(g.attrs["spacing_m"]), urdf=urdf,
                   proxy_parts=parts, gaussians=gs, record=record)
