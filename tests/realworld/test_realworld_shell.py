"""`bench realworld --hollow-shell`: the hollow rule balls built as their wall (and gas), as `geometry --hollow-shell`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from contracts.realworld import REALWORLD_YAML, load_realworld
from flows.realworld import run_realworld, slug


@pytest.mark.slow  # L0 and L1 of a tennis ball through the Prefect flows: ~1-3 min on the loaded 2-core VM
def test_the_bench_builds_a_hollow_ball_as_its_shell_with_its_gas_when_asked(tmp_path: Path) -> None:
    tennis = [o for o in load_realworld(REALWORLD_YAML).objects if o.name == "tennis ball"]
    report = run_realworld(tennis, tmp_path, priors_only=True, hollow_shell=True)
    assert report.objects[0].status == "ok", report.objects[0].error
    record = json.loads((tmp_path / slug("tennis ball") / "geometry.json").read_text())
    assert record["particles"]["kind"] == "shell" and record["particles"]["gauge_pressure_pa"] > 5e4
    assert 0.045 <= report.objects[0].ours.mass_kg <= 0.065  # still the rule's 56-59.4 g ball
