"""Coloured binary glTF export of the aligned mesh."""

from __future__ import annotations

from pathlib import Path

import trimesh


def write_glb(mesh: trimesh.Trimesh, path: Path) -> None:
    """Write the mesh with per-vertex colours (COLOR_0) as a .glb (glTF is y-up: the asset's z-up is kept as data)."""
    data = trimesh.exchange.gltf.export_glb(trimesh.Scene(mesh.copy()), include_normals=True)
    Path(path).write_bytes(data)
