"""Table III metrics from per-arm records: rates with N and a Wilson 95 % interval, mean simulation calls."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass, field

from contracts.evaluation import ARMS, ArmResult
from tasks.evaluation.paper import LOWER_IS_BETTER, TARGETS

METRICS: dict[str, tuple[str, ...]] = {
    "hierarchy": ("delivery", "physics_pass", "sim_calls"),
    "harness": ("target_satisfaction", "hard_failure", "sim_calls"),
    "manipulation": ("task_success", "material_pass", "joint_success"),
}


@dataclass
class Figure:
    """One aggregated figure: value, how many units it counts (k of n for rates) and where it came from."""

    value: float | None
    n: int
    k: float | None = None
    low: float | None = None
    high: float | None = None
    unit: str = "rate"
    sources: list[str] = field(default_factory=list)  # case ids (or case/condition) the figure aggregates

    def as_dict(self) -> dict:
        """JSON form."""
        return asdict(self)


def wilson(k: float, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval of a proportion k / n."""
    if n == 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    # at k = 0 or k = n the interval ends exactly at the rate (c - h / c + h equal it only up to round-off)
    lo = 0.0 if k <= 0 else max(0.0, c - h)
    hi = 1.0 if k >= n else min(1.0, c + h)
    return (lo, hi)


def rate(flags: list[tuple[str, bool]]) -> Figure:
    """Fraction of True among (source, flag) pairs."""
    n = len(flags)
    k = float(sum(1 for _, f in flags if f))
    lo, hi = wilson(k, n)
    return Figure(value=k / n if n else None, n=n, k=k, low=lo if n else None, high=hi if n else None,
                  sources=[s for s, _ in flags])


def mean(values: list[tuple[str, float]], unit: str = "calls") -> Figure:
    """Mean of (source, value) pairs."""
    n = len(values)
    return Figure(value=sum(v for _, v in values) / n if n else None, n=n, unit=unit, sources=[s for s, _ in values])


def arm_figures(ablation: str, records: list[ArmResult]) -> dict[str, Figure]:
    """The ablation's metrics over one arm's records (missing outputs count as failures)."""
    if ablation == "hierarchy":
        return {"delivery": rate([(r.case_id, r.delivered) for r in records]),
                "physics_pass": rate([(r.case_id, bool(r.delivered and r.physics_pass)) for r in records]),
                "sim_calls": mean([(r.case_id, float(r.sim_calls)) for r in records if r.delivered])}
    if ablation == "harness":
        return {"target_satisfaction": rate([(r.case_id, bool(r.delivered and r.target_satisfied)) for r in records]),
                "hard_failure": rate([(r.case_id, bool(r.hard_failure or not r.delivered)) for r in records]),
                "sim_calls": mean([(r.case_id, float(r.sim_calls)) for r in records if r.delivered])}
    trials = [(f"{r.case_id}#{i}", c) for r in records for i, c in enumerate(r.conditions)]
    return {"task_success": rate([(s, c.task_success) for s, c in trials]),
            "material_pass": rate([(s, c.material_pass) for s, c in trials]),
            "joint_success": rate([(s, c.task_success and c.material_pass) for s, c in trials])}


def aggregate(records: Iterable[ArmResult]) -> dict[str, dict[str, dict[str, Figure]]]:
    """ablation -> arm -> metric -> Figure, over whatever records exist (only cases both arms ran are compared)."""
    recs = list(records)
    out: dict[str, dict[str, dict[str, Figure]]] = {}
    for ablation, arms in ARMS.items():
        by_arm = {a: {r.case_id: r for r in recs if r.ablation == ablation and r.arm == a} for a in arms}
        common = sorted(set(by_arm[arms[0]]) & set(by_arm[arms[1]]))
        if not common:
            continue
        out[ablation] = {a: arm_figures(ablation, [by_arm[a][c] for c in common]) for a in arms}
    return out


def direction_ok(metric: str, baseline: float | None, ours: float | None) -> bool | None:
    """True when ours is at least as good as the baseline in the metric's direction (None if unknown)."""
    if baseline is None or ours is None:
        return None
    return ours <= baseline if metric in LOWER_IS_BETTER else ours >= baseline


def meets_target(metric: str, value: float | None) -> bool | None:
    """Whether a figure of our pipeline meets issue 9's target."""
    if value is None or metric not in TARGETS:
        return None
    op, t = TARGETS[metric]
    return value >= t if op == ">=" else value <= t
