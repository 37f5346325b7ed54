"""Export an asset to simulators: every target folder is built in a temporary directory and renamed into place.

    export_asset(asset_dir, ["usd", "drake"])   # -> ExportManifest; DIR/export/{tetmesh,usd,drake}/ + manifest.json

No Prefect flow: the work is file writing plus one cached tet mesh (tasks.export.inputs.cached_tet_mesh), so the
command starts no server. A target whose package is missing, or a bad asset directory, fails before anything is
written; a target that fails midway leaves the earlier export untouched.
"""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path

from pydantic import ValidationError

from cache.tempfiles import dead_partials, owner_tag, remove_paths
from contracts.errors import InputError
from contracts.export import ExportManifest, TargetManifest
from tasks.export.inputs import ExportInputs, load_export_inputs, write_readme, write_tet_files
from tasks.export.registry import exporter, resolve_targets
from tasks.export.tetmesh import tet_quality
from tasks.publish import replace_directory, write_text_atomic

MANIFEST = "manifest.json"
TETMESH_DIR = "tetmesh"


def _old_manifest(out_root: Path) -> ExportManifest | None:
    """The manifest an earlier export left (None when absent or unreadable: it is then rewritten)."""
    try:
        return ExportManifest.model_validate_json((out_root / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValidationError):
        return None


def _write_tetmesh_dir(inputs: ExportInputs, out_dir: Path) -> dict[str, float]:
    """tetmesh/: the .vtk, .msh, quality.json and a README; returns the quality figures."""
    write_tet_files(inputs, out_dir)
    quality = tet_quality(inputs.tet)
    surface_volume = float(abs(_surface_volume(inputs)))
    quality["surface_volume_m3"] = surface_volume
    quality["volume_error_rel"] = abs(quality["volume_m3"] - surface_volume) / surface_volume
    (out_dir / "quality.json").write_text(json.dumps(quality, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    write_readme(out_dir, "tet mesh", f"meshio.read('{inputs.slug}.msh') or meshio.read('{inputs.slug}.vtk')", [
        "Linear tetrahedra (isosurface stuffing, deterministic), positively oriented; quality figures in quality.json."])
    return quality


def _surface_volume(inputs: ExportInputs) -> float:
    """Enclosed volume of the L0 surface mesh [m^3] (divergence theorem)."""
    import numpy as np

    p = inputs.surface_vertices_m[inputs.surface_faces]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def export_asset(asset_dir: Path, to: str | list[str], out_root: Path | None = None,
                 edge_length_m: float | None = None) -> ExportManifest:
    """Export asset_dir to the named targets under out_root (default asset_dir/export); returns the manifest."""
    asset_dir = Path(asset_dir)
    if not asset_dir.is_dir():
        raise InputError(f"{asset_dir} is not an asset directory")
    names = resolve_targets(to) if isinstance(to, str) else resolve_targets(",".join(to))
    exporters = {n: exporter(n) for n in names}  # a missing package fails here, before any work
    inputs = load_export_inputs(asset_dir, edge_length_m=edge_length_m)
    out_root = Path(out_root) if out_root is not None else asset_dir / "export"
    created = not out_root.exists()
    out_root.mkdir(parents=True, exist_ok=True)
    remove_paths(dead_partials(out_root, "export"))  # what a killed export left
    work = Path(tempfile.mkdtemp(prefix=f".export.tmp-{owner_tag()}", dir=out_root))
    try:
        _write_tetmesh_dir(inputs, work / TETMESH_DIR)
        built: dict[str, TargetManifest] = {}
        for name, export in exporters.items():
            folder = work / name
            folder.mkdir()
            target = export(inputs, folder)
            missing = [f for f in target.files if not (folder / f).exists()]
            if missing:
                raise RuntimeError(f"export {name} lists files it did not write: {missing}")
            built[name] = target.model_copy(update={"files": [f"{name}/{f}" for f in target.files]})
        for name in [TETMESH_DIR, *built]:
            replace_directory(work / name, out_root / name)
        old = _old_manifest(out_root)
        targets = {**(old.targets if old else {}), **built}
        manifest = ExportManifest(asset=str(asset_dir.resolve()), tet_mesh=f"{TETMESH_DIR}/{inputs.slug}.vtk",
                                  targets=targets)
        write_text_atomic(out_root / MANIFEST, manifest.model_dump_json(indent=2) + "\n")
        return manifest
    finally:
        shutil.rmtree(work, ignore_errors=True)
        if created and not any(out_root.iterdir()):  # a failed first export leaves no empty folder either
            out_root.rmdir()
