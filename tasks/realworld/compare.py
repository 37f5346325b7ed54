"""Our figures beside the published ones: one Comparison per measured quantity, and the set's summary."""

from __future__ import annotations

from collections.abc import Sequence

from contracts.errors import InputError
from contracts.realworld import (Comparison, ObjectReport, OurFigures, Quantity, RealWorldObject, ReportSummary,
                                 ValueRange)
from tasks.realworld.physics import squeeze_modulus_range

FACTOR = 2.0  # mass and modulus pass within this factor of the published range
SQUEEZE_POISSON = 0.48  # the equivalent solid's Poisson ratio when ours is unknown (the rubber prior's)


def ratio_to_range(value: float, band: ValueRange) -> float:
    """value / the nearest end of the range (1 inside it)."""
    if value < band.low:
        return value / band.low
    if value > band.high:
        return value / band.high
    return 1.0


def within_factor(quantity: Quantity, band: ValueRange, ours: float | None, factor: float = FACTOR) -> Comparison:
    """A log-scale quantity: passes when ours is within `factor` of the range."""
    criterion = f"within {factor:g}x of the range"
    if ours is None:
        return Comparison(quantity=quantity, measured=band, ours=None, passed=None, criterion=criterion)
    r = ratio_to_range(ours, band)
    return Comparison(quantity=quantity, measured=band, ours=ours, ratio=r,
                      passed=1.0 / factor <= r <= factor, criterion=criterion)


def in_band(quantity: Quantity, band: ValueRange, ours: float | None) -> Comparison:
    """A linear quantity: passes when ours lies in the band."""
    passed = None if ours is None else band.low <= ours <= band.high
    return Comparison(quantity=quantity, measured=band, ours=ours, passed=passed,
                      criterion="inside the rule's band")


def compare(obj: RealWorldObject, ours: OurFigures) -> list[Comparison]:
    """Every published quantity of the object beside ours."""
    out = []
    if obj.mass is not None:
        out.append(within_factor("mass_kg", obj.mass.mass_kg, ours.mass_kg))
    if obj.modulus is not None:
        out.append(within_factor("youngs_modulus_pa", obj.modulus.youngs_modulus_pa, ours.youngs_modulus_pa))
    if obj.squeeze is not None:
        band = squeeze_modulus_range(obj.squeeze, ours.poisson_ratio or SQUEEZE_POISSON)
        out.append(within_factor("squeeze_modulus_pa", band, ours.youngs_modulus_pa))
    if obj.rebound is not None:
        out.append(in_band("rebound_ratio", obj.rebound.rebound_ratio, ours.rebound_ratio))
    return out


def _passed(reports: Sequence[ObjectReport], quantities: set[str]) -> tuple[int, int]:
    """(objects with a measurement of one of the quantities, objects whose comparisons of them all passed)."""
    measured = passed = 0
    for r in reports:
        cs = [c for c in r.comparisons if c.quantity in quantities]
        if cs:
            measured += 1
            passed += all(c.passed for c in cs)
    return measured, passed


def summarise(reports: Sequence[ObjectReport]) -> ReportSummary:
    """The set's headline counts."""
    e_n, e_ok = _passed(reports, {"youngs_modulus_pa", "squeeze_modulus_pa"})
    m_n, m_ok = _passed(reports, {"mass_kg"})
    b_n, b_ok = _passed(reports, {"rebound_ratio"})
    return ReportSummary(objects=len(reports), built=sum(r.status == "ok" for r in reports),
                         concept_matches=sum(r.ours.concept == r.expected_concept for r in reports),
                         modulus_measured=e_n, modulus_within_2x=e_ok, mass_measured=m_n, mass_within_2x=m_ok,
                         rule_balls=b_n, rebound_in_band=b_ok)


def select_objects(objects: Sequence[RealWorldObject], only: Sequence[str] | None = None,
                   limit: int | None = None) -> list[RealWorldObject]:
    """The objects named by `only` (in the set's order; InputError naming any the set does not hold), else all; the
    first `limit` of them."""
    chosen = list(objects)
    if only:
        known = {o.name for o in objects}
        unknown = [n for n in only if n not in known]
        if unknown:
            raise InputError(f"not in the real-world set: {', '.join(unknown)} (known: {', '.join(sorted(known))})")
        chosen = [o for o in objects if o.name in set(only)]
    return chosen[:limit] if limit is not None else chosen
