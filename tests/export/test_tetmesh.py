"""Tet mesh: quality of fTetWild's mesh, its boundary, the .vtk / .msh round trip and the content cache."""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

if importlib.util.find_spec("pytetwild") is None:  # (importing pytetwild itself needs pyvista: not used here)
    pytest.skip("needs the export extra (pytetwild)", allow_module_level=True)

import trimesh  # noqa: E402

from contracts.errors import InputError  # noqa: E402
from tasks.export import inputs as export_inputs  # noqa: E402
from tests.export.assets import GENERATED  # noqa: E402
from tasks.export.tetmesh import (  # noqa: E402
    ATTEMPTS,
    MIN_DIHEDRAL_DEG,
    TetMesh,
    boundary_faces,
    read_msh,
    read_vtk,
    signed_volumes_m3,
    surface_of,
    tet_quality,
    tetrahedralize,
    write_msh,
    write_vtk,
)



def _enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    p = vertices[faces]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


@pytest.fixture(scope="module")
def box(tmp_path_factory: pytest.TempPathFactory) -> tuple[trimesh.Trimesh, TetMesh]:
    """A sponge-sized box resting on z = 0 and its tet mesh (about a second), meshed in an empty working directory
    that must stay empty (fTetWild writes a file into the current directory unless kept from it)."""
    surface = trimesh.creation.box((0.1, 0.07, 0.03))
    surface.apply_translation((0.0, 0.0, 0.015))
    cwd, work = Path.cwd(), tmp_path_factory.mktemp("cwd")
    os.chdir(work)
    try:
        tet = tetrahedralize(surface.vertices, surface.faces)
    finally:
        os.chdir(cwd)
    assert not list(work.iterdir())
    return surface, tet


def test_quality_volume_and_frame(box: tuple[trimesh.Trimesh, TetMesh]) -> None:
    surface, tet = box
    q = tet_quality(tet)
    assert q["inverted_count"] == 0 and q["min_volume_m3"] > 0
    assert q["min_dihedral_deg"] >= MIN_DIHEDRAL_DEG and q["sliver_count"] == 0
    assert q["volume_m3"] == pytest.approx(surface.volume, rel=0.02)
    assert np.all(signed_volumes_m3(tet.nodes_m, tet.tets) > 0)
    lo, hi = surface.bounds
    tol = float(max(a[2] for a in ATTEMPTS) * np.linalg.norm(hi - lo) * 1.01)  # fTetWild's envelope
    assert np.all(tet.nodes_m >= lo - tol) and np.all(tet.nodes_m <= hi + tol)
    assert tet.nodes_m[:, 2].min() == pytest.approx(0.0, abs=tol)  # resting on z = 0, same frame as the surface


def test_boundary_is_closed_and_outward(box: tuple[trimesh.Trimesh, TetMesh]) -> None:
    _, tet = box
    vertices, faces = surface_of(tet)
    closed = trimesh.Trimesh(vertices, faces, process=False)
    assert closed.is_watertight
    assert _enclosed_volume(vertices, faces) == pytest.approx(tet_quality(tet)["volume_m3"], rel=1e-9)  # outward
    assert boundary_faces(tet).max() < len(tet.nodes_m)


def test_vtk_and_msh_round_trip(box: tuple[trimesh.Trimesh, TetMesh], tmp_path: Path) -> None:
    _, tet = box
    for write, read, name in ((write_vtk, read_vtk, "m.vtk"), (write_msh, read_msh, "m.msh")):
        back = read(write(tet, tmp_path / name))
        np.testing.assert_array_equal(back.nodes_m, tet.nodes_m)
        np.testing.assert_array_equal(back.tets, tet.tets)
    meshio = pytest.importorskip("meshio")  # an independent reader agrees
    m = meshio.read(tmp_path / "m.msh")
    np.testing.assert_allclose(m.points, tet.nodes_m)
    np.testing.assert_array_equal(m.cells_dict["tetra"], tet.tets)


def test_unreadable_mesh_is_input_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.vtk"
    bad.write_text("# vtk DataFile Version 4.2\nnot a mesh\n")
    with pytest.raises(InputError):
        read_vtk(bad)
    with pytest.raises(InputError):
        tetrahedralize(np.zeros((3, 3)), np.zeros((0, 3), np.int64))
    inside_out = trimesh.creation.box((0.1, 0.1, 0.1))
    with pytest.raises(InputError, match="encloses no volume"):
        tetrahedralize(inside_out.vertices, inside_out.faces[:, ::-1])


def test_cached_by_surface(box: tuple[trimesh.Trimesh, TetMesh], monkeypatch: pytest.MonkeyPatch) -> None:
    surface, tet = box
    calls: list[int] = []

    def fake(vertices_m: np.ndarray, faces: np.ndarray, *, edge_length_m: float | None = None) -> TetMesh:
        calls.append(1)
        return tet

    monkeypatch.setattr(export_inputs, "tetrahedralize", fake)
    first = export_inputs.cached_tet_mesh(surface.vertices, surface.faces)
    second = export_inputs.cached_tet_mesh(surface.vertices, surface.faces)
    assert len(calls) == 1
    np.testing.assert_array_equal(second.tets, first.tets)
    export_inputs.cached_tet_mesh(surface.vertices * 1.01, surface.faces)  # another surface: meshed again
    assert len(calls) == 2


@pytest.mark.slow
@pytest.mark.skipif(GENERATED is None, reason="DEFORMSMITH_TEST_ASSETS names no folder of generated assets")
@pytest.mark.parametrize("name", ["sponge", "turtle", "jelly", "duck"])
def test_asset_tet_mesh_quality(name: str) -> None:
    """The real assets: no inverted tet, no sliver, volume within 2 % of the surface's, in the particles' frame (the
    particles inside the tet mesh's box, the same centre of volume within a lattice spacing)."""
    from tasks.asset_dir import AssetDir

    assert GENERATED is not None
    l0 = AssetDir(GENERATED / name).l0
    tet = tetrahedralize(l0.mesh.vertices, l0.mesh.faces)
    q = tet_quality(tet)
    assert q["inverted_count"] == 0 and q["sliver_count"] == 0 and q["min_dihedral_deg"] >= MIN_DIHEDRAL_DEG
    assert q["volume_m3"] == pytest.approx(l0.mesh.volume, rel=0.02)
    envelope = max(a[2] for a in ATTEMPTS) * float(np.linalg.norm(np.ptp(l0.mesh.vertices, axis=0)))
    assert np.all(l0.particles_m >= tet.nodes_m.min(axis=0)) and np.all(l0.particles_m <= tet.nodes_m.max(axis=0))
    assert np.all(tet.nodes_m >= l0.mesh.bounds[0] - envelope) and np.all(tet.nodes_m <= l0.mesh.bounds[1] + envelope)
    vol = signed_volumes_m3(tet.nodes_m, tet.tets)
    tet_centre = (tet.nodes_m[tet.tets].mean(axis=1) * vol[:, None]).sum(axis=0) / vol.sum()
    particle_centre = (l0.particles_m * l0.volumes_m3[:, None]).sum(axis=0) / l0.volumes_m3.sum()
    assert np.linalg.norm(tet_centre - particle_centre) < l0.spacing_m
