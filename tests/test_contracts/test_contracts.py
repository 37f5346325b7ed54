"""Contracts: every stage file validates; malformed files and bad values fail with a precise message."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from pydantic import ValidationError

from contracts import AssetRequest, ContractError, Material, ShapeProgram, load_contract, load_contract_file
from contracts.errors import validation_message
from contracts.registry import SCHEMAS
from contracts.stage import STAGE_FILES, STAGES_DIR


@pytest.mark.parametrize("stage", sorted(STAGE_FILES))
def test_every_stage_contract_file_validates(stage: str) -> None:
    contract = load_contract(stage)  # type: ignore[arg-type]
    assert contract.stage == stage
    assert contract.hard_gates and contract.permitted_actions
    gate_metrics = {g.metric for g in contract.hard_gates}
    assert gate_metrics <= set(contract.required_observations)


def test_malformed_contract_names_file_and_field(tmp_path: Path) -> None:
    data = yaml.safe_load((STAGES_DIR / STAGE_FILES["L2"]).read_text())
    data["editable_fields"][0]["low"] = "not-a-number"
    bad = tmp_path / "L2_material.yaml"
    bad.write_text(yaml.safe_dump(data))
    with pytest.raises(ContractError) as info:
        load_contract_file(bad)
    msg = str(info.value)
    assert str(bad) in msg and "editable_fields.0.low" in msg


def test_contract_with_unobserved_gate_is_rejected(tmp_path: Path) -> None:
    data = yaml.safe_load((STAGES_DIR / STAGE_FILES["L1"]).read_text())
    data["required_observations"].remove("mass_kg")
    data["hard_gates"].append({"name": "mass", "metric": "mass_kg", "op": "<=", "threshold": 10})
    bad = tmp_path / "c.yaml"
    bad.write_text(yaml.safe_dump(data))
    with pytest.raises(ContractError, match="mass_kg"):
        load_contract_file(bad)


def test_unreadable_yaml_is_a_clear_error(tmp_path: Path) -> None:
    bad = tmp_path / "c.yaml"
    bad.write_text("stage: [L0\n")
    with pytest.raises(ContractError, match="not valid YAML"):
        load_contract_file(bad)


def test_gates_evaluate_values_and_reject_missing_or_nan() -> None:
    contract = load_contract("L2")
    good = {"finite": 1, "in_domain": 1, "engine_health_ok": 1, "j_min": 0.8, "j_max": 1.2, "ground_tunnelling_m": 0.0,
            "stable_long_rollout": 1}
    assert contract.failed_gates(good) == []
    assert [g.metric for g in contract.failed_gates({**good, "j_min": math.nan})] == ["j_min"]
    missing = dict(good)
    del missing["finite"]
    assert [g.metric for g in contract.failed_gates(missing)] == ["finite"]


@pytest.mark.parametrize("kwargs", [
    {"youngs_modulus_pa": 0.0, "poisson_ratio": 0.3},
    {"youngs_modulus_pa": 1e5, "poisson_ratio": 0.5},
    {"youngs_modulus_pa": float("nan"), "poisson_ratio": 0.3},
    {"youngs_modulus_pa": 1e5, "poisson_ratio": 0.3, "damping_rate_per_s": -1.0},
])
def test_invalid_material_is_rejected(kwargs: dict) -> None:
    with pytest.raises(ValidationError):
        Material(**kwargs)


def test_lame_parameters_match_their_definitions() -> None:
    m = Material(youngs_modulus_pa=1e5, poisson_ratio=0.3)
    assert m.mu_pa == pytest.approx(1e5 / 2.6)
    assert m.lambda_pa == pytest.approx(1e5 * 0.3 / (1.3 * 0.4))
    assert m.p_wave_speed_m_per_s(200.0) == pytest.approx(math.sqrt((m.lambda_pa + 2 * m.mu_pa) / 200.0))


def test_request_needs_exactly_one_geometry_source(tmp_path: Path) -> None:
    with pytest.raises(ValidationError):
        AssetRequest()
    with pytest.raises(ValidationError):
        AssetRequest(image_path=tmp_path / "a.png", mesh_path=tmp_path / "a.obj")
    assert AssetRequest(text="a sponge").input_kind == "text"
    assert AssetRequest(text="a sponge", image_path=tmp_path / "a.png").input_kind == "image"


def test_unknown_fields_are_rejected() -> None:
    with pytest.raises(ValidationError):
        Material(youngs_modulus_pa=1e5, poisson_ratio=0.3, youngs_modulus=3)


def test_validation_message_is_one_line_naming_fields_and_values() -> None:
    with pytest.raises(ValidationError) as bad_values:
        Material(youngs_modulus_pa=-5.0, poisson_ratio=0.7)
    names = {"youngs_modulus_pa": "E [Pa]"}
    text = validation_message(bad_values.value, names=names, with_input=True)
    assert "\n" not in text
    assert text.startswith("E [Pa] = -5.0: ") and "; poisson_ratio = 0.7: " in text
    assert validation_message(bad_values.value, limit=1).count(";") == 0
    with pytest.raises(ValidationError) as whole_model:  # a model validator's error: no field, no pydantic prefix
        AssetRequest()
    text = validation_message(whole_model.value)
    assert text and not text.startswith(("Value error", ":")) and "\n" not in text


def test_shape_program_roundtrips_through_json() -> None:
    prog = ShapeProgram.model_validate({
        "name": "ball", "category": "ball",
        "parts": [{"primitive": {"kind": "ellipsoid", "radii_m": [0.05, 0.05, 0.05]}, "color_rgb": [1, 0, 0]}],
    })
    again = ShapeProgram.model_validate_json(prog.model_dump_json())
    assert again == prog and again.canonical_json() == prog.canonical_json()


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "flows.cli.main", *args], capture_output=True, text=True, timeout=120)


def test_schema_command_prints_json_schema_of_every_model() -> None:
    out = _cli("schema", "Material")
    assert out.returncode == 0, out.stderr
    schema = json.loads(out.stdout)
    assert "youngs_modulus_pa" in schema["properties"]
    assert set(SCHEMAS) >= {"AssetRequest", "ShapeProgram", "StageContract", "Attempt", "AssetManifest"}


def test_schema_command_unknown_name_is_one_line_error() -> None:
    out = _cli("schema", "Nope")
    assert out.returncode != 0
    assert out.stderr.strip().count("\n") == 0 and out.stderr.startswith("error: unknown schema")
