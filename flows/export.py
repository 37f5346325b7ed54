"""Export an asset to simulators: every target folder is built in a temporary directory and renamed into place.

    export_asset(asset_dir, ["usd", "drake"])   # -> ExportManifest; DIR/export/{tetmesh,usd,drake}/ + manifest.json

No Prefect flow: the work is file writing plus one cached tet mesh (tasks.export.inputs.cached_tet_mesh), so the
command starts no server. A target whose package is missing, or a bad asset directory, fails before anything is
written; a target that fails midway leaves the earlier export untouched.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from cache.tempfiles import dead_partials, owner_tag, remove_paths
from contracts.errors import InputError
from contracts.export import ExportManifest, TargetManifest
from tasks.export.inputs import load_export_inputs, write_tetmesh_dir
from tasks.export.manifest import MANIFEST, TETMESH_DIR, read_manifest
from tasks.export.registry import exporter, resolve_targets
from tasks.publish import replace_directory, write_text_atomic


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
        write_tetmesh_dir(inputs, work / TETMESH_DIR)
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
        old = read_manifest(out_root)
        targets = {**(old.targets if old else {}), **built}
        manifest = ExportManifest(asset=str(asset_dir.resolve()), tet_mesh=f"{TETMESH_DIR}/{inputs.slug}.vtk",
                                  targets=targets)
        write_text_atomic(out_root / MANIFEST, manifest.model_dump_json(indent=2) + "\n")
        return manifest
    finally:
        shutil.rmtree(work, ignore_errors=True)
        if created and not any(out_root.iterdir()):  # a failed first export leaves no empty folder either
            out_root.rmdir()
