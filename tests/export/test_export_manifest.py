"""The export root's manifest.json (tasks.export.manifest): read back when valid, a crosscheck's calibration recorded
on its target with the files it wrote; and the volume a surface encloses (tasks.export.tetmesh), which the tet mesh's
quality figures are measured against."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contracts.export import ExportManifest, ExportMaterial, TargetManifest
from tasks.export.manifest import MANIFEST, read_manifest, record_calibration
from tasks.export.tetmesh import enclosed_volume_m3

MATERIAL = ExportMaterial(youngs_modulus_pa=1e5, poisson_ratio=0.3, damping_rate_per_s=1.0, density_kg_per_m3=100.0,
                          ground_friction=0.5, gripper_friction=0.8, mass_kg=0.1)


def test_a_calibration_is_recorded_on_its_target(tmp_path: Path) -> None:
    assert read_manifest(tmp_path) is None
    record_calibration(tmp_path, "mujoco", {"files": ["mujoco/x.xml"]})  # no manifest: nothing written
    assert not (tmp_path / MANIFEST).exists()
    (tmp_path / MANIFEST).write_text("{broken")
    assert read_manifest(tmp_path) is None
    target = TargetManifest(target="mujoco", files=["mujoco/a.xml"], load_hint="load", material=MATERIAL)
    (tmp_path / MANIFEST).write_text(ExportManifest(asset="a", tet_mesh="tetmesh/a.vtk",
                                                    targets={"mujoco": target}).model_dump_json())
    record_calibration(tmp_path, "drake", {"files": ["drake/x.sdf"]})  # a target it does not have: left alone
    record_calibration(tmp_path, "mujoco", {"parameters": {"young_pa": 2e5}, "files": ["mujoco/a.xml", "mujoco/b"]})
    manifest = read_manifest(tmp_path)
    assert manifest is not None and list(manifest.targets) == ["mujoco"]
    assert manifest.targets["mujoco"].files == ["mujoco/a.xml", "mujoco/b"]
    assert manifest.targets["mujoco"].calibrated == {"parameters": {"young_pa": 2e5},
                                                     "files": ["mujoco/a.xml", "mujoco/b"]}


def test_the_enclosed_volume_of_a_closed_surface() -> None:
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64) * 2.0
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # outward
    assert np.isclose(enclosed_volume_m3(v, f), 8.0 / 6.0)
    assert np.isclose(enclosed_volume_m3(v, f[:, ::-1]), -8.0 / 6.0)  # inward faces: negative
