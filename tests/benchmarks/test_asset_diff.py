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
