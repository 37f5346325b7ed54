"""Shared trials for the L3 tests: a 3 cm soft cube (1728 particles at 2.5 mm, 5 mm grid), draft timing; and the
asset directory of 'a soft foam cube 3 cm' (L0 + L1) that the flow tests run L3 on.

The trials and the asset are made once per test run (tests.worker_share): the files that read them may run on
different xdist workers."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan
from tasks.manipulation.body import TrialBody, box_body
from tasks.manipulation.outcome import TrialTolerances
from tasks.manipulation.trial import TrialResult, run_trial
from tasks.robot import select_grasps
from tests.worker_share import shared_dir, shared_value

EDGE_M = 0.03
SPACING_M = 0.0025
RHO = 300.0
FIRM = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=5.0)
GEL = Material(youngs_modulus_pa=1e4, poisson_ratio=0.3, damping_rate_per_s=5.0)
GEL_RHO = 1000.0
TOL = TrialTolerances(lift_height_m=0.05)


@dataclass
class Cube:
    """The test object and its frozen physical model."""

    body: TrialBody
    physical: PhysicalModel

    def plan(self, squeeze_depth_m: float, **kw: object) -> ActionPlan:
        """A draft-timed plan on the best grasp."""
        g = select_grasps(self.body.surface_points_m, self.body.surface_normals,
                          np.asarray(self.physical.center_of_mass_m), self.physical.gripper_friction).best()
        args = dict(grasp=g, squeeze_depth_m=squeeze_depth_m, target_xy_m=(0.08, 0.06), lift_height_m=0.05,
                    closing_speed_m_per_s=0.04, closure_duration_s=0.3, lift_duration_s=0.4,
                    transport_duration_s=0.6, release_duration_s=0.2, retreat_duration_s=0.2, settle_duration_s=0.2)
        args.update(kw)
        return ActionPlan(**args)  # type: ignore[arg-type]


@pytest.fixture(scope="session")
def cube() -> Cube:
    """A 3 cm cube of a firm foam (rho 300 kg/m^3), gripper friction 0.8."""
    body = box_body(EDGE_M, SPACING_M)
    phys = PhysicalModel(density_kg_per_m3=RHO, volume_m3=body.volume_m3, mass_kg=RHO * body.volume_m3,
                         particle_count=len(body.particles_m), particle_spacing_m=SPACING_M, ground_friction=0.5,
                         gripper_friction=0.8, center_of_mass_m=(0.0, 0.0, EDGE_M / 2), extents_m=(EDGE_M,) * 3,
                         category="foam")
    return Cube(body, phys)


@pytest.fixture(scope="session")
def firm_trial(cube: Cube, tmp_path_factory: pytest.TempPathFactory) -> TrialResult:
    """A 4 mm squeeze per finger: should pick and place."""
    return shared_value(tmp_path_factory, "l3-firm-trial",
                        lambda: run_trial(cube.body, cube.physical, FIRM, cube.plan(0.004), tolerances=TOL))


@pytest.fixture(scope="session")
def weak_trial(cube: Cube, tmp_path_factory: pytest.TempPathFactory) -> TrialResult:
    """A 1 mm squeeze per finger on a soft, dense gel cube (E 10 kPa, 1000 kg/m^3): 2 mu N < m g, so it slips.

    (On the firm foam cube a 1 mm squeeze already holds: ~1.8 N per finger against a 0.08 N weight.)"""
    gel = cube.physical.model_copy(update={"density_kg_per_m3": GEL_RHO, "mass_kg": GEL_RHO * cube.body.volume_m3,
                                           "category": "gel"})
    return shared_value(tmp_path_factory, "l3-weak-trial",
                        lambda: run_trial(cube.body, gel, GEL, Cube(cube.body, gel).plan(0.001), tolerances=TOL))


FAST_COACD = dict(preprocess_resolution=20, max_convex_hull=8, threshold=0.15, mcts_iterations=30, mcts_nodes=8,
                  mcts_max_depth=2, resolution=500, max_input_faces=3000)


def foam_asset(out: Path, text: str, density: float) -> Path:
    """L0 of a text request (draft, a fast convex decomposition) and an L1 physical.json of foam at `density`
    (mu 0.8)."""
    from contracts.request import AssetRequest
    from flows.l0_geometry import L0Result, write_l0
    from tasks.asset_dir import AssetDir
    from tasks.geometry import pipeline, sources
    from tasks.geometry.outputs import load_l0
    from tasks.physical.model import build_physical_model
    from tests.asset_records import physical_record

    s = pipeline.settings_from_contract("draft", coacd_overrides=FAST_COACD)
    mesh, info = sources.build_mesh(AssetRequest(text=text), s)
    proxy = pipeline.build_proxy(mesh, s.coacd)
    particles = pipeline.build_particles(mesh, s.particles)
    gaussians = pipeline.build_gaussians(mesh, particles, s)
    write_l0(L0Result(mesh, proxy, particles, gaussians, info,
                      pipeline.check_geometry(mesh, proxy, particles, gaussians)), out)
    a = load_l0(out)
    phys = build_physical_model(a.particles_m, a.volumes_m3, a.spacing_m, density, 0.6, 0.8, "foam")
    AssetDir(out).write_physical(physical_record(phys))
    return out


@pytest.fixture(scope="session")
def foam_cube_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """L0 of 'a soft foam cube 3 cm' and an L1 physical.json (foam prior: density 86 kg/m^3, mu 0.8): graspable by
    every gripper. A template: tests run on a copy of it."""
    return shared_dir(tmp_path_factory, "cube", lambda out: foam_asset(out, "a soft foam cube 3 cm", 86.0))
