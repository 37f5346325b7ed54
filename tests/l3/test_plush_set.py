"""The developers' plush set (not the evaluation suite): six plush animals of 15-35 cm, each generated from text at
draft quality on the CPU (`deformsmith generate`, L0 -> L3), must each pass L3; an object whose grasp is
wider than 8 cm is picked with the wide gripper. `python tests/l3/test_plush_set.py OUT.json` (PLUSH_SET_DIR: where
the assets go) runs the set and writes the rows recorded in tasks/manipulation/BENCHMARKS.md."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pytest

PLUSH_SET = (
    "a plush elephant about 30 cm long",
    "a plush dog 20 cm",
    "a teddy bear 25 cm tall",
    "a plush bunny 20 cm",
    "a plush cat 22 cm",
    "a plush penguin 18 cm",
)
WIDE_M = 0.08


def run_plush(text: str, out_dir: Path, cpu_threads: int = 2) -> dict[str, Any]:
    """Generate one plush asset (CLI, draft, CPU) and read back L3's record: outcome, gripper, forces, wall time."""
    t0 = time.perf_counter()
    env = {**os.environ, "DEFORMSMITH_PROBE_WORKERS": os.environ.get("DEFORMSMITH_PROBE_WORKERS", "2")}
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "generate", text, "--out", str(out_dir),
                           "--cpu-threads", str(cpu_threads)], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    row: dict[str, Any] = {"text": text, "exit": proc.returncode, "wall_s": round(wall, 1)}
    path = out_dir / "manipulation.json"
    if not path.is_file():
        row["error"] = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no manipulation.json"]
        row["passed"] = False
        return row
    rec = json.loads(path.read_text(encoding="utf-8"))
    labels = rec.get("labels") or (rec.get("best_attempt") or {}).get("labels") or {}
    plan = rec.get("plan") or (rec.get("best_attempt") or {}).get("plan") or {}
    grasp = plan.get("grasp") or {}
    row.update({
        "passed": bool(rec.get("passed")), "reason": rec.get("reason", ""),
        "gripper": plan.get("gripper"), "grasp_width_m": grasp.get("width_m"),
        "extents_m": rec.get("physical_model", {}).get("extents_m"), "mass_kg": labels.get("mass_kg"),
        "force_target_n": labels.get("grip_force_target_n"),
        "max_finger_force_n": [labels.get("max_finger_force_0_n"), labels.get("max_finger_force_1_n")],
        "hold_normal_force_n": labels.get("hold_normal_force_n"),
        "hold_friction_ratio": labels.get("hold_friction_ratio"),
        "squeeze_per_finger_m": labels.get("squeeze_per_finger_m"), "lift_rise_m": labels.get("lift_rise_m"),
        "strain_p99": labels.get("strain_p99"), "trials": len(rec.get("attempts", [])),
        "held_out_success": (rec.get("held_out") or {}).get("success_rate"),
    })
    return row


@pytest.mark.slow
def test_the_plush_set_passes_l3(tmp_path: Path) -> None:
    rows = [run_plush(text, tmp_path / f"plush_{i}") for i, text in enumerate(PLUSH_SET)]
    print(json.dumps(rows, indent=1))
    # every toy of the set (#36: the penguin, carried to its target and then falling over, included)
    assert all(r["passed"] for r in rows), [(r["text"], r.get("reason") or r.get("error")) for r in rows if not r["passed"]]
    for r in rows:  # wider than the Franka Hand's 80 mm stroke: a wider gripper; wider than 85 mm: the 2F-140
        if r.get("grasp_width_m") and r["grasp_width_m"] > WIDE_M:
            assert r["gripper"] != "franka_hand", r
        if r.get("grasp_width_m") and r["grasp_width_m"] > 0.085:
            assert r["gripper"] == "robotiq_2f140", r
        if r["passed"]:
            assert max(r["max_finger_force_n"]) <= 20.0
            assert r["hold_friction_ratio"] >= 1.0  # 2 mu N >= m g while held


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("plush_set.json")
    work = Path(os.environ.get("PLUSH_SET_DIR") or tempfile.mkdtemp(prefix="plush_set-"))
    results = []
    for i, text in enumerate(PLUSH_SET):
        results.append(run_plush(text, work / f"plush_{i}"))
        print(json.dumps(results[-1]), flush=True)
        out.write_text(json.dumps(results, indent=1), encoding="utf-8")
