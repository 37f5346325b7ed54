"""The paper's Table III figures and this project's targets (issue 9), per ablation and metric."""

from __future__ import annotations

# metric -> (baseline, ours) as fractions (sim calls as counts); None where the paper gives no figure
PAPER: dict[str, dict[str, tuple[float | None, float | None]]] = {
    "hierarchy": {"delivery": (0.83, 0.93), "physics_pass": (0.80, 0.87), "sim_calls": (None, None)},
    "harness": {"target_satisfaction": (0.40, 0.73), "hard_failure": (0.17, 0.07), "sim_calls": (None, 14.0)},
    "manipulation": {"task_success": (0.40, 0.67), "material_pass": (0.67, 0.83), "joint_success": (0.27, 0.57)},
}
# metric -> (op, threshold) that our full pipeline ("ours" arm) must reach
TARGETS: dict[str, tuple[str, float]] = {
    "delivery": (">=", 0.97), "physics_pass": (">=", 0.95), "target_satisfaction": (">=", 0.90),
    "hard_failure": ("<=", 0.03), "sim_calls": ("<=", 14.0), "task_success": (">=", 0.85),
    "material_pass": (">=", 0.90), "joint_success": (">=", 0.80),
}
# higher is better for every metric except these
LOWER_IS_BETTER = {"hard_failure", "sim_calls"}
