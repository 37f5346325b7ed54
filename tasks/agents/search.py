"""One-dimensional searches of the rule Designer: safeguarded secant / bisection on a measured residual, bisection
on pass/fail evidence, enumeration of whole numbers. Coordinates are 'search coordinates': log10 for log fields."""

from __future__ import annotations

import math
from dataclasses import dataclass

from contracts.stage import EditableField

REL_TOL = 1e-3        # a measured-residual bracket narrower than this fraction of the search range is exhausted
PASS_FAIL_TOL = 0.02  # a pass/fail bracket narrower than this fraction of the search range is exhausted
MAX_LOG_STEP = 2.0    # decades one extrapolated step may move a log field
MAX_LIN_STEP = 0.5    # fraction of the range one extrapolated step may move a linear field
BISECTION_OVERSHOOT = 1.5  # a bisection field overshoots its first estimate to get a bracket sooner


def to_u(field: EditableField, x: float) -> float:
    """Field value -> search coordinate."""
    return math.log10(x) if field.scale == "log" else float(x)


def from_u(field: EditableField, u: float) -> float:
    """Search coordinate -> field value (clamped into the field's bounds)."""
    x = 10.0 ** u if field.scale == "log" else u
    return min(max(x, field.low), field.high)


def span(field: EditableField) -> float:
    """Width of the field's range in search coordinates."""
    return max(to_u(field, field.high) - to_u(field, field.low), 1e-12)


@dataclass(frozen=True)
class Point:
    """A measured point: search coordinate u and residual v = metric - aim (in the band's scale)."""

    u: float
    v: float


def _dedupe(points: list[Point]) -> list[Point]:
    """Keep the latest measurement per coordinate."""
    by_u: dict[float, Point] = {}
    for p in points:
        by_u[round(p.u, 12)] = p
    return list(by_u.values())


def root_step(
    points: list[Point], prior_slope: float, method: str, lo: float, hi: float, u_ref: float, width: float,
    log_field: bool = False, lo_open: float = -math.inf, hi_open: float = math.inf,
) -> float | None:
    """Next u where the residual should vanish, inside [lo, hi] and strictly between the open limits (values that
    failed a gate); None when no new informative point exists."""
    pts = _dedupe([p for p in points if math.isfinite(p.u) and math.isfinite(p.v)])
    if not pts:
        return None
    neg = [p for p in pts if p.v < 0]
    pos = [p for p in pts if p.v > 0]
    tol = REL_TOL * width
    if neg and pos:
        a = min(neg, key=lambda p: abs(p.v))
        b = min(pos, key=lambda p: abs(p.v))
        left, right = sorted((a.u, b.u))
        w = right - left
        if w < tol:
            return None
        if method == "bisection":
            u = 0.5 * (left + right)
        else:  # regula falsi on the closest opposite-sign pair, kept 5% away from the ends
            u = a.u - a.v * (b.u - a.u) / (b.v - a.v)
            u = min(max(u, left + 0.05 * w), right - 0.05 * w)
    else:
        best = sorted(pts, key=lambda p: abs(p.v))
        slope = prior_slope
        if len(best) >= 2 and abs(best[1].u - best[0].u) > tol:
            s = (best[1].v - best[0].v) / (best[1].u - best[0].u)
            if s * prior_slope > 0 and 0.1 * abs(prior_slope) <= abs(s) <= 10 * abs(prior_slope):
                slope = s
        step = -best[0].v / slope
        if method == "bisection":
            step *= BISECTION_OVERSHOOT
        cap = MAX_LOG_STEP if log_field else MAX_LIN_STEP * width
        step = max(-cap, min(cap, step))
        u = best[0].u + step
    return _inside(u, lo, hi, u_ref, tol, lo_open, hi_open)


def _inside(
    u: float, lo: float, hi: float, u_ref: float, tol: float, lo_open: float = -math.inf, hi_open: float = math.inf
) -> float | None:
    """u clamped into the closed field range [lo, hi], and moved half-way from u_ref towards an open limit (a value
    that failed a gate) it reached or crossed; None if nothing new results."""
    u = min(max(u, lo), hi)
    if u <= lo_open:
        u = 0.5 * (lo_open + max(u_ref, lo_open))
    if u >= hi_open:
        u = 0.5 * (hi_open + min(u_ref, hi_open))
    return None if abs(u - u_ref) < tol else u


def bisect_step(too_low: list[float], too_high: list[float], lo: float, hi: float, u_ref: float, width: float) -> float | None:
    """Pass/fail bisection: midway between the largest 'too low' and smallest 'too high' point (bounds otherwise)."""
    a = max([lo, *too_low])
    b = min([hi, *too_high])
    if b - a < PASS_FAIL_TOL * width:
        return None
    return _inside(0.5 * (a + b), lo, hi, u_ref, REL_TOL * width)


def enumerate_step(current: float, tested: set[int], low: float, high: float, direction: int) -> float | None:
    """The next untested whole number from current in the given direction (+1 / -1) inside [low, high]."""
    k = int(round(current)) + direction
    while math.ceil(low) <= k <= math.floor(high):
        if k not in tested:
            return float(k)
        k += direction
    return None
