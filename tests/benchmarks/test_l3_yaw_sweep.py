"""The yaw-sweep tool: its input errors and its per-frame summary."""

from __future__ import annotations

import math
from typing import Any

from benchmarks.l3_yaw_sweep import main, summarise


def test_a_folder_without_an_l2_material_is_refused(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main([str(tmp_path)]) == 2
    assert "not an L2 asset directory" in capsys.readouterr().err


def test_bad_yaws_are_refused(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    (tmp_path / "material.json").write_text("{}")
    assert main([str(tmp_path), "--yaws", "0,north"]) == 2
    assert "comma-separated numbers" in capsys.readouterr().err


def test_the_summary_counts_lifts_per_frame_and_averages_the_hold_force_of_lifts() -> None:
    rows: list[dict[str, Any]] = [{"frame": None, "lifted": True, "success": True, "hold_normal_force_n": 1.0},
            {"frame": None, "lifted": False, "success": False, "hold_normal_force_n": math.nan},
            {"frame": 45.0, "lifted": True, "success": False, "hold_normal_force_n": 2.0},
            {"frame": 45.0, "lifted": True, "success": True, "hold_normal_force_n": 3.0},
            {"frame": 45.0, "error": "unreachable"}]
    s = summarise(rows)
    assert s["none"] == {"trials": 2, "lifted": 1, "succeeded": 1,
                         "hold_normal_force_n": {"mean": 1.0, "min": 1.0, "max": 1.0}}
    assert s["45"]["trials"] == 2 and s["45"]["lifted"] == 2 and s["45"]["succeeded"] == 1
    assert s["45"]["hold_normal_force_n"]["mean"] == 2.5
