"""Genesis probes and calibration: Genesis's neo-Hookean stress and the virial plate force on known states (fast,
numpy), the calibration loop wired to the Genesis runner with stand-in probes (fast: E and the damping rate fitted,
scene_calibrated.py, calibration.json and the manifest entry written), and with genesis-world installed the real
compression of a cube whose modulus is known and the damping of a free fall (slow: Genesis compiles for minutes on
a first CPU run)."""

from __future__ import annotations

import ast
import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from tasks.export import genesis_probes as gp
from tests.export.test_crosscheck import grid_sponge  # noqa: F401  (fixture)


def test_genesis_neo_hookean_stress_and_virial_plate_force() -> None:
    """tau = mu (F F^T - I) + lambda ln J I: zero at rest, -(lambda + 2 mu) e to first order in a confined squeeze,
    and the zz virial of a uniformly stressed column between two walls gives back the wall force."""
    mu, lam = gp.lame_pa(1.0e5, 0.3)
    assert mu == pytest.approx(1.0e5 / 2.6) and lam == pytest.approx(1.0e5 * 0.3 / (1.3 * 0.4))
    eye = np.tile(np.eye(3), (5, 1, 1))
    assert np.allclose(gp.kirchhoff_zz_pa(eye, mu, lam), 0.0)
    e = 1e-4
    squeeze = np.tile(np.diag([1.0, 1.0, 1.0 - e]), (5, 1, 1))
    assert gp.kirchhoff_zz_pa(squeeze, mu, lam)[0] == pytest.approx(-(lam + 2 * mu) * e, rel=1e-3)
    # a 10 x 10 x 10 column of 4 mm particles between walls 40 mm apart, all at tau_zz: F = -tau_zz V / h (no weight)
    n, s = 1000, 0.004
    F = np.tile(np.diag([1.0, 1.0, 0.9]), (n, 1, 1))
    tau = gp.kirchhoff_zz_pa(F, mu, lam)[0]
    z = np.repeat(np.arange(10) * s + s / 2, 100)
    force = gp.plate_force_from_stress_n(F, z, mu, lam, s ** 3, 0.0, 0.0, 0.04)
    assert force == pytest.approx(-tau * n * s ** 3 / 0.04) and force > 0
    # the weight: the ground carries it, the plate half of it less for a body centred between the walls
    heavy = gp.plate_force_from_stress_n(F, z, mu, lam, s ** 3, 1.0, 0.0, 0.04)
    assert heavy == pytest.approx(force - 0.5 * 9.81, rel=1e-9)


def test_genesis_calibration_fits_e_and_damping_and_writes_the_calibrated_scene(
        grid_sponge: Path, monkeypatch: pytest.MonkeyPatch) -> None:  # noqa: F811
    """The generic loop on the Genesis runner, Genesis's probes replaced by known responses (30 % too soft, rebound
    falling with the damping rate): the fitted E and rate reach L2's modulus and rebound within 15 %, and
    scene_calibrated.py (PARAMS with them), calibration.json and manifest.json's calibrated entry are written."""
    from flows.crosscheck import crosscheck_asset

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: importlib.machinery.ModuleSpec("genesis", None) if name == "genesis"
                        else real(name, *a))
    material = json.loads((grid_sponge / "material.json").read_text())
    target_e = material["metrics"]["object_effective_modulus_pa"]
    target_r = material["metrics"]["object_rebound_ratio"]
    seen: dict[str, list[float]] = {"compress": [], "drop": []}

    def compress(scene_py: Path, strain: float, area_m2: float, young_pa: float | None = None,
                 damping_rate_per_s: float | None = None) -> dict[str, float]:
        assert Path(scene_py).is_file() and strain == 0.1 and area_m2 > 0
        seen["compress"].append(float(young_pa or 0))
        m = 0.7 * float(young_pa or 0) * target_e / material["material"]["youngs_modulus_pa"]
        return {"effective_modulus_pa": m, "recovery_ratio": 1.0, "compression_strain": strain,
                "compression_force_n": m * area_m2 * strain}

    def drop(scene_py: Path, height_fraction: float, young_pa: float | None = None,
             damping_rate_per_s: float | None = None) -> dict[str, float]:
        seen["drop"].append(float(damping_rate_per_s or 0))
        r = 3.0 * target_r / (1.0 + float(damping_rate_per_s or 0) / 20.0)
        return {"rebound_ratio": r, "max_impact_strain": 0.02, "settle_time_s": 0.2,
                "dissipated_energy_fraction": 1 - r * r}

    monkeypatch.setattr(gp, "compress", compress)
    monkeypatch.setattr(gp, "drop", drop)
    report = crosscheck_asset(grid_sponge, "genesis", calibrate=True)
    cal = report.calibration
    assert cal is not None and report.agrees is True, report.model_dump_json(indent=1)
    assert abs(cal["residuals"]["effective_modulus_pa"]) <= 0.15 and abs(cal["residuals"]["rebound_ratio"]) <= 0.15
    assert set(cal["parameters"]) == {"young_pa", "damping_rate_per_s"}
    assert cal["parameters"]["damping_rate_per_s"] > material["material"]["damping_rate_per_s"]  # it bounced too much
    assert cal["sim_calls"] == len(seen["compress"]) + len(seen["drop"]) - 2  # the 'before' pair is not calibration's
    folder = grid_sponge / "export" / "genesis"
    source = (folder / "scene_calibrated.py").read_text()
    tree = ast.parse(source)
    params = next(ast.literal_eval(n.value) for n in tree.body
                  if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "PARAMS")
    assert params["youngs_modulus_pa"] == pytest.approx(cal["parameters"]["young_pa"])
    assert params["damping_rate_per_s"] == pytest.approx(cal["parameters"]["damping_rate_per_s"])
    exported = json.loads((folder / "params.json").read_text())
    assert params["substeps"] >= exported["substeps"] * math.sqrt(params["youngs_modulus_pa"]
                                                                  / exported["youngs_modulus_pa"]) - 1
    assert json.loads((folder / "calibration.json").read_text())["sim"] == "genesis"
    entry = json.loads((grid_sponge / "export" / "manifest.json").read_text())["targets"]["genesis"]["calibrated"]
    assert "genesis/scene_calibrated.py" in entry["files"] and entry["residuals"] == cal["residuals"]


# -- with genesis-world ---------------------------------------------------------------------------------------------
def _cube_scene(tmp_path: Path, spacing_m: float = 0.004, side_m: float = 0.04) -> Path:
    """A 4 cm cube (E = 100 kPa, nu = 0.3, 200 kg/m^3, damping 10 1/s) exported for Genesis at the given spacing."""
    from contracts.export import ExportMaterial
    from tasks.export import genesis
    from tasks.export.inputs import ExportInputs
    from tasks.export.tetmesh import surface_of
    from tests.export.test_mujoco_export import block_tets

    mat = ExportMaterial(youngs_modulus_pa=1.0e5, poisson_ratio=0.3, density_kg_per_m3=200.0, damping_rate_per_s=10.0,
                         ground_friction=0.6, gripper_friction=0.8, mass_kg=200.0 * side_m ** 3)
    tet = block_tets(3, (side_m, side_m, side_m))
    inputs = ExportInputs(asset_dir=tmp_path, material=mat, tet=tet, surface_vertices_m=tet.nodes_m,
                          surface_faces=np.zeros((0, 3), np.int64), gaussians=None, name="cube")
    out = tmp_path / "genesis"
    out.mkdir()
    params = genesis.scene_params(inputs, spacing_m)
    genesis.write_obj(out / str(params["surface_file"]), *surface_of(tet))
    genesis.write_scene(out / genesis.SCENE, params, "cube")
    return out / genesis.SCENE


@pytest.mark.slow
def test_genesis_compression_of_a_cube_gives_its_youngs_modulus(tmp_path: Path) -> None:
    """Unconfined frictionless compression of a cube to 10 %: (F / A) / e is E (neo-Hookean, nu = 0.3: within 10 %)
    with F the coupler's reaction on the plate; the stress virial agrees to within a grid cell's lever (25 %); the
    cube recovers its height once the plate is withdrawn."""
    pytest.importorskip("genesis")
    r = gp.compress(_cube_scene(tmp_path), 0.1, 0.04 * 0.04)
    assert 0.09 <= r["compression_strain"] <= 0.12
    assert r["effective_modulus_pa"] == pytest.approx(1.0e5, rel=0.10)
    assert r["compression_force_from_stress_n"] == pytest.approx(r["compression_force_n"], rel=0.25)
    assert r["recovery_ratio"] >= 0.9


@pytest.mark.slow
def test_genesis_scene_damps_velocities_as_deformsmith(tmp_path: Path) -> None:
    """scene.py's damping (Genesis's Drag on the MPM grid): a body falling 80 ms reaches -g t undamped and DeformSmith's
    damped speed -g (1 - exp(-c t)) / c with the rate (its grid damping every substep: the continuous limit)."""
    pytest.importorskip("genesis")
    mod = gp.load_scene_module(_cube_scene(tmp_path))
    t = 40 * float(mod.PARAMS["dt_s"])
    for rate in (0.0, 10.0):
        scene, body = mod.build_scene(lift_m=0.045, damping_rate_per_s=rate)
        for _ in range(40):
            scene.step()
        vz = float(gp._numpy(body.get_particles_vel())[:, 2].mean())
        expected = -9.81 * t if rate == 0.0 else -9.81 * (1.0 - math.exp(-rate * t)) / rate
        assert vz == pytest.approx(expected, rel=0.005), rate
