"""`deformsmith export`: target folders, manifest, README lines, the exported numbers, bad input, atomicity.

The default run replaces the tet mesher by a structured tet grid of the surface's box (the mesher has its own tests in
test_tetmesh.py): what is checked here is the command and the files each target writes.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from contracts.export import ExportManifest
from tasks.export import inputs as export_inputs
from tasks.export import registry
from tasks.export.tetmesh import TetMesh, signed_volumes_m3
from tests.export.assets import copy_sponge



def grid_tets(vertices_m: np.ndarray, faces: np.ndarray, *, edge_length_m: float | None = None) -> TetMesh:
    """Stand-in mesher: the surface's bounding box as 4 x 3 x 2 cubes of 6 tets each, positively oriented."""
    lo, hi = vertices_m.min(axis=0), vertices_m.max(axis=0)
    n = (4, 3, 2)
    axes = [np.linspace(lo[i], hi[i], n[i] + 1) for i in range(3)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    idx = np.arange(len(nodes)).reshape(n[0] + 1, n[1] + 1, n[2] + 1)
    kuhn = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]
    tets = []
    for i in range(n[0]):
        for j in range(n[1]):
            for k in range(n[2]):
                c = [idx[i + a, j + b, k + d] for a in (0, 1) for b in (0, 1) for d in (0, 1)]
                tets += [[c[q] for q in t] for t in kuhn]
    t = np.array(tets, dtype=np.int64)
    flip = signed_volumes_m3(nodes, t) < 0
    t[flip] = t[flip][:, [0, 2, 1, 3]]
    return TetMesh(nodes_m=nodes, tets=t)


@pytest.fixture
def asset(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the sponge asset (no recordings), meshed by the stand-in."""
    out = copy_sponge(tmp_path / "sponge")
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None)  # the stand-in needs no libigl
    return out


def run_cli(argv: list[str], monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """`deformsmith ARGV` in this process: (exit code, stderr)."""
    from flows.cli import main as cli_main

    monkeypatch.setattr(sys, "argv", ["deformsmith", *argv])
    code: Any = 0
    try:
        cli_main.main()
    except SystemExit as exc:
        code = exc.code or 0
    return int(code), capsys.readouterr().err


def targets_here() -> str:
    """The targets this environment can write (usd needs usd-core)."""
    import importlib.util

    return "usd,drake,sofa" if importlib.util.find_spec("pxr") else "drake,sofa"


def test_export_writes_each_target_folder_and_the_manifest(
        asset: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    before = (asset / "export" / "physgaussian_config.json").read_bytes()
    code, err = run_cli(["export", str(asset), "--to", targets_here()], monkeypatch, capsys)
    assert code == 0, err
    root = asset / "export"
    manifest = ExportManifest.model_validate_json((root / "manifest.json").read_text())
    material = json.loads((asset / "material.json").read_text())["material"]
    physical = json.loads((asset / "physical.json").read_text())["physical_model"]
    assert set(manifest.targets) == set(targets_here().split(","))
    assert (root / manifest.tet_mesh).is_file() and (root / "tetmesh" / "quality.json").is_file()
    for name, t in manifest.targets.items():
        assert t.target == name
        assert t.material.youngs_modulus_pa == material["youngs_modulus_pa"]
        assert t.material.poisson_ratio == material["poisson_ratio"]
        assert t.material.damping_rate_per_s == material["damping_rate_per_s"]
        assert t.material.density_kg_per_m3 == physical["density_kg_per_m3"]
        assert t.material.mass_kg == physical["mass_kg"]
        assert all((root / f).is_file() for f in t.files)
        readme = (root / name / "README.md").read_text()
        assert f"Load: {t.load_hint}" in readme
        assert {p.suffix for p in (root / name).iterdir()} >= {".vtk", ".msh", ".md"}  # self-contained
    assert (root / "physgaussian_config.json").read_bytes() == before  # the earlier export is left alone
    assert not [p for p in root.iterdir() if p.name.startswith(".")]  # no temporary folder left
    sdf = (root / "drake" / "kitchen_sponge.sdf").read_text()
    assert "<drake:material_model>neohookean</drake:material_model>" in sdf
    assert f"<drake:youngs_modulus>{material['youngs_modulus_pa']!r}</drake:youngs_modulus>" in sdf

    # a second export of one target keeps the others in the manifest
    code, err = run_cli(["export", str(asset), "--to", "sofa"], monkeypatch, capsys)
    assert code == 0, err
    again = ExportManifest.model_validate_json((root / "manifest.json").read_text())
    assert set(again.targets) == set(manifest.targets)


def test_export_prints_its_load_commands_on_stdout_each_on_one_line(
        asset: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """The export's result (where each target went and the command that loads it) is on stdout, one line each even
    on a narrow console, so that a load command is pasted whole; stderr stays empty."""
    from flows.cli.apps import results

    monkeypatch.setattr(results, "width", 40)
    monkeypatch.setattr(sys, "argv", ["deformsmith", "export", str(asset), "--to", "sofa"])
    from flows.cli import main as cli_main

    with pytest.raises(SystemExit) as done:  # Typer's exit 0
        cli_main.main()
    out, err = capsys.readouterr()
    assert not done.value.code, err
    root = asset / "export"
    manifest = ExportManifest.model_validate_json((root / "manifest.json").read_text())
    assert err == ""
    assert out.splitlines() == [f"tet mesh: {root / manifest.tet_mesh}",
                                f"sofa: {root / 'sofa'}/  load: {manifest.targets['sofa'].load_hint}",
                                f"manifest: {root / 'manifest.json'}"]


def test_usd_opens_validates_and_reads_back(asset: Path, tmp_path: Path) -> None:
    pytest.importorskip("pxr")
    from pxr import Usd, UsdGeom, UsdPhysics, UsdValidation

    from flows.export import export_asset

    out = tmp_path / "out"
    manifest = export_asset(asset, "usd", out)
    stage = Usd.Stage.Open(str(out / "usd" / "kitchen_sponge.usda"))
    registry_ = UsdValidation.ValidationRegistry()
    errors = UsdValidation.ValidationContext(registry_.GetOrLoadAllValidators()).Validate(stage)
    assert not errors, [e.GetMessage() for e in errors]
    assert UsdGeom.GetStageUpAxis(stage) == "Z" and UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    body = stage.GetPrimAtPath("/World/kitchen_sponge")
    schemas = body.GetMetadata("apiSchemas")
    assert "OmniPhysicsDeformableBodyAPI" in schemas.GetAddedOrExplicitItems()
    tet = UsdGeom.TetMesh(stage.GetPrimAtPath("/World/kitchen_sponge/simulation"))
    grid = grid_tets(np.zeros((1, 3)), np.zeros((0, 3)))  # shape only: 4 x 3 x 2 cubes x 6
    assert len(tet.GetTetVertexIndicesAttr().Get()) == len(grid.tets)
    mat = stage.GetPrimAtPath("/World/kitchen_sponge/PhysicsMaterial")
    m = manifest.targets["usd"].material
    assert mat.GetAttribute("deformsmith:youngsModulusPa").Get() == m.youngs_modulus_pa
    assert mat.GetAttribute("omniphysics:youngsModulus").Get() == pytest.approx(m.youngs_modulus_pa, rel=1e-6)
    assert mat.GetAttribute("omniphysics:poissonsRatio").Get() == pytest.approx(m.poisson_ratio, rel=1e-6)
    assert UsdPhysics.MaterialAPI(mat).GetDensityAttr().Get() == pytest.approx(m.density_kg_per_m3)
    assert UsdPhysics.MaterialAPI(mat).GetDynamicFrictionAttr().Get() == pytest.approx(m.ground_friction)
    assert body.GetAttribute("physxDeformableBody:linearDamping").Get() == pytest.approx(m.damping_rate_per_s)
    points = UsdGeom.Points(stage.GetPrimAtPath("/World/kitchen_sponge/gaussians"))
    from tasks.geometry.gaussians import read_3dgs_ply

    gs = read_3dgs_ply(asset / "gaussians.ply")
    assert len(points.GetPointsAttr().Get()) == len(gs["positions_m"])
    colors = np.asarray(points.GetDisplayColorPrimvar().Get())
    np.testing.assert_allclose(colors, np.clip(gs["colors"], 0, 1), atol=1e-6)


def test_drake_loads_and_steps_one_second(asset: Path, tmp_path: Path) -> None:
    pytest.importorskip("pydrake")
    from flows.export import export_asset
    from tasks.export.drake import load_and_step

    export_asset(asset, "drake", tmp_path / "out")
    run = load_and_step(tmp_path / "out" / "drake", duration_s=1.0, time_step_s=0.01)  # 1 s simulated, < 1 s wall
    before, after = np.asarray(run["positions_before_m"]), np.asarray(run["positions_after_m"])
    assert run["deformable_bodies"] == 1 and np.isfinite(after).all()
    assert after[:, 2].min() > -1e-3  # the ground holds it
    assert abs(after.mean(axis=0) - before.mean(axis=0)).max() < 2e-3  # it rests where it was


class _Node:
    """A recording stand-in for SofaPython3's Node: addObject / addChild and attributes."""

    def __init__(self, name: str = "root") -> None:
        self.name, self.objects, self.children = name, [], []  # type: ignore[var-annotated]

    def addObject(self, kind: str, **data: Any) -> dict:  # noqa: N802 (Sofa's API)
        self.objects.append((kind, data))
        return data

    def addChild(self, name: str) -> _Node:  # noqa: N802
        child = _Node(name)
        self.children.append(child)
        return child


def test_sofa_scene_compiles_and_builds_its_graph(asset: Path, tmp_path: Path) -> None:
    from flows.export import export_asset

    manifest = export_asset(asset, "sofa", tmp_path / "out")
    scene = tmp_path / "out" / "sofa" / "scene.py"
    namespace: dict[str, Any] = {"__file__": str(scene)}
    exec(compile(scene.read_text(), str(scene), "exec"), namespace)
    root = namespace["createScene"](_Node())
    body = root.children[0]
    kinds = {k: d for k, d in body.objects}
    m = manifest.targets["sofa"].material
    ff = kinds["TetrahedronHyperelasticityFEMForceField"]
    assert ff["materialName"] == "NeoHookean"
    assert ff["ParameterSet"] == pytest.approx([m.mu_pa, m.youngs_modulus_pa / (3 * (1 - 2 * m.poisson_ratio))])
    assert Path(kinds["MeshVTKLoader"]["filename"]).is_file()
    assert kinds["MeshMatrixMass"]["massDensity"] == m.density_kg_per_m3
    assert root.gravity == [0.0, 0.0, -9.81]


def test_bad_input_is_one_error_line_and_writes_nothing(
        asset: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    code, err = run_cli(["export", str(tmp_path / "nope"), "--to", "sofa"], monkeypatch, capsys)
    assert code == 2 and err.startswith("error:") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "nope").exists()

    code, err = run_cli(["export", str(asset), "--to", "ansys"], monkeypatch, capsys)
    assert code == 2 and "unknown export target ansys" in err

    record = json.loads((asset / "material.json").read_text())
    (asset / "material.json").write_text(json.dumps({**record, "passed": False}))
    code, err = run_cli(["export", str(asset), "--to", "sofa"], monkeypatch, capsys)
    assert code == 2 and "only a validated material is exported" in err

    (asset / "material.json").unlink()
    code, err = run_cli(["export", str(asset), "--to", "sofa"], monkeypatch, capsys)
    assert code == 2 and err.startswith("error:") and "material.json" in err
    assert sorted(p.name for p in (asset / "export").iterdir()) == ["physgaussian_config.json"]


def test_missing_package_names_the_extra(
        asset: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(registry.TARGETS, "usd", registry.Target("usd", "tasks.export.usd", "no_such_pkg_e25"))
    code, err = run_cli(["export", str(asset), "--to", "usd"], monkeypatch, capsys)
    assert code == 2 and err.strip() == 'error: export to usd needs the no_such_pkg_e25 package: pip install -e ".[export]"'
    assert sorted(p.name for p in (asset / "export").iterdir()) == ["physgaussian_config.json"]


def test_a_failing_target_leaves_the_earlier_export(asset: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from flows.export import export_asset
    from tasks.export import sofa

    export_asset(asset, "drake")
    before = sorted(p.name for p in (asset / "export").iterdir())

    def broken(inputs: Any, out_dir: Path) -> Any:
        (out_dir / "half.txt").write_text("half")
        raise RuntimeError("boom")

    monkeypatch.setattr(sofa, "export", broken)
    with pytest.raises(RuntimeError):
        export_asset(asset, "drake,sofa")
    assert sorted(p.name for p in (asset / "export").iterdir()) == before
    assert set(ExportManifest.model_validate_json((asset / "export" / "manifest.json").read_text()).targets) == {
        "drake"}
    with pytest.raises(RuntimeError):  # a first export that fails leaves no folder behind
        export_asset(asset, "sofa", asset / "elsewhere")
    assert not (asset / "elsewhere").exists()


@pytest.mark.slow
def test_real_sponge_export_steps_one_second_in_drake(tmp_path: Path) -> None:
    """The stuffed tet mesh of the sponge, exported to Drake: 1 s of simulated time (SAP, dt 10 ms) without NaN, resting
    on the ground (about 10-15 s)."""
    pytest.importorskip("pydrake")
    from flows.export import export_asset
    from tasks.export.drake import load_and_step

    asset = copy_sponge(tmp_path / "sponge")
    manifest = export_asset(asset, "drake")
    quality = json.loads((asset / "export" / "tetmesh" / "quality.json").read_text())
    assert quality["inverted_count"] == 0 and quality["volume_error_rel"] < 0.02
    run = load_and_step(asset / "export" / "drake", duration_s=1.0, time_step_s=0.01)
    before, after = np.asarray(run["positions_before_m"]), np.asarray(run["positions_after_m"])
    assert np.isfinite(after).all()
    assert after[:, 2].min() > -1e-3 and abs(after[:, 2].mean() - before[:, 2].mean()) < 5e-3  # rests, no collapse
    assert manifest.targets["drake"].mapping == ""  # neo-Hookean in Drake: the same model
