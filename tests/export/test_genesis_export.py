"""Genesis export: the scene file (MPM neo-Hookean Elastic with the validated E, nu, rho on a ground plane, the damping
rate as Genesis's Drag force field on the MPM grid) is written with its surface mesh and parses; with genesis-world installed it builds
and steps 1 s without NaN (slow: Genesis compiles its kernels for minutes on a CPU)."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.export.test_mujoco_export import MATERIAL, block_inputs


def test_genesis_scene_file_is_written_and_parses(tmp_path: Path) -> None:
    from tasks.export import genesis

    out = tmp_path / "genesis"
    manifest = genesis.export(block_inputs(tmp_path), out)
    assert manifest.target == "genesis" and all((out / f).is_file() for f in manifest.files)
    source = (out / "scene.py").read_text()
    tree = ast.parse(source)  # valid Python
    calls = {n.func.attr for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)}
    assert {"Elastic", "Plane", "Mesh", "Scene", "build", "step", "Box", "Drag", "add_force_field", "activate"} <= calls
    assert 'model="neohooken"' in source and 'Drag(linear=rate)' in source
    functions = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
    assert {"build_scene", "build_plate_scene", "move_plate"} <= functions
    params = json.loads((out / "params.json").read_text())
    assert params["youngs_modulus_pa"] == MATERIAL.youngs_modulus_pa and params["poisson_ratio"] == 0.3
    assert params["density_kg_per_m3"] == MATERIAL.density_kg_per_m3
    assert params["damping_rate_per_s"] == MATERIAL.damping_rate_per_s
    obj = (out / params["surface_file"]).read_text().splitlines()
    assert sum(1 for line in obj if line.startswith("f ")) == 2 * 6 * 4  # the block's boundary: 6 faces x 4 cells x 2
    assert "Drag(linear=rate)" in manifest.damping_mapping and "10 1/s" in manifest.damping_mapping


def test_genesis_calibrated_params_scale_the_substeps_with_the_stiffness() -> None:
    """A calibrated E four times the exported one needs twice the substeps (wave speed ~ sqrt(E)); a softer one keeps
    the exported step."""
    from tasks.export import genesis

    params = {"youngs_modulus_pa": 1.0e5, "substeps": 10, "damping_rate_per_s": 5.0, "dt_s": 2e-3}
    stiff = genesis.calibrated_params(params, 4.0e5, 7.5)
    assert stiff["substeps"] == 20 and stiff["youngs_modulus_pa"] == 4.0e5 and stiff["damping_rate_per_s"] == 7.5
    assert genesis.calibrated_params(params, 0.5e5, 1.0)["substeps"] == 10 and params["substeps"] == 10


@pytest.mark.slow
def test_genesis_scene_builds_and_steps_one_second(tmp_path: Path) -> None:
    pytest.importorskip("genesis")
    from tasks.export import genesis

    out = tmp_path / "genesis"
    genesis.export(block_inputs(tmp_path), out)
    run = subprocess.run([sys.executable, "scene.py"], cwd=out, capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, run.stderr[-2000:]
    z = float(run.stdout.strip().splitlines()[-1].split(":")[-1])
    assert -0.01 < z < 0.01  # finite, resting on the ground


@pytest.mark.slow
def test_genesis_drop_probe_reports_the_drop_metrics(tmp_path: Path) -> None:
    """L2's drop on the exported scene in Genesis (the crosscheck's Genesis probe): rebound, impact strain, settle
    time, all finite; the block falls its drop height and comes to rest on the ground."""
    pytest.importorskip("genesis")
    import math

    from tasks.export import genesis, genesis_probes

    out = tmp_path / "genesis"
    genesis.export(block_inputs(tmp_path), out)
    r = genesis_probes.drop(out / "scene.py", 0.25, duration_s=1.0)
    for name in ("rebound_ratio", "max_impact_strain", "settle_time_s", "dissipated_energy_fraction"):
        assert math.isfinite(r[name]), name
    assert 0.0 <= r["rebound_ratio"] < 1.0 and r["first_contact_time_s"] > 0.0
    assert r["damping_rate_per_s"] == MATERIAL.damping_rate_per_s  # scene.py's rate, its Drag field's
