"""Tet mesh: quality and determinism of the isosurface-stuffing mesh, its boundary, the .vtk / .msh round trip and the
content cache."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("igl", reason="needs the export extra (libigl)")

import trimesh  # noqa: E402

from contracts.errors import InputError  # noqa: E402
from tasks.export import inputs as export_inputs  # noqa: E402
from tasks.export.stuffing import signed_distance_m  # noqa: E402
from tasks.export.tetmesh import (  # noqa: E402
    ENVELOPE_FRACTION,
    MAX_SURFACE_DEVIATION,
    MAX_VOLUME_ERROR,
    MIN_DIHEDRAL_DEG,
    TetMesh,
    boundary_faces,
    read_msh,
    read_vtk,
    signed_volumes_m3,
    surface_deviation_m,
    surface_of,
    tet_quality,
    tetrahedralize,
    write_msh,
    write_vtk,
)
from tests.export.assets import GENERATED, SPONGE  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def _enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    p = vertices[faces]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def _digest(tet: TetMesh) -> str:
    return hashlib.sha256(tet.nodes_m.tobytes() + tet.tets.tobytes()).hexdigest()


@pytest.fixture(scope="module")
def box(tmp_path_factory: pytest.TempPathFactory) -> tuple[trimesh.Trimesh, TetMesh]:
    """A sponge-sized box resting on z = 0 and its tet mesh, meshed in an empty working directory that must stay
    empty (the mesher writes no file)."""
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


def _assert_usable(tet: TetMesh, vertices: np.ndarray, faces: np.ndarray, volume_m3: float) -> dict[str, float]:
    """The quality bars: no inverted tet, no sliver, the volume within MAX_VOLUME_ERROR, a closed manifold boundary
    within the envelope of the surface and no surface vertex farther than MAX_SURFACE_DEVIATION from it, in the
    surface's frame."""
    q = tet_quality(tet)
    assert q["inverted_count"] == 0 and q["min_volume_m3"] > 0 and np.all(signed_volumes_m3(tet.nodes_m, tet.tets) > 0)
    assert q["min_dihedral_deg"] >= MIN_DIHEDRAL_DEG and q["sliver_count"] == 0
    assert q["volume_m3"] == pytest.approx(volume_m3, rel=MAX_VOLUME_ERROR)
    sv, sf = surface_of(tet)
    assert trimesh.Trimesh(sv, sf, process=False).is_watertight
    diag = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    envelope = ENVELOPE_FRACTION * diag * 1.01
    assert surface_deviation_m(tet, vertices, faces) <= MAX_SURFACE_DEVIATION * diag
    assert np.abs(signed_distance_m(sv, np.asarray(vertices, np.float64), np.asarray(faces, np.int64))).max() <= envelope
    lo, hi = np.min(vertices, axis=0), np.max(vertices, axis=0)
    assert np.all(tet.nodes_m >= lo - envelope) and np.all(tet.nodes_m <= hi + envelope)
    return q


def test_quality_volume_and_frame(box: tuple[trimesh.Trimesh, TetMesh]) -> None:
    surface, tet = box
    _assert_usable(tet, surface.vertices, surface.faces, surface.volume)
    tol = ENVELOPE_FRACTION * float(np.linalg.norm(surface.extents)) * 1.01
    assert tet.nodes_m[:, 2].min() == pytest.approx(0.0, abs=tol)  # resting on z = 0, same frame as the surface


def test_stencils_conform_with_guaranteed_angles() -> None:
    """An ellipsoid at a few spacings: every interior face shared by exactly two tets (the quad diagonals agree on
    both sides), a watertight boundary, and dihedral angles inside isosurface stuffing's bounds [10.7, 164.8] deg."""
    surface = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    surface.apply_scale((0.04, 0.03, 0.02))
    surface.apply_translation((0.001, -0.002, 0.02))
    for fraction in (0.08, 0.12, 0.2):
        tet = tetrahedralize(surface.vertices, surface.faces, edge_length_m=fraction * 0.1)
        t = np.sort(tet.tets, axis=1)
        faces = np.concatenate([t[:, [0, 1, 2]], t[:, [0, 1, 3]], t[:, [0, 2, 3]], t[:, [1, 2, 3]]])
        _, counts = np.unique(faces, axis=0, return_counts=True)
        assert counts.max() == 2
        q = _assert_usable(tet, surface.vertices, surface.faces, surface.volume)
        assert 10.7 <= q["min_dihedral_deg"] and q["max_dihedral_deg"] <= 164.8


def test_boundary_is_closed_and_outward(box: tuple[trimesh.Trimesh, TetMesh]) -> None:
    _, tet = box
    vertices, faces = surface_of(tet)
    closed = trimesh.Trimesh(vertices, faces, process=False)
    assert closed.is_watertight
    assert _enclosed_volume(vertices, faces) == pytest.approx(tet_quality(tet)["volume_m3"], rel=1e-9)  # outward
    assert boundary_faces(tet).max() < len(tet.nodes_m)


def test_same_mesh_whatever_the_listing_order(box: tuple[trimesh.Trimesh, TetMesh]) -> None:
    """The mesh depends on the surface, not on how its vertices and faces are listed."""
    surface = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    rng = np.random.default_rng(7)
    perm, face_order = rng.permutation(len(surface.vertices)), rng.permutation(len(surface.faces))
    relabel = np.empty_like(perm)
    relabel[perm] = np.arange(len(perm))
    first = tetrahedralize(surface.vertices, surface.faces)
    second = tetrahedralize(surface.vertices[perm], relabel[surface.faces[face_order]])
    assert _digest(first) == _digest(second)


_CHILD = textwrap.dedent("""
    import hashlib, sys
    import trimesh
    from tasks.export.inputs import cached_tet_mesh
    s = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    s.apply_scale((1.0, 0.8, 0.6))
    for _ in range(2):  # meshed, then read back from this process's cache
        tet = cached_tet_mesh(s.vertices, s.faces)
        print(hashlib.sha256(tet.nodes_m.tobytes() + tet.tets.tobytes()).hexdigest())
""")


def test_byte_identical_across_processes_caches_and_threads(tmp_path: Path) -> None:
    """Two fresh Python processes, each with its own empty cache and a different thread count, mesh the same surface
    to the same bytes (nodes and tets), read the same bytes back from their caches, equal to this process's mesh."""
    procs = []
    for k, threads in enumerate(("1", "2")):
        env = {**os.environ, "DEFORMSMITH_CACHE": str(tmp_path / f"cache{k}"), "IGL_NUM_THREADS": threads,
               "OMP_NUM_THREADS": threads, "PYTHONPATH": str(REPO)}
        procs.append(subprocess.Popen([sys.executable, "-c", _CHILD], cwd=REPO, env=env, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True))
    digests = []
    for proc in procs:
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        digests += out.split()
    s = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    s.apply_scale((1.0, 0.8, 0.6))
    assert len(digests) == 4 and set(digests) == {_digest(tetrahedralize(s.vertices, s.faces))}
    assert all((tmp_path / f"cache{k}").is_dir() for k in range(2))  # each process filled its own cache


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
    with pytest.raises(InputError, match="too fine"):  # a lattice of ~10^12 vertices is refused, not allocated
        tetrahedralize(inside_out.vertices, inside_out.faces, edge_length_m=1e-5)


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


def _check_asset(asset_dir: Path) -> TetMesh:
    """An asset's mesh meets the bars, in the particles' frame (the particles inside the tet mesh's box, the same
    centre of volume within a lattice spacing)."""
    from tasks.asset_dir import AssetDir
    from tasks.geometry.outputs import load_l0

    l0 = load_l0(AssetDir(asset_dir).path)
    tet = tetrahedralize(l0.mesh.vertices, l0.mesh.faces)
    _assert_usable(tet, l0.mesh.vertices, l0.mesh.faces, l0.mesh.volume)
    assert np.all(l0.particles_m >= tet.nodes_m.min(axis=0)) and np.all(l0.particles_m <= tet.nodes_m.max(axis=0))
    vol = signed_volumes_m3(tet.nodes_m, tet.tets)
    tet_centre = (tet.nodes_m[tet.tets].mean(axis=1) * vol[:, None]).sum(axis=0) / vol.sum()
    particle_centre = (l0.particles_m * l0.volumes_m3[:, None]).sum(axis=0) / l0.volumes_m3.sum()
    assert np.linalg.norm(tet_centre - particle_centre) < l0.spacing_m
    return tet


def test_committed_sponge_tet_mesh() -> None:
    """The committed sponge (a generated asset's surface, 19k faces) meets every bar."""
    _check_asset(SPONGE)


@pytest.mark.slow
@pytest.mark.skipif(GENERATED is None, reason="DEFORMSMITH_TEST_ASSETS names no folder of generated assets")
@pytest.mark.parametrize("name", ["sponge", "ball", "turtle", "jelly", "duck"])
def test_asset_tet_mesh_quality(name: str) -> None:
    """The real assets (those of the DEFORMSMITH_TEST_ASSETS folder): every bar, and the same bytes twice."""
    assert GENERATED is not None
    if not (GENERATED / name).is_dir():
        pytest.skip(f"no {name} in {GENERATED}")
    first = _check_asset(GENERATED / name)
    assert _digest(first) == _digest(_check_asset(GENERATED / name))
