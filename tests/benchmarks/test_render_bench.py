"""`python -m benchmarks.render_bench`: seconds per frame of the splat renderer (was tasks/render/bench.py)."""

from __future__ import annotations

from benchmarks.render_bench import run


def test_bench_reports_seconds_per_frame_and_gaussians() -> None:
    data = run(None, synthetic=300, width=64, height=48, repeats=1, devices=("cpu",))
    assert data["gaussians_per_frame"] == 300 and data["width"] == 64 and data["asset"].startswith("synthetic")
    assert data["cpu"]["deterministic"] and 0.0 < data["cpu"]["steady_s"] < 5.0 and data["cpu"]["threads"] >= 1
