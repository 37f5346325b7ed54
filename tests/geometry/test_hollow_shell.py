"""A hollow object's MPM particles are its shell (issue #39, session 32): L0 keeps the lattice points within the wall
of the surface when the lattice resolves the wall (two particle spacings, within the budget), records it in
geometry.json, and L1 spreads the wall's mass over the shell. The shell is opt-in (the L0 contract's hollow_particles:
shell; default solid, as before: a rubber shell alone is a dead ball); the shell tests set it. Small spheres (a few
thousand particles at most)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from contracts.asset_dir import ParticleBody
from contracts.concept import ConceptMatch
from flows.l0_geometry import L0Result, write_l0
from tasks.geometry import pipeline
from tasks.geometry.collision import CoacdSettings
from tasks.geometry.outputs import load_l0
from tasks.geometry.particles import MIN_WALL_SPACINGS, ParticleSettings, sample_particles, surface_distance
from tasks.geometry.shell import Surface, concept_wall_m
from tasks.physical.mass import mass_check, shell_estimate
from tasks.physical.plan import l1_plan

RADIUS_M = 0.03
WALL_M = 0.006  # 3 mm spacing: ~2k particles
SETTINGS = ParticleSettings(cells_per_longest_extent=10, max_particles=5000, min_particles=0, hollow_particles="shell")
SOLID = SETTINGS.model_copy(update={"hollow_particles": "solid"})  # the default
RUBBER_BALL = ConceptMatch(concept="tennis_ball", noun="tennis ball", body_plan="catalogue:tennis_ball",
                           category="ball", fallback_level="exact", default_material="rubber", hollow=True,
                           wall_thickness_m=WALL_M, density_kg_per_m3=950.0, typical_mass_kg=0.058,
                           typical_size_m=0.068)


def _sphere(radius_m: float = RADIUS_M) -> trimesh.Trimesh:
    m = trimesh.creation.icosphere(subdivisions=4, radius=radius_m)
    m.apply_translation((0.0, 0.0, radius_m))  # the canonical frame: resting on z = 0
    m.visual.vertex_colors = np.tile([200, 60, 40, 255], (len(m.vertices), 1)).astype(np.uint8)
    return m


def _shell_volume(radius_m: float, wall_m: float) -> float:
    return 4.0 / 3.0 * math.pi * (radius_m**3 - (radius_m - wall_m) ** 3)


def test_a_hollow_concepts_particles_are_its_shell() -> None:
    mesh = _sphere()
    arrays, body = pipeline.build_body(pipeline.mesh_to_arrays(mesh), SETTINGS, WALL_M)
    assert body.shell and body.wall_m == WALL_M and body.reason is None
    assert body.spacing_m <= WALL_M / MIN_WALL_SPACINGS + 1e-12
    pos, vol = arrays["positions_m"], arrays["volumes_m3"]
    assert 500 < len(pos) <= SETTINGS.max_particles
    r = np.linalg.norm(pos - np.array([0.0, 0.0, RADIUS_M]), axis=1)
    # nothing near the centre: every particle lies within the wall of the surface (positions are the centroids of
    # the wall's sub-samples, so the innermost are within half a sub-sample of the wall's inner face)
    assert r.min() > RADIUS_M - WALL_M - 0.25 * body.spacing_m
    assert r.min() < RADIUS_M - WALL_M + 0.5 * body.spacing_m  # ... and the wall is that thick, not thinner
    depth = surface_distance(mesh, pos, WALL_M)
    assert depth.max() <= WALL_M
    # the volumes sum to the shell's (the sphere's: within 2 %), not the enclosed volume
    assert float(vol.sum()) == pytest.approx(body.volume_m3, rel=1e-9)
    assert body.volume_m3 == pytest.approx(_shell_volume(RADIUS_M, WALL_M), rel=0.02)
    assert body.enclosed_volume_m3 == pytest.approx(float(mesh.volume), rel=1e-9)
    checks = pipeline.check_geometry(pipeline.mesh_to_arrays(mesh), {"union_volume_m3": np.array(mesh.volume),
                                     "part_face_count": np.array([1])}, arrays,
                                     {"positions_m": pos[:10]})
    assert checks.metrics["particle_volume_ratio"] == pytest.approx(1.0, abs=1e-6)
    assert checks.metrics["particle_body_volume_ratio"] == pytest.approx(body.volume_m3 / mesh.volume, rel=1e-6)
    assert "particles fill mesh" not in checks.failed


def test_a_wall_the_lattice_cannot_resolve_stays_solid_and_says_why() -> None:
    mesh = pipeline.mesh_to_arrays(_sphere())
    thin = 0.0004  # 0.2 mm spacing: ~600k particles, over the budget of 5000
    arrays, body = pipeline.build_body(mesh, SETTINGS, thin)
    assert body.kind == "solid" and body.wall_m is None and body.requested_wall_m == thin
    assert body.reason is not None and "over the budget of 5000" in body.reason and "0.4 mm wall" in body.reason
    solid = pipeline.build_particles(mesh, SETTINGS)
    np.testing.assert_array_equal(arrays["positions_m"], solid["positions_m"])
    assert float(arrays["volumes_m3"].sum()) == pytest.approx(float(pipeline.arrays_to_mesh(mesh).volume), rel=1e-9)


def test_a_solid_concept_is_unchanged() -> None:
    mesh = _sphere()
    assert pipeline.hollow_wall(RUBBER_BALL.model_copy(update={"hollow": False, "wall_thickness_m": None}),
                                "a rubber ball") == (None, None)
    assert pipeline.hollow_wall(None, "a ball") == (None, None)
    arrays, body = pipeline.build_body(pipeline.mesh_to_arrays(mesh), SETTINGS)
    pos, vol, _, dx, _ = sample_particles(pipeline.arrays_to_mesh(pipeline.mesh_to_arrays(mesh)), SETTINGS)
    np.testing.assert_array_equal(arrays["positions_m"], pos)
    np.testing.assert_array_equal(arrays["volumes_m3"], vol)
    assert body == ParticleBody(kind="solid", spacing_m=dx, volume_m3=body.enclosed_volume_m3,
                                enclosed_volume_m3=body.enclosed_volume_m3)


def test_which_hollow_concepts_get_a_shell() -> None:
    assert pipeline.hollow_wall(RUBBER_BALL, "a tennis ball") == (WALL_M, None)
    sheet = RUBBER_BALL.model_copy(update={"sheet": True})
    assert "one-layer sheet" in str(pipeline.hollow_wall(sheet, "a resistance band")[1])
    no_wall = RUBBER_BALL.model_copy(update={"wall_thickness_m": None})
    assert "no wall thickness" in str(pipeline.hollow_wall(no_wall, "a tennis ball")[1])
    wall, why = pipeline.hollow_wall(RUBBER_BALL, "a tennis ball of soft pu foam")
    assert wall is None and "not the rubber of its wall" in str(why)


def test_the_shell_weighs_the_walls_mass_at_the_walls_density() -> None:
    mesh = _sphere()
    arrays, body = pipeline.build_body(pipeline.mesh_to_arrays(mesh), SETTINGS, WALL_M)
    shell_m3 = float(arrays["volumes_m3"].sum())
    enclosed = float(mesh.volume)
    rho = 950.0
    check = mass_check(shell_m3, float(mesh.extents.max()), float(mesh.area), "rubber", rho, (900.0, 1300.0),
                       RUBBER_BALL, enclosed_volume_m3=enclosed)
    wall_mass = RUBBER_BALL.mass_estimate_kg(enclosed, float(mesh.area))
    assert wall_mass is not None
    # the mass the probes use (density x the particles' volume) is the concept's wall mass ...
    assert check.density_kg_per_m3 * shell_m3 == pytest.approx(wall_mass, rel=1e-6)
    # ... at the wall's density, up to area x wall overstating a curved wall's volume (1 - w/R + (w/R)^2 / 3)
    curved = _shell_volume(RADIUS_M, WALL_M) / (4.0 * math.pi * RADIUS_M**2 * WALL_M)
    assert check.density_kg_per_m3 == pytest.approx(rho / curved, rel=0.03)
    assert any("built as its shell" in n for n in check.notes)
    # the same object built solid keeps its effective density over the enclosed volume (as before)
    solid = mass_check(enclosed, float(mesh.extents.max()), float(mesh.area), "rubber", rho, (900.0, 1300.0),
                       RUBBER_BALL)
    assert solid.density_kg_per_m3 * enclosed == pytest.approx(wall_mass, rel=1e-6)
    assert solid.density_kg_per_m3 == pytest.approx(rho * 3.0 * WALL_M / RADIUS_M, rel=0.03)  # A w / V = 3 w / R


def test_geometry_json_records_the_shell_and_l1_weighs_it(tmp_path: Path) -> None:
    from tasks.geometry.pipeline import BuildInfo

    mesh = pipeline.mesh_to_arrays(_sphere())
    s = pipeline.settings_from_contract("draft", coacd_overrides={"method": "hull"})
    s = s.model_copy(update={"particles": SETTINGS, "gaussians_per_particle": 0.05, "max_gaussians": 2000})
    info = BuildInfo(source="text", name="tennis ball", category="ball", concept=RUBBER_BALL)
    proxy = pipeline.build_proxy(mesh, CoacdSettings(method="hull"))
    # the wall as L0 builds it: fitted on the mesh to the concept's typical mass (tasks.geometry.shell)
    wall = concept_wall_m(RUBBER_BALL, Surface.of(_sphere()))
    assert wall is not None and pipeline.hollow_wall(RUBBER_BALL, "a tennis ball", mesh) == (wall, None)
    particles, body = pipeline.build_body(mesh, s.particles, wall)
    gaussians = pipeline.build_gaussians(mesh, particles, s)
    checks = pipeline.check_geometry(mesh, proxy, particles, gaussians)
    write_l0(L0Result(mesh, proxy, particles, gaussians, info, checks, body), tmp_path / "ball")
    asset = load_l0(tmp_path / "ball")
    assert asset.shell and asset.body == body
    assert asset.record["particles"]["kind"] == "shell" and asset.record["particles"]["wall_m"] == wall
    plan = l1_plan(asset, "a tennis ball")
    estimate = shell_estimate(RUBBER_BALL, Surface.of(asset.mesh))
    assert estimate is not None
    assert plan.mass.density_kg_per_m3 * float(asset.volumes_m3.sum()) == pytest.approx(estimate[0], rel=1e-6)
    assert 900.0 < plan.mass.density_kg_per_m3 < 1000.0  # the wall's rubber (950: the particles hold the wall L1
    # weighs), not ~300 kg/m^3 over the enclosed volume


def test_an_exported_shell_weighs_what_the_asset_weighs() -> None:
    """The exports are solid tet meshes of the surface: a shell asset goes out at its mass over the enclosed volume."""
    from types import SimpleNamespace

    from contracts.material import Material
    from tasks.export.inputs import export_material

    body = ParticleBody(kind="shell", wall_m=WALL_M, requested_wall_m=WALL_M, spacing_m=0.003, volume_m3=5.0e-5,
                        enclosed_volume_m3=1.5e-4)
    mat = Material(youngs_modulus_pa=1.5e6, poisson_ratio=0.48, damping_rate_per_s=0.0)
    physical = SimpleNamespace(density_kg_per_m3=1100.0, mass_kg=1100.0 * 5.0e-5, ground_friction=0.6,
                               gripper_friction=0.8)

    class Dir:
        def __init__(self, particles: ParticleBody | None) -> None:
            self.particles = particles

        def material(self) -> SimpleNamespace:
            return SimpleNamespace(material=mat, passed=True, message="")

        def physical_model(self) -> SimpleNamespace:
            return physical

        def adopted_material(self) -> SimpleNamespace:
            return SimpleNamespace(material=mat)

        def geometry(self) -> SimpleNamespace:
            return SimpleNamespace(particles=self.particles)

    shell = export_material(Dir(body))  # type: ignore[arg-type]
    assert shell.density_kg_per_m3 * body.enclosed_volume_m3 == pytest.approx(physical.mass_kg)
    assert shell.mass_kg == pytest.approx(physical.mass_kg)
    assert export_material(Dir(None)).density_kg_per_m3 == 1100.0  # type: ignore[arg-type]


def test_l0_builds_a_squash_ball_as_its_shell_and_a_duck_solid_over_the_draft_budget(tmp_path: Path) -> None:
    """Through run_l0 at draft with the shell opted into (the L0 contract's hollow_particles: shell): the squash ball's
    wall (fitted to its 24 g at the rubber class's 950 kg/m^3 on the shell's true volume: 7.5 mm, the lexicon's 5 mm
    having been area x wall; ~2k particles at 2 mm) is a shell; the bath duck's ~1.6 mm wall would take ~100k
    particles at 0.8 mm, over draft's 20k: solid, and geometry.json says why."""
    from contracts.request import AssetRequest
    from flows.l0_geometry import run_l0, with_hollow_particles

    shell = with_hollow_particles("shell")
    ball = run_l0(AssetRequest(text="a squash ball", quality="draft"), contract=shell, use_cache=False)
    assert ball.checks.passed and ball.body is not None and ball.body.shell and ball.info.concept is not None
    fitted = concept_wall_m(ball.info.concept, Surface.of(pipeline.arrays_to_mesh(ball.mesh)))
    assert ball.body.wall_m == fitted and fitted is not None and fitted > 0.005
    assert len(ball.particles["positions_m"]) < 5000
    assert float(ball.particles["volumes_m3"].sum()) == pytest.approx(ball.body.volume_m3, rel=1e-9)
    duck = run_l0(AssetRequest(text="a rubber duck", quality="draft"), contract=shell, use_cache=False)
    assert duck.body is not None and duck.body.kind == "solid" and duck.info.concept is not None
    assert duck.body.requested_wall_m == concept_wall_m(duck.info.concept,
                                                        Surface.of(pipeline.arrays_to_mesh(duck.mesh)))
    assert "over the budget of 20000" in str(duck.body.reason)
    write_l0(duck, tmp_path / "duck")
    assert load_l0(tmp_path / "duck").record["particles"]["reason"] == duck.body.reason


def test_by_default_a_hollow_concept_is_built_solid_and_says_the_shell_is_opt_in(tmp_path: Path) -> None:
    """The L0 contract's default (hollow_particles: solid): a squash ball's particles are the solid of before, and
    geometry.json says why; the choice keys the particles' cache."""
    from contracts.request import AssetRequest
    from contracts.stage import L0Parameters, load_contract
    from flows.harness import probe_cache_key
    from flows.l0_geometry import build_particles, run_l0, with_hollow_particles

    arrays, body = pipeline.build_body(pipeline.mesh_to_arrays(_sphere()), SOLID, WALL_M)
    assert body.kind == "solid" and body.requested_wall_m == WALL_M and body.reason == pipeline.SHELL_OPT_IN
    np.testing.assert_array_equal(arrays["positions_m"],
                                  pipeline.build_particles(pipeline.mesh_to_arrays(_sphere()), SOLID)["positions_m"])
    assert L0Parameters.of(load_contract("L0")).hollow_particles == "solid"
    assert pipeline.settings_from_contract("draft").particles.hollow_particles == "solid"
    request = AssetRequest(text="a squash ball", quality="draft")
    ball = run_l0(request, use_cache=False)
    assert ball.checks.passed and ball.body is not None and ball.body.kind == "solid"
    assert ball.body.wall_m is None and ball.info.concept is not None
    assert ball.body.requested_wall_m == concept_wall_m(ball.info.concept,
                                                        Surface.of(pipeline.arrays_to_mesh(ball.mesh)))
    assert ball.body.reason == pipeline.SHELL_OPT_IN
    assert "opt-in" in ball.body.reason and "hollow_particles: shell" in ball.body.reason
    assert "0.12" in ball.body.reason and "0.53-0.58" in ball.body.reason
    # the particles of before: the solid lattice of the mesh, the volumes summing to the mesh volume
    draft = pipeline.settings_from_contract("draft").particles
    pos, vol, _, _, _ = sample_particles(pipeline.arrays_to_mesh(ball.mesh), draft)
    np.testing.assert_array_equal(ball.particles["positions_m"], pos)
    np.testing.assert_array_equal(ball.particles["volumes_m3"], vol)
    write_l0(ball, tmp_path / "ball", request=request)
    asset = load_l0(tmp_path / "ball")
    assert not asset.shell and asset.record["particles"]["reason"] == pipeline.SHELL_OPT_IN
    assert "built as its shell" not in " ".join(l1_plan(asset, "a squash ball").mass.notes)
    # solid and shell are different particles' cache keys
    shell = pipeline.settings_from_contract("draft", with_hollow_particles("shell")).particles
    assert shell.hollow_particles == "shell"
    keys = {probe_cache_key(build_particles, {"mesh": ball.mesh, "particles": s, "wall_m": 0.005})
            for s in (draft, shell)}
    assert len(keys) == 2 and None not in keys
