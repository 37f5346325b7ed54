"""Building blocks: SDF meshing, lattice inside test, particles, Gaussian binding and 3DGS .ply, size parsing."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh
from plyfile import PlyData

from contracts.shape import Ellipsoid, Part, ShapeProgram, Torus, Transform
from tasks.geometry import catalogue
from tasks.geometry.gaussians import make_gaussians, read_3dgs_ply, rest_covariances, write_3dgs_ply
from tasks.geometry.meshing import mesh_program
from tasks.geometry.particles import ParticleSettings, sample_particles
from tasks.geometry.raster import lattice_winding
from tasks.render.splats import deform_gaussians


def _sphere(r: float = 0.05) -> ShapeProgram:
    return ShapeProgram(name="sphere", category="ball", parts=[Part(primitive=Ellipsoid(radii_m=(r, r, r)))])


def test_sdf_mesh_is_watertight_with_the_analytic_volume() -> None:
    mesh = mesh_program(_sphere(0.05), 64)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(4 / 3 * math.pi * 0.05**3, rel=0.01)
    torus = ShapeProgram(name="t", category="x", parts=[Part(primitive=Torus(major_radius_m=0.05, minor_radius_m=0.02))])
    tm = mesh_program(torus, 96)
    assert tm.is_watertight and tm.euler_number == 0  # genus one survives meshing
    assert tm.volume == pytest.approx(2 * math.pi**2 * 0.05 * 0.02**2, rel=0.02)


def test_smooth_union_and_colours_follow_the_parts() -> None:
    prog = ShapeProgram(name="two", category="x", parts=[
        Part(primitive=Ellipsoid(radii_m=(0.03, 0.03, 0.03)), color_rgb=(1, 0, 0)),
        Part(primitive=Ellipsoid(radii_m=(0.03, 0.03, 0.03)), transform=Transform(translation_m=(0.05, 0, 0)),
             color_rgb=(0, 0, 1), blend_m=0.01),
    ])
    mesh = mesh_program(prog, 64)
    assert mesh.is_watertight and mesh.body_count == 1
    vc = mesh.visual.vertex_colors
    left, right = mesh.vertices[:, 0] < -0.01, mesh.vertices[:, 0] > 0.06
    assert vc[left, 0].mean() > 200 and vc[left, 2].mean() < 50
    assert vc[right, 2].mean() > 200 and vc[right, 0].mean() < 50


def test_lattice_winding_matches_a_sphere_and_flags_open_meshes() -> None:
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    n = 41
    origin = np.full(3, -1.2) + 1e-4
    dx = 2.4 / (n - 1)
    w, unbalanced = lattice_winding(mesh.vertices, mesh.faces, origin, dx, (n, n, n))
    g = origin + dx * np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), -1)
    r = np.linalg.norm(g, axis=-1)
    clear = np.abs(r - 1.0) > 0.02
    assert np.array_equal((w > 0)[clear], (r < 1.0)[clear]) and unbalanced == 0.0
    half = mesh.slice_plane([0, 0, 0], [0, 0, 1])  # open bowl
    _, unbalanced = lattice_winding(half.vertices, half.faces, origin, dx, (n, n, n))
    assert unbalanced > 0.5
    from tasks.geometry.checks import winding_numbers

    np.testing.assert_allclose(winding_numbers(mesh, np.array([[0.0, 0, 0], [0.5, 0.2, 0], [2.0, 0, 0]])), [1, 1, 0],
                               atol=1e-6)


def test_particle_volumes_sum_exactly_and_particles_lie_inside() -> None:
    mesh = mesh_program(_sphere(0.05), 64)
    pos, vol, col, dx, fill = sample_particles(mesh, ParticleSettings(cells_per_longest_extent=20, max_particles=20000))
    assert vol.sum() == pytest.approx(mesh.volume, rel=1e-12)
    assert fill == pytest.approx(1.0, abs=0.03)  # the lattice itself measures the volume to 3 %
    assert len(pos) > 1000 and (np.linalg.norm(pos, axis=1) < 0.05).all()
    assert dx == pytest.approx(0.1 / 20, rel=0.05) and col.shape == (len(pos), 3)


def test_gaussians_follow_an_affine_particle_motion_exactly() -> None:
    mesh = mesh_program(_sphere(0.05), 48)
    pos, _, _, dx, _ = sample_particles(mesh, ParticleSettings(cells_per_longest_extent=16, max_particles=20000))
    g = make_gaussians(mesh, pos, dx, 2000, seed=1)
    assert set(np.unique(g["particle_index"])) <= set(range(len(pos)))
    np.testing.assert_allclose(g["particle_weight"].sum(axis=1), 1.0, rtol=1e-5)
    rot = trimesh.transformations.rotation_matrix(0.7, [0.3, 1, 0.2])[:3, :3]
    A = rot @ np.diag([1.3, 0.8, 1.0])  # rotate + stretch
    b = np.array([0.1, -0.2, 0.05])
    F = np.broadcast_to(A, (len(pos), 3, 3))
    cov0 = rest_covariances(g["scales_m"], g["rotations_wxyz"])
    x, cov = deform_gaussians(g["positions_m"], cov0, g["particle_index"], g["particle_weight"], pos, pos @ A.T + b, F)
    np.testing.assert_allclose(x, g["positions_m"].astype(np.float64) @ A.T + b, atol=1e-6)
    np.testing.assert_allclose(cov, A @ cov0 @ A.T, atol=1e-12)


def test_3dgs_ply_round_trips_through_plyfile(tmp_path: Path) -> None:
    mesh = mesh_program(_sphere(0.05), 48)
    pos, _, _, dx, _ = sample_particles(mesh, ParticleSettings(cells_per_longest_extent=16, max_particles=20000))
    g = make_gaussians(mesh, pos, dx, 500, seed=0, dense=False)
    path = tmp_path / "g.ply"
    write_3dgs_ply(g, path)
    ply = PlyData.read(str(path))
    assert ply.elements[0].name == "vertex" and ply.elements[0].count == 500
    names = [p.name for p in ply.elements[0].properties]
    assert names == ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity",
                     "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    assert not ply.text and ply.byte_order == "<"
    back = read_3dgs_ply(path)
    np.testing.assert_allclose(back["positions_m"], g["positions_m"], atol=1e-7)
    np.testing.assert_allclose(back["colors"], g["colors"], atol=1e-5)
    np.testing.assert_allclose(back["scales_m"], g["scales_m"], rtol=1e-5)
    np.testing.assert_allclose(back["opacities"], g["opacities"], atol=1e-5)


def test_a_large_flat_good_keeps_its_draft_gaussians_within_the_fleet_budget(tmp_path: Path) -> None:
    """A 50 x 35 cm sheet at a 5.8 mm particle spacing asks for ~330k surface discs at 0.1 x the spacing; at draft it
    gets the contract's 60k, and its gaussians.ply (68 B each) stays near 4 MB."""
    from tasks.geometry.gaussians import dense_count
    from tasks.geometry.pipeline import settings_from_contract

    mesh = trimesh.creation.box((0.5, 0.35, 0.02))
    mesh.visual.vertex_colors = np.tile([200, 220, 240, 255], (len(mesh.vertices), 1)).astype(np.uint8)
    spacing = 0.0058
    pos = np.stack(np.meshgrid(*(np.arange(-h + spacing / 2, h, spacing) for h in (0.25, 0.175, 0.01)),
                               indexing="ij"), -1).reshape(-1, 3)
    asked = dense_count(float(mesh.area), spacing, 0.75)
    cap = settings_from_contract("draft").max_gaussians
    assert asked > 300_000 and cap == 60_000
    assert settings_from_contract("standard").max_gaussians > cap
    g = make_gaussians(mesh, pos, spacing, 2 * len(pos), seed=0, max_count=cap)
    assert len(g["positions_m"]) == cap
    write_3dgs_ply(g, tmp_path / "g.ply")
    assert (tmp_path / "g.ply").stat().st_size < 68 * cap + 2000


@pytest.mark.parametrize("text, ext, longest", [
    ("a soft plush turtle toy, about 25 cm long", (0.25, None, None), None),
    ("kitchen sponge 10 x 7 x 3 cm", (0.10, 0.07, 0.03), None),
    ("a sheet of bubble wrap, 30 cm by 1 m", (0.30, 1.0, None), None),  # each number with its own unit
    ("a towel 50cm x 1 m x 5 mm", (0.50, 1.0, 0.005), None),
    ("a rubber ball 6 cm in diameter", (0.06, 0.06, None), None),
    ("a teddy bear 12 inches tall", (None, None, 0.3048), None),
    ("a 40mm marshmallow", (None, None, None), 0.04),
])
def test_sizes_are_parsed_in_si(text: str, ext: tuple, longest: float | None) -> None:
    size = catalogue.parse_size(text)
    for got, want in zip(size.extents_m, ext):
        assert (got is None and want is None) or got == pytest.approx(want)
    assert (size.longest_m is None and longest is None) or size.longest_m == pytest.approx(longest)


def test_modifiers_fallback_and_absurd_sizes() -> None:
    d = catalogue.design_from_text("a small flat foam block")
    assert d.entry == "foam_block" and d.modifiers == ["small", "flat"] and not d.warnings
    assert d.size.axis_scale[2] < d.size.axis_scale[0] < 1.0
    assert catalogue.design_from_text("a soft plush turtle, 25 cm long").modifiers == []  # 'long' belongs to the size
    d = catalogue.design_from_text("a stuffed quokka")  # not in the lexicon: a generic plush animal, never a named one
    assert d.match_score == 0 and d.program.category == "plush_animal" and d.entry.startswith("generic_")
    assert "'quokka' is not in the lexicon" in d.warnings[0] and d.concept.fallback_level == "category"
    from contracts.errors import InputError

    with pytest.raises(InputError, match="outside the supported range"):
        catalogue.design_from_text("a 50 m teddy bear")
    with pytest.raises(InputError, match="outside the supported range"):
        catalogue.design_from_text("a 2 mm sponge")
    assert len(catalogue.entry_names()) >= 40


def test_winding_numbers_in_blocks_equal_each_point_alone() -> None:
    """The block split (a bounded working set) gives every point the number it has on its own, bit for bit."""
    import trimesh

    from tasks.geometry import checks

    mesh = trimesh.creation.icosphere(subdivisions=5, radius=0.1)  # 20,480 faces: 12 points a block
    pts = np.random.default_rng(0).uniform(-0.15, 0.15, (40, 3))
    together = checks.winding_numbers(mesh, pts)
    alone = np.array([checks.winding_numbers(mesh, p[None, :])[0] for p in pts])
    assert checks._WINDING_BLOCK // len(mesh.faces) < len(pts)  # several blocks
    np.testing.assert_array_equal(together, alone)
    inside = np.linalg.norm(pts, axis=1) < 0.099
    np.testing.assert_allclose(together[inside], 1.0, atol=1e-9)
