"""MuJoCo export: the MJCF (3-D flexcomp from the tet mesh, elasticity, mass, friction, table) loads in the real
package and steps 1 s without NaN; the damping mapping; the contact settings that keep the plate probe honest."""

from __future__ import annotations

import itertools
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from contracts.export import ExportMaterial
from tasks.export.inputs import ExportInputs
from tasks.export.tetmesh import TetMesh

mujoco = pytest.importorskip("mujoco")


def block_tets(n: int = 3, size_m: tuple[float, float, float] = (0.04, 0.04, 0.03)) -> TetMesh:
    """A box of n^3 nodes, each cell split into 6 positive tets (Kuhn), resting on z = 0, centred on the z axis."""
    axes = [np.linspace(-s / 2, s / 2, n) if i < 2 else np.linspace(0, s, n) for i, s in enumerate(size_m)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    idx = np.arange(n ** 3).reshape(n, n, n)
    tets = []
    for i, j, k in itertools.product(range(n - 1), repeat=3):
        c = [idx[i + a, j + b, k + d] for a in (0, 1) for b in (0, 1) for d in (0, 1)]
        for perm in itertools.permutations([4, 2, 1]):
            path = [0]
            for q in perm:
                path.append(path[-1] + q)
            tets.append([c[q] for q in path])
    t = np.array(tets, np.int64)
    p = grid[t]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    t[vol < 0] = t[vol < 0][:, [0, 2, 1, 3]]
    return TetMesh(nodes_m=grid, tets=t)


MATERIAL = ExportMaterial(youngs_modulus_pa=1.0e5, poisson_ratio=0.3, density_kg_per_m3=200.0, damping_rate_per_s=10.0,
                          ground_friction=0.6, gripper_friction=0.8, mass_kg=200.0 * 0.04 * 0.04 * 0.03)


def block_inputs(tmp_path: Path) -> ExportInputs:
    tet = block_tets()
    return ExportInputs(asset_dir=tmp_path, material=MATERIAL, tet=tet, surface_vertices_m=tet.nodes_m,
                        surface_faces=np.zeros((0, 3), np.int64), gaussians=None, name="test block")


def test_mujoco_export_loads_and_steps_one_second(tmp_path: Path) -> None:
    from tasks.export import mujoco as mj

    out = tmp_path / "mujoco"
    manifest = mj.export(block_inputs(tmp_path), out)
    assert manifest.target == "mujoco" and all((out / f).is_file() for f in manifest.files)
    xml = out / "test_block.xml"
    flex = ET.parse(xml).getroot().find("worldbody/flexcomp")
    assert flex is not None and flex.get("dim") == "3" and flex.get("type") == "direct"
    assert math.isclose(float(flex.get("mass")), MATERIAL.mass_kg, rel_tol=1e-6)
    el = flex.find("elasticity")
    assert el is not None and float(el.get("young")) == pytest.approx(1.0e5) and float(el.get("poisson")) == 0.3
    assert float(flex.find("contact").get("friction")) == pytest.approx(0.6)
    assert len(flex.get("element").split()) == 4 * len(block_tets().tets)
    r = mj.load_and_step(xml, 1.0)
    assert r["finite"] == 1.0 and r["time_s"] == pytest.approx(1.0, abs=1e-3)
    assert r["nflexvert"] == 27
    assert -2e-3 < r["z_min_after_m"] < 1e-3  # fell the 1 mm onto the table and rests on it, not through it
    assert 0.028 < r["z_max_after_m"] < 0.031  # and keeps its height (E = 100 kPa barely sags under its weight)


def test_damping_mapping_matches_the_fundamental_mode() -> None:
    from tasks.export.mujoco_scene import damping_time_s, fundamental_period_s

    T = fundamental_period_s(0.03, 1.0e5, 200.0)
    w0 = 2 * math.pi / T
    b = damping_time_s(10.0, 0.03, 1.0e5, 200.0)
    assert b * w0 / 2 == pytest.approx(10.0 / (2 * w0))  # the same modal damping ratio at w0


def test_contacts_are_stiff_against_the_body(tmp_path: Path) -> None:
    """A mass-normalised soft contact lets a plate sink into light flex nodes: the table and the body carry the
    same stiff impedance, so the body rests on the table within a fraction of a millimetre."""
    from tasks.export import mujoco as mj

    out = tmp_path / "mujoco"
    mj.export(block_inputs(tmp_path), out)
    root = ET.parse(out / "test_block.xml").getroot()
    table = root.find("worldbody/geom")
    body = root.find("worldbody/flexcomp/contact")
    assert table is not None and body is not None and table.get("solimp") == body.get("solimp")
    assert float(table.get("solimp").split()[1]) >= 0.99
