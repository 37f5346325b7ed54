"""The typed asset directory (tasks/asset_dir.py) and the typed stage parameters (contracts/stage.py).

asset_fixture/ holds the JSON documents of a real turtle asset (CPU, draft) as the unmodified code wrote them.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from contracts.asset_dir import DOCUMENT_FILES, GeometryRecord, ManipulationRecord, MaterialRecord, PhysicalRecord
from contracts.errors import ContractError, InputError
from contracts.manifest import AssetManifest
from contracts.stage import L1Parameters, L2Parameters, L3Parameters, load_contract, packaged_parameters
from tasks.asset_dir import AssetDir

FIXTURE = Path(__file__).parent / "asset_fixture"
DOCUMENTS = ("geometry", "physical", "material", "manipulation", "manifest")


@pytest.fixture
def asset(tmp_path: Path) -> AssetDir:
    """A private copy of the fixture's documents."""
    shutil.copytree(FIXTURE, tmp_path / "turtle")
    return AssetDir(tmp_path / "turtle")


@pytest.mark.parametrize("name", DOCUMENTS)
def test_each_document_reads_typed_and_writes_back_byte_for_byte(asset: AssetDir, tmp_path: Path, name: str) -> None:
    doc = getattr(asset, name)()
    out = AssetDir(tmp_path / "out")
    out.write(name, doc)
    assert out.file(name).read_bytes() == (FIXTURE / DOCUMENT_FILES[name]).read_bytes()


def test_documents_are_typed_where_later_layers_read_them(asset: AssetDir) -> None:
    assert isinstance(asset.geometry(), GeometryRecord) and asset.geometry().info.category == "plush_animal"
    assert isinstance(asset.physical(), PhysicalRecord) and isinstance(asset.material(), MaterialRecord)
    assert isinstance(asset.manipulation(), ManipulationRecord) and isinstance(asset.manifest(), AssetManifest)
    assert asset.physical_model() == asset.manifest().physical_model
    assert asset.material_model() == asset.manifest().material
    assert asset.manipulation().plan == asset.manifest().action_plan


def test_a_legacy_record_without_a_later_key_keeps_it_absent(asset: AssetDir, tmp_path: Path) -> None:
    raw = json.loads(asset.file("geometry").read_text())
    del raw["request"]  # geometry.json written before it stored the request
    asset.file("geometry").write_text(json.dumps(raw))
    doc = asset.geometry()
    assert doc.request is None
    out = AssetDir(tmp_path / "out")
    out.write_geometry(doc)
    assert json.loads(out.file("geometry").read_text()) == raw


def test_a_record_built_by_its_layer_writes_its_defaults_too(asset: AssetDir, tmp_path: Path) -> None:
    raw = json.loads(asset.file("physical").read_text())
    given = {k: v for k, v in raw.items() if k not in ("schema_version", "stage")}  # as run_l1 builds it
    out = AssetDir(tmp_path / "out")
    out.write_physical(PhysicalRecord(**given))
    assert out.file("physical").read_bytes() == asset.file("physical").read_bytes()


@pytest.mark.parametrize("name", DOCUMENTS)
def test_a_missing_document_is_an_input_error_naming_the_file(tmp_path: Path, name: str) -> None:
    with pytest.raises(InputError, match=DOCUMENT_FILES[name].replace(".", r"\.")):
        getattr(AssetDir(tmp_path), name)()


def test_a_malformed_document_is_an_input_error_naming_the_file_and_the_field(asset: AssetDir) -> None:
    asset.file("physical").write_text("{not json")
    with pytest.raises(InputError, match=r"physical\.json: not valid JSON"):
        asset.physical()
    raw = json.loads((FIXTURE / "material.json").read_text())
    raw["material"]["poisson_ratio"] = 0.7
    del raw["targets"]
    asset.file("material").write_text(json.dumps(raw))
    with pytest.raises(InputError, match=r"material\.json: not a valid material document: .*targets") as err:
        asset.material()
    assert "poisson_ratio" in str(err.value)


def test_a_failed_stage_has_no_model_to_give(asset: AssetDir) -> None:
    raw = json.loads(asset.file("physical").read_text())
    raw.update(passed=False, status="no_valid_candidate", message="mass implausible", physical_model=None)
    asset.file("physical").write_text(json.dumps(raw))
    with pytest.raises(InputError, match="L1 did not produce a valid physical model .mass implausible"):
        asset.physical_model()


def test_writing_checks_the_document_type(asset: AssetDir) -> None:
    with pytest.raises(TypeError, match="physical.json takes a PhysicalRecord"):
        asset.write("physical", asset.material())


def test_stage_parameters_take_their_defaults_from_the_packaged_contract_alone() -> None:
    l3 = load_contract("L3")
    user = l3.model_copy(update={"parameters": {"lift_height_m": 0.05}})  # a user contract naming one setting
    p = L3Parameters.of(user)
    assert p.lift_height_m == 0.05 and p.place_tolerance_m == packaged_parameters("L3")["place_tolerance_m"]
    from contracts.robot import ActionPlan
    from tasks.manipulation.outcome import TrialTolerances

    lift = L3Parameters.of(l3).lift_height_m
    assert TrialTolerances().lift_height_m == lift and ActionPlan.model_fields["lift_height_m"].get_default(
        call_default_factory=True) == lift
    assert L1Parameters.of(load_contract("L1")).place_duration_s > 0
    assert L2Parameters.of(load_contract("L2")).specimen_particles_per_axis == 10
    bad = load_contract("L2").model_copy(update={"parameters": {"compression_strain": "a lot"}})
    with pytest.raises(ContractError, match="L2: invalid parameters: compression_strain"):
        L2Parameters.of(bad)
