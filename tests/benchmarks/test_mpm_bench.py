"""`python -m benchmarks.mpm_bench`: the MPM step on the standard cube scene (was tasks/mpm/bench.py and
`deformsmith bench mpm`)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from benchmarks.mpm_bench import app, run_bench
from contracts.errors import InputError


def test_bench_compares_the_batch_with_its_scenes_one_after_another() -> None:
    """`--batch B --compare-sequential`: B single-scene runs beside the batch, both ratios from the same process; a
    batch of one has nothing to compare and is refused."""
    res = run_bench("cpu", particles=216, steps=4, batch=2, workers=1, compare_sequential=True)
    cmp = res["sequential_comparison"]
    assert cmp["scenes"] == 2 and len(cmp["single_us_per_step"]) == 2
    assert cmp["batch_us_per_step"] == res["us_per_step"]
    assert cmp["sequential_us_per_step"] == pytest.approx(sum(cmp["single_us_per_step"]))
    assert cmp["ratio_per_step"] == pytest.approx(cmp["sequential_us_per_step"] / res["us_per_step"])
    assert cmp["ratio_end_to_end"] == pytest.approx(cmp["sequential_rollouts_s"] / cmp["batch_rollout_s"])
    assert min(cmp["single_us_per_step"]) > 0 and cmp["batch_rollout_s"] > 0
    assert run_bench("cpu", particles=216, steps=2, batch=2)["sequential_comparison"] is None
    with pytest.raises(InputError):
        run_bench("cpu", particles=216, steps=2, batch=1, compare_sequential=True)


def test_bench_cli_prints_both_ratios_and_refuses_a_batch_of_one() -> None:
    runner = CliRunner()
    res = runner.invoke(app, ["--particles", "216", "--steps", "3", "--batch", "2", "--workers", "1",
                              "--compare-sequential", "--json"])
    assert res.exit_code == 0, res.output
    cmp = json.loads(res.stdout)["sequential_comparison"]
    assert cmp["ratio_per_step"] > 0 and cmp["ratio_end_to_end"] > 0
    bad = runner.invoke(app, ["--particles", "216", "--steps", "3", "--compare-sequential"])
    assert bad.exit_code == 2 and "--batch >= 2" in bad.output
