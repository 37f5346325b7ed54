"""A pressurised shell is exported at its wall's modulus (issue #39): where an export writes a Young's modulus it
writes the rubber's E plus the modulus the inflation gas adds (material.gas_modulus_pa, tasks.realworld.inflation),
and it records that this is a homogenised wall modulus (the manifest's material, each README, the PhysGaussian
config); a solid's exports are byte for byte what they were before."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from contracts.asset_dir import ParticleBody
from tasks.asset_dir import AssetDir
from tasks.export import inputs as export_inputs
from tasks.export import registry
from tasks.export.physgaussian import write_physgaussian_export
from tests.export.assets import copy_sponge
from tests.export.test_adopted_material import _exported, _usd
from tests.export.test_export_cmd import grid_tets

GAS_PA = 1.36e7  # the tennis shell's dE_gas at its built wall (docs/REALWORLD.md, session 33)
PRESSURE_PA, SOURCE = 82.7e3, "12 psi over the ambient (a test's)"

# The committed sponge's export (every target, the stand-in mesher) and its PhysGaussian config, file by file, as the
# code wrote them before pressurised shells were exported at their wall's modulus (5663e5b); manifest.json with the
# asset's path replaced by ASSET. A change here changes every solid asset's export: say so in the CHANGELOG.
SOLID_EXPORT_SHA256 = {
    "drake/README.md": "b58fba75a75e2ca5834bb50adb8db842618fdecfc9789d8674d9e05b6a2218fb",
    "drake/ground.sdf": "4ba536a6b7f0e87745f6b2a4b6aadce654771f9e7cc3a3c1830e1160fdf9f8c3",
    "drake/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "drake/kitchen_sponge.sdf": "a5615b2a27ac3bd4e09524f4fdd2062da180d404f0a7260ba07f4204f73e98c3",
    "drake/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
    "genesis/README.md": "992e9f4e35eb129431d72a74182b2ff3ca744da96b9c79b140088f66d660bc61",
    "genesis/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "genesis/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
    "genesis/kitchen_sponge_surface.obj": "b4d7e22d056eb0f3da68e4fdfe26c4f805969a50ec2264b9f796b68805920304",
    "genesis/params.json": "349fc690eaf91191854f544dd74fb62969aec76d63d47776ddab9f8bc4e81cdb",
    "genesis/scene.py": "94c76551bfe4dd45758cafdee5fee89d80bb330993d7770fc6a01ab6ac20660a",
    "manifest.json": "1b80eccdbb9f49941f081f6d5c43145f132188f27ec76aa5287467591cf49aad",
    "mujoco/README.md": "d6817359d908c2e0f809e4ea9b1624eb3e7f68f213f82b77653beeb5e3536cae",
    "mujoco/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "mujoco/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
    "mujoco/kitchen_sponge.xml": "bbe2a3867d4e5658d6b42b9db1446d22a5c822784e9f06537034e3545d675ac9",
    "mujoco/parameters.json": "c1de78c2a669b43d8d1083f95c97329ed3a40784cf869b835ea177a9df900aad",
    "physgaussian_config.json": "91b46a5a7d8a9843b9bce62994a879aa86644675055c209714ad48c97671333d",
    "sofa/README.md": "9fb514210b57e74daf24b43613154c6efaf3d24c274a3478abd4b10caabf068c",
    "sofa/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "sofa/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
    "sofa/scene.py": "f2bf3111aee3533664d25d5d435dfbcd3088f772e6a9b6dda3f2daf1cd7a0879",
    "tetmesh/README.md": "4df214aa59044f310e5bf8abf95f58564d2baab1f6f042ba062ed24338bb1676",
    "tetmesh/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "tetmesh/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
    "tetmesh/quality.json": "16fccf75f3801624935d30eeff352e41281188373fb2a12c463ad27f43ff9611",
    "usd/README.md": "7c242dd1e8db43babd1f9f59757193ae92d88c38bd19527e96ffa9c1efdf72ea",
    "usd/kitchen_sponge.msh": "f706fd14efda3212a2a3e84f95476973c76cba4964e040443b0062e96130339f",
    "usd/kitchen_sponge.usda": "2c3b5d5990f9fd54707fcb91003bbdda206a064b54444b7b67c541f350677b1c",
    "usd/kitchen_sponge.vtk": "070c002796b6b7431804cd8821bf5a38e7fc1cbabbcf595ee6a0691d2e0f7e54",
}


@pytest.fixture
def asset(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> AssetDir:
    """A copy of the committed sponge (a solid: L0-L2, asset.json), meshed for export by the stand-in."""
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None)
    return AssetDir(copy_sponge(tmp_path / "sponge"))


def _pressurise(adir: AssetDir) -> float:
    """Make the asset a pressurised shell as L0 and L2 record one: geometry.json's particles a shell with its gas,
    material.json's material with the gas's modulus and its `inflation` record. Returns the rubber's E."""
    geometry = adir.geometry()
    phys = adir.physical_model()
    body = ParticleBody(kind="shell", wall_m=0.003, requested_wall_m=0.003, spacing_m=phys.particle_spacing_m,
                        volume_m3=phys.volume_m3, enclosed_volume_m3=2.0 * phys.volume_m3,
                        gauge_pressure_pa=PRESSURE_PA, gauge_pressure_source=SOURCE)
    adir.write_geometry(geometry.model_copy(update={"particles": body}))
    record = adir.material()
    assert record.material is not None
    rubber = record.material.youngs_modulus_pa
    material = record.material.model_copy(update={"gas_modulus_pa": GAS_PA})
    adir.write_material(record.model_copy(update={"material": material, "inflation": {
        "gauge_pressure_pa": PRESSURE_PA, "source": SOURCE, "radius_m": 0.033, "wall_m": 0.003,
        "poisson_ratio": material.poisson_ratio, "gas_modulus_pa": GAS_PA, "rubber_youngs_modulus_pa": rubber,
        "wall_modulus_pa": material.wall_modulus_pa, "model": "homogenised equivalent, not a gas simulation"}}))
    return rubber


def _digests(export_root: Path, asset_dir: Path) -> dict[str, str]:
    out = {}
    for p in sorted(export_root.rglob("*")):
        if p.is_file():
            data = p.read_bytes()
            if p.name == "manifest.json":
                data = data.replace(str(asset_dir.resolve()).encode(), b"ASSET")
            out[str(p.relative_to(export_root))] = hashlib.sha256(data).hexdigest()
    return out


def test_a_solids_exports_are_byte_for_byte_as_before(asset: AssetDir) -> None:
    from flows.export import export_asset

    export_asset(asset.path, "all" if _usd() else "mujoco,genesis,drake,sofa")
    write_physgaussian_export(asset)
    got = _digests(asset.path / "export", asset.path)
    want = {k: v for k, v in SOLID_EXPORT_SHA256.items() if _usd() or not k.startswith("usd/")}
    assert got == want
    assert "homogenised_wall" not in export_inputs.export_material(asset).model_dump(mode="json")


def test_a_pressurised_shell_is_exported_at_its_wall_modulus_and_says_so(asset: AssetDir) -> None:
    from flows.export import export_asset

    rubber = _pressurise(asset)
    wall = rubber + GAS_PA
    assert asset.adopted_material().material.wall_modulus_pa == wall
    export = export_asset(asset.path, "all" if _usd() else "mujoco,genesis,drake,sofa")
    for name, target in export.targets.items():
        m = target.material
        assert m.youngs_modulus_pa == wall and m.gas_modulus_pa == 0.0, name  # not the rubber's, not counted twice
        assert m.mu_pa == pytest.approx(wall / (2 * (1 + m.poisson_ratio)), rel=1e-12), name
        w = m.homogenised_wall
        assert w is not None and (w.rubber_youngs_modulus_pa, w.gas_modulus_pa, w.wall_modulus_pa) == \
            (rubber, GAS_PA, wall), name
        assert (w.gauge_pressure_pa, w.gauge_pressure_source) == (PRESSURE_PA, SOURCE), name
        assert "homogenised wall modulus" in w.note, name
        readme = (asset.path / "export" / name / "README.md").read_text(encoding="utf-8")
        assert "homogenised wall modulus" in readme and f"{rubber:.6g} Pa" in readme, name
    manifest = json.loads((asset.path / "export" / "manifest.json").read_text(encoding="utf-8"))
    assert all(t["material"]["homogenised_wall"]["wall_modulus_pa"] == wall for t in manifest["targets"].values())
    slug = export_inputs.load_export_inputs(asset.path).slug
    for name, (e, _, _) in _exported(asset.path / "export", slug).items():  # each simulator's own file
        assert e == pytest.approx(wall, rel=1e-6), name
    config = json.loads(write_physgaussian_export(asset).read_text(encoding="utf-8"))
    assert config["E"] == wall and config["homogenised_wall"]["rubber_youngs_modulus_pa"] == rubber
