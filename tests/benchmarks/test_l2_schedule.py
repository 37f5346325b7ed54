"""`python -m benchmarks.l2_schedule`: its options, the driver's signature, and the intent it defaults to."""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from benchmarks.l2_schedule import app, physical_intent, run_l2_bench


def test_the_default_intent_is_the_one_l1_ran_with(tmp_path: Path) -> None:
    """No physical.json: no intent; else the intent L1 recorded."""
    assert physical_intent(tmp_path) is None
    (tmp_path / "physical.json").write_text(json.dumps({"intent": "a soft foam"}), encoding="utf-8")
    assert physical_intent(tmp_path) == "a soft foam"


def test_the_command_calls_the_driver_with_its_options_in_order() -> None:
    """The command passes (asset, intent, schedules, probes, device, repeat) positionally."""
    assert list(inspect.signature(run_l2_bench).parameters) == ["asset_dir", "intent", "schedules", "probes", "device",
                                                                  "repeat"]


@pytest.fixture
def stub_asset(tmp_path: Path) -> Path:
    """A directory that looks like an asset (option checks come before any probe runs)."""
    d = tmp_path / "asset"
    d.mkdir()
    (d / "geometry.json").write_text(json.dumps({"files": {}}))
    return d


def test_bench_l2_rejects_unknown_schedules_and_probes(stub_asset: Path) -> None:
    """`python -m benchmarks.l2_schedule`: a bad --schedule / --probe is one clear line, before anything runs."""
    runner = CliRunner()
    res = runner.invoke(app, ["--asset", str(stub_asset), "--schedule", "threads", "--json"])
    assert res.exit_code == 2 and "unknown schedule(s) threads" in res.output
    res = runner.invoke(app, ["--asset", str(stub_asset), "--probe", "lift", "--json"])
    assert res.exit_code == 2 and "unknown probe(s) lift" in res.output
