"""benchmarks.asset_diff: two asset directories compared file by file, numbers by their relative difference."""

from __future__ import annotations

import json
from pathlib import Path

from benchmarks import asset_diff


def _asset(root: Path, drift: float, key: str) -> Path:
    root.mkdir(parents=True)
    (root / "material.json").write_text(json.dumps({"metrics": {"rebound": 0.5, "late_drift_ratio": drift},
                                                    "passed": True, "cache_key": key}))
    (root / "mesh.bin").write_bytes(b"\x00\x01")
    return root


def test_equal_assets_are_equal_file_by_file(tmp_path: Path) -> None:
    a, b = _asset(tmp_path / "a", 0.01, "k1"), _asset(tmp_path / "b", 0.01, "k1")
    report = asset_diff.diff(a, b)
    assert report["equal"] == report["files"] == 2 and report["differ"] == {}


def test_differing_numbers_and_values_are_reported(tmp_path: Path) -> None:
    a, b = _asset(tmp_path / "a", 0.010, "k1"), _asset(tmp_path / "b", 0.012, "k2")
    (b / "extra.txt").write_text("x")
    report = asset_diff.diff(a, b)
    entry = report["differ"]["material.json"]
    assert abs(entry["max_rel"] - 0.002 / 0.012) < 1e-9 and entry["max_at"] == "/metrics/late_drift_ratio"
    assert entry["values"] == [{"at": "/cache_key", "a": "k1", "b": "k2"}]
    assert report["only_in_b"] == ["extra.txt"] and report["equal"] == 1


def test_a_missing_directory_is_an_error(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    assert asset_diff.main([str(tmp_path / "none"), str(tmp_path)]) == 2
    assert "is not a directory" in capsys.readouterr().err


def _run(root: Path, *, rebound: float, passed: bool, key: str, video: bytes = b"v") -> Path:
    root.mkdir(parents=True)
    (root / "asset.json").write_text(json.dumps({
        "validation": [{"passed": passed, "metrics": {"rebound": rebound, "late_drift_ratio": 2e-5 + rebound * 1e-6}}],
        "provenance": {"cache_keys": {"l2.selection.0": key}},
        "recording": f"recordings/L2_drop-{key[:11]}"}))
    (root / "evidence").mkdir()
    (root / "evidence" / "attempts.jsonl").write_text(json.dumps({"adopted": passed, "E_pa": 3.0e4}) + "\n")
    (root / "drop.mp4").write_bytes(video)
    return root


def test_gpu_noise_is_equivalent_but_not_equal(tmp_path: Path) -> None:
    a = _run(tmp_path / "a", rebound=0.300, passed=True, key="90013e83e4340eb629f9", video=b"one")
    b = _run(tmp_path / "b", rebound=0.303, passed=True, key="96481ee3a4feaf4b8e7e", video=b"two")
    report = asset_diff.diff(a, b)
    assert report["differ"]["asset.json"]["keys"] and not report["differ"]["asset.json"]["values"]
    verdict = asset_diff.equivalence(report)
    assert verdict["equivalent"] and verdict["unchecked_by_bytes"] == ["drop.mp4"]
    assert asset_diff.main([str(a), str(b), "--equivalent"]) == 0


def test_a_flipped_decision_or_a_far_number_is_another_asset(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    a = _run(tmp_path / "a", rebound=0.30, passed=True, key="90013e83e4340eb629f9")
    b = _run(tmp_path / "b", rebound=0.30, passed=False, key="90013e83e4340eb629f9")
    broken = asset_diff.equivalence(asset_diff.diff(a, b))["broken"]
    assert {(x["file"], x["why"]) for x in broken} == {("asset.json", "decision differs"),
                                                       ("evidence/attempts.jsonl", "decision differs")}
    c = _run(tmp_path / "c", rebound=0.36, passed=True, key="90013e83e4340eb629f9")
    verdict = asset_diff.equivalence(asset_diff.diff(a, c))
    assert not verdict["equivalent"]
    assert [x["at"] for x in verdict["broken"]] == ["/validation/0/metrics/rebound"]
    assert asset_diff.equivalence(asset_diff.diff(a, c), rtol=0.25)["equivalent"]
    assert asset_diff.main([str(a), str(c), "--equivalent"]) == 1
    assert "number out of tolerance" in capsys.readouterr().out


def test_a_file_in_one_run_only_is_another_asset(tmp_path: Path) -> None:
    a = _run(tmp_path / "a", rebound=0.3, passed=True, key="90013e83e4340eb629f9")
    b = _run(tmp_path / "b", rebound=0.3, passed=True, key="90013e83e4340eb629f9")
    (b / "extra.json").write_text("{}")
    verdict = asset_diff.equivalence(asset_diff.diff(a, b))
    assert not verdict["equivalent"] and verdict["broken"] == [{"file": "extra.json", "why": "in one run only"}]
