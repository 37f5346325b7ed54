"""Drake's crosscheck probes (real pydrake, the export extra): L2's compression and drop on a 27-node block, the
timestep's numerical dissipation the calibration relies on, and `deformsmith crosscheck --sim drake` end to end."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from tasks.export.crosscheck import METRICS

pytest.importorskip("pydrake")

G = 9.81


def _block(tmp_path: Path):  # type: ignore[no-untyped-def]
    from tasks.export.probe_schedule import TetBody
    from tasks.export.tetmesh import write_vtk
    from tests.export.test_mujoco_export import MATERIAL, block_tets

    tet = block_tets()
    vtk = tmp_path / "block.vtk"
    write_vtk(tet, vtk)
    body = TetBody(tet.nodes_m, tet.tets, MATERIAL.density_kg_per_m3, 0.005, MATERIAL.youngs_modulus_pa)
    return body, vtk, MATERIAL


def test_drake_probes_on_a_block_report_every_metric(tmp_path: Path) -> None:
    """Every crosscheck metric finite and plausible: a frictionless prism's effective modulus within a factor 2 of
    E at L2's strain, full recovery, a rebound below 1, and the first contact when a body falling under gravity and
    the exported mass damping (dv/dt = -g - c v) has fallen the drop height."""
    from tasks.export.drake_probes import DrakeParams, compress, drop

    body, vtk, material = _block(tmp_path)
    p = DrakeParams(material, 1e-3)
    c = compress(body, vtk, p, 0.1, 0.04 * 0.04)
    d = drop(body, vtk, p, 0.25)
    got = {**c, **d}
    for name in METRICS:
        assert math.isfinite(got[name]), name
    assert 0.5 * material.youngs_modulus_pa < c["effective_modulus_pa"] < 2.0 * material.youngs_modulus_pa
    assert 0.08 < c["compression_strain"] < 0.13 and 0.9 <= c["recovery_ratio"] <= 1.0
    assert 0.0 <= d["rebound_ratio"] < 1.0
    c_rate, h = material.damping_rate_per_s, 0.25 * body.height_m
    t = np.linspace(0.0, 0.2, 200001)
    fallen = (G / c_rate) * (t - (1.0 - np.exp(-c_rate * t)) / c_rate)
    t_fall = float(t[np.searchsorted(fallen, h)])  # 0.0416 s (undamped: 0.0391 s)
    assert abs(d["first_contact_time_s"] - t_fall) <= 2.5e-3 + 1e-3  # one sample interval and one step


def test_drake_timestep_takes_impact_energy(tmp_path: Path) -> None:
    """Drake's first-order Newmark scheme dissipates in proportion to w dt: a finer step gives the block more
    rebound, undamped (why the calibration's first knob is the timestep)."""
    from tasks.export.drake_probes import DrakeParams, drop

    body, vtk, material = _block(tmp_path)
    undamped = material.model_copy(update={"damping_rate_per_s": 0.0})
    coarse = drop(body, vtk, DrakeParams(undamped, 1e-3), 0.25, duration_s=0.2)["rebound_ratio"]  # bounces by 0.1 s
    fine = drop(body, vtk, DrakeParams(undamped, 2.5e-4), 0.25, duration_s=0.2)["rebound_ratio"]
    assert fine > coarse + 0.1, (coarse, fine)  # measured: 0.0 at 1 ms, 0.375 at 0.25 ms


def test_node_masses_sum_to_the_body_mass() -> None:
    from tasks.export.drake_probes import node_masses_kg
    from tests.export.test_mujoco_export import block_tets

    tet = block_tets()
    m = node_masses_kg(tet.nodes_m, tet.tets, 500.0)
    assert m.sum() == pytest.approx(500.0 * 0.04 * 0.04 * 0.03, rel=1e-12) and np.all(m > 0)


def test_drake_crosscheck_reports_every_metric_and_writes_a_loadable_calibrated_body(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """`crosscheck_asset(DIR, "drake")` on the committed sponge (a 60-node stand-in mesh): every metric beside L2's,
    the report written; the calibrated SDFormat body the runner writes parses in pydrake with the fitted E."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
    from pydrake.systems.framework import DiagramBuilder

    from flows import crosscheck as xc
    from tasks.export.sim_runners import drake_runner
    from tasks.export import inputs as export_inputs
    from tasks.export import registry
    from tasks.export.crosscheck import probe_targets
    from tests.export.assets import copy_sponge
    from tests.export.test_export_cmd import grid_tets

    asset = copy_sponge(tmp_path / "sponge")
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None, raising=False)
    report = xc.crosscheck_asset(asset, "drake", calibrate=False)
    material = json.loads((asset / "material.json").read_text())["metrics"]
    folder = asset / "export" / "drake"
    assert json.loads((folder / "crosscheck.json").read_text())["sim"] == "drake"
    for name, row in report.metrics.items():
        assert row.ours == material[METRICS[name][1]] and row.theirs is not None and math.isfinite(row.theirs), name
    assert report.parameters["timestep_s"] == 1e-3 and report.sim_calls == 2

    inputs = export_inputs.load_export_inputs(asset)
    targets = probe_targets(asset)
    runner = drake_runner(inputs, targets, targets.area_m2 or 1e-3, folder)
    fitted = {"young_pa": 1.23e5, "mass_damping_per_s": 4.5, "timestep_s": 2.5e-4}
    (name,) = runner.write_calibrated(fitted, folder)  # type: ignore[misc]
    text = (folder / name).read_text()
    assert "<drake:youngs_modulus>123000.0<" in text and "<drake:mass_damping>4.5<" in text
    assert "time_step=0.00025" in text
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=2.5e-4, discrete_contact_approximation="sap"), builder)
    Parser(plant).AddModels(folder / name)
    plant.Finalize()
    assert plant.deformable_model().num_bodies() == 1


@pytest.mark.slow
def test_drake_calibration_brings_modulus_and_rebound_to_l2(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The sponge (60-node stand-in mesh) calibrated in Drake: the residuals of the modulus and the rebound fall, the
    fitted timestep is finer than the exported one (Drake's integrator takes the impact), and the manifest records
    the calibration."""
    from flows import crosscheck as xc
    from tasks.export import inputs as export_inputs
    from tasks.export import registry
    from tests.export.assets import copy_sponge
    from tests.export.test_export_cmd import grid_tets

    asset = copy_sponge(tmp_path / "sponge")
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None, raising=False)
    report = xc.crosscheck_asset(asset, "drake", calibrate=True)
    for m in ("effective_modulus_pa", "rebound_ratio"):
        row = report.metrics[m]
        assert row.rel_error_calibrated is not None and row.rel_error is not None
        assert row.rel_error_calibrated < max(row.rel_error, 0.05), m
    assert report.calibration is not None and report.calibration["parameters"]["timestep_s"] < 1e-3
    manifest = json.loads((asset / "export" / "manifest.json").read_text())
    assert manifest["targets"]["drake"]["calibrated"]["sim"] == "drake"
