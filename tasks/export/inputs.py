"""What every export target reads from an asset directory: the validated material, the tet mesh, surface, Gaussians."""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cache import CacheMiss, CacheStore, cache_root, content_key
from contracts.errors import InputError
from contracts.export import ExportMaterial
from tasks.asset_dir import AssetDir
from tasks.export.tetmesh import TetMesh, enclosed_volume_m3, tet_quality, tetrahedralize, write_msh, write_vtk
from tasks.export.wall import homogenised_wall
from tasks.geometry.gaussians import GaussianSet
from tasks.geometry.outputs import load_l0

TETMESH_VERSION = "3"  # bump when tetrahedralize's output for the same surface changes (3: isosurface stuffing)


@dataclass
class ExportInputs:
    """An asset as the exporters see it (asset frame: z up, resting on z = 0, metres)."""

    asset_dir: Path
    material: ExportMaterial
    tet: TetMesh
    surface_vertices_m: np.ndarray   # (V, 3) the L0 surface mesh (particles.zarr/surface_mesh), float64
    surface_faces: np.ndarray        # (F, 3) int64
    gaussians: GaussianSet | None    # rest Gaussians (positions_m, colors 0..1, ...) or None without gaussians.ply
    surface_colors: np.ndarray | None = None  # (V, 4) uint8 vertex colours of the surface mesh
    name: str = "asset"              # the asset's name (L0 build info), for file and body names
    particles_m: np.ndarray | None = None         # (P, 3) L0 particle rest positions (particles.zarr)
    particle_volumes_m3: np.ndarray | None = None  # (P,)

    @property
    def slug(self) -> str:
        """The name as a file / body identifier: letters, digits and underscores."""
        return re.sub(r"[^A-Za-z0-9_]+", "_", self.name).strip("_") or "asset"


def write_tet_files(inputs: ExportInputs, out_dir: Path) -> list[str]:
    """The tet mesh as <slug>.vtk and <slug>.msh in out_dir; their names (relative to out_dir)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    write_vtk(inputs.tet, out_dir / f"{inputs.slug}.vtk")
    write_msh(inputs.tet, out_dir / f"{inputs.slug}.msh")
    return [f"{inputs.slug}.vtk", f"{inputs.slug}.msh"]


def write_tetmesh_dir(inputs: ExportInputs, out_dir: Path) -> dict[str, float]:
    """The export's tetmesh/ folder: the .vtk, .msh, quality.json (tet_quality and the volume against the surface's)
    and a README; returns the quality figures."""
    write_tet_files(inputs, out_dir)
    quality = tet_quality(inputs.tet)
    surface_volume = abs(enclosed_volume_m3(inputs.surface_vertices_m, inputs.surface_faces))
    quality["surface_volume_m3"] = surface_volume
    quality["volume_error_rel"] = abs(quality["volume_m3"] - surface_volume) / surface_volume
    (out_dir / "quality.json").write_text(json.dumps(quality, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    write_readme(out_dir, "tet mesh", f"meshio.read('{inputs.slug}.msh') or meshio.read('{inputs.slug}.vtk')", [
        "Linear tetrahedra (isosurface stuffing, deterministic), positively oriented; quality figures in quality.json."])
    return quality


def write_readme(out_dir: Path, target: str, load_hint: str, lines: Sequence[str] = (),
                 material: ExportMaterial | None = None) -> str:
    """README.md of an export folder: the load line first, then notes (and, for a pressurised shell's `material`,
    what its Young's modulus is: material_lines); returns its name."""
    body = [f"# {target} export (DeformSmith)", "", f"Load: {load_hint}", "",
            "Units: SI (metres, kilograms, seconds, pascals); frame z up, the object resting on z = 0.", "", *lines,
            *(material_lines(material) if material is not None else [])]
    (out_dir / "README.md").write_text("\n".join(body).rstrip() + "\n", encoding="utf-8")
    return "README.md"


def material_lines(material: ExportMaterial) -> list[str]:
    """README lines on the exported material: for a pressurised shell, that its Young's modulus is the homogenised
    wall's, with the rubber's and the gas's; none for any other material."""
    w = material.homogenised_wall
    if w is None:
        return []
    pressure = (f" at a gauge pressure of {w.gauge_pressure_pa:.4g} Pa ({w.gauge_pressure_source})"
                if w.gauge_pressure_pa is not None else "")
    return ["", f"Young's modulus: {w.wall_modulus_pa:.6g} Pa is a pressurised shell's homogenised wall modulus, the "
            f"rubber's {w.rubber_youngs_modulus_pa:.6g} Pa plus {w.gas_modulus_pa:.6g} Pa for its inflation gas"
            f"{pressure}; a homogenised equivalent of the gas, not a gas simulation. This export is a solid body at "
            "the wall's modulus (the asset simulates the shell's wall at it), stiffer than the hollow ball."]


def export_material(adir: AssetDir) -> ExportMaterial:
    """The asset's adopted material (AssetDir.adopted_material) with L1's density, mass and friction (InputError when
    L2 did not pass). The export is a solid tet mesh of the surface: a hollow object whose particles are its shell
    (geometry.json `particles`) goes out at its mass over the enclosed volume (an effective density), so that it
    weighs what the asset weighs. A pressurised shell (a material with a gas modulus) goes out at its wall's modulus,
    the rubber's E plus the gas's, as DeformSmith simulates its wall, recorded as such (`homogenised_wall`,
    tasks.realworld.inflation.homogenised_wall); note that the tet mesh is then a solid body at the wall's modulus,
    stiffer than the shell it stands for."""
    record = adir.material()
    if record.material is None or not record.passed:
        raise InputError(f"{adir.file('material')}: L2 did not validate a material ({record.message or 'failed'}); "
                         "only a validated material is exported")
    physical = adir.physical_model()
    m = adir.adopted_material().material
    body = adir.geometry().particles
    density = physical.mass_kg / body.enclosed_volume_m3 if body is not None and body.shell \
        else physical.density_kg_per_m3
    # a pressurised shell (a gas modulus): exported at its wall's modulus, and says so
    wall = homogenised_wall(m, record.inflation) if m.gas_modulus_pa else None
    return ExportMaterial(youngs_modulus_pa=m.youngs_modulus_pa if wall is None else wall.wall_modulus_pa,
                          poisson_ratio=m.poisson_ratio,
                          density_kg_per_m3=density, damping_rate_per_s=m.damping_rate_per_s,
                          viscosity_pa_s=m.viscosity_pa_s,
                          ground_friction=physical.ground_friction, gripper_friction=physical.gripper_friction,
                          mass_kg=physical.mass_kg, **({"homogenised_wall": wall} if wall is not None else {}))


def cached_tet_mesh(vertices_m: np.ndarray, faces: np.ndarray, edge_length_m: float | None = None) -> TetMesh:
    """tetrahedralize, cached in the content cache by the surface, the edge length and TETMESH_VERSION."""
    v = np.ascontiguousarray(vertices_m, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    key = content_key("export.tetmesh", TETMESH_VERSION, v, f, edge_length_m)
    store = CacheStore(cache_root())
    try:
        hit = store.get(key)
        return TetMesh(nodes_m=np.asarray(hit["nodes_m"]), tets=np.asarray(hit["tets"]))
    except CacheMiss:
        pass
    tet = tetrahedralize(v, f, edge_length_m=edge_length_m)
    store.put(key, {"nodes_m": tet.nodes_m, "tets": tet.tets}, meta={"task": "export.tetmesh"})
    return tet


def load_export_inputs(asset_dir: Path, *, edge_length_m: float | None = None) -> ExportInputs:
    """Read an asset directory through the typed readers and build (or fetch from the cache) its tet mesh."""
    adir = AssetDir(Path(asset_dir))
    if not Path(asset_dir).is_dir():
        raise InputError(f"{asset_dir} is not a directory")
    material = export_material(adir)
    l0 = load_l0(adir.path)
    vertices = np.asarray(l0.mesh.vertices, dtype=np.float64)
    faces = np.asarray(l0.mesh.faces, dtype=np.int64)
    colors = np.asarray(l0.mesh.visual.vertex_colors, dtype=np.uint8) if hasattr(l0.mesh.visual, "vertex_colors") \
        else None
    gaussians = GaussianSet(l0.gaussians) if l0.gaussians else None
    name = str((l0.record.get("info") or {}).get("name") or Path(asset_dir).resolve().name)
    return ExportInputs(asset_dir=Path(asset_dir), material=material, tet=cached_tet_mesh(vertices, faces, edge_length_m),
                        surface_vertices_m=vertices, surface_faces=faces, gaussians=gaussians, surface_colors=colors,
                        name=name, particles_m=np.asarray(l0.particles_m, dtype=np.float64),
                        particle_volumes_m3=np.asarray(l0.volumes_m3, dtype=np.float64))
