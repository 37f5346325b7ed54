"""Closed-form physics that puts a rule's test in the simulation's terms: a squeeze between two plates as an
equivalent solid's modulus (Hertz), and a drop through air (quadratic drag) around an impact simulated without air."""

from __future__ import annotations

import math

from contracts.realworld import LoadDeformation, ValueRange

G_M_PER_S2 = 9.81
AIR_DENSITY_KG_PER_M3 = 1.2  # at ~20 degC, sea level
DRAG_COEFFICIENT = 0.5  # a sphere below the drag crisis (Re ~1e4-1e5), the regime of every rule drop here


def hertz_modulus_pa(load_n: float, deformation_m: float, diameter_m: float, poisson_ratio: float) -> float:
    """Young's modulus of a solid elastic sphere that a load between two rigid plates deforms by `deformation_m`
    plate to plate (Hertz: each contact takes half, F = 4/3 E* sqrt(R) d^1.5, E = E* (1 - nu^2)) [Pa]."""
    d = 0.5 * deformation_m
    e_star = 3.0 * load_n / (4.0 * math.sqrt(0.5 * diameter_m) * d ** 1.5)
    return e_star * (1.0 - poisson_ratio ** 2)


def squeeze_modulus_range(squeeze: LoadDeformation, poisson_ratio: float) -> ValueRange:
    """The equivalent solid's modulus range of a rule's squeeze test (the most deformation gives the lowest) [Pa]."""
    dia = 0.5 * (squeeze.diameter_m.low + squeeze.diameter_m.high)
    lo = hertz_modulus_pa(squeeze.load_n, squeeze.deformation_m.high, dia, poisson_ratio)
    hi = hertz_modulus_pa(squeeze.load_n, squeeze.deformation_m.low, dia, poisson_ratio)
    return ValueRange(low=lo, high=hi)


def terminal_speed_m_per_s(mass_kg: float, diameter_m: float) -> float:
    """Terminal speed of a sphere falling through air, quadratic drag [m/s]."""
    area = math.pi * diameter_m ** 2 / 4.0
    return math.sqrt(2.0 * mass_kg * G_M_PER_S2 / (AIR_DENSITY_KG_PER_M3 * DRAG_COEFFICIENT * area))


def impact_speed_m_per_s(drop_height_m: float, terminal_m_per_s: float | None) -> float:
    """Speed at the floor after a fall from rest through `drop_height_m` (None: in vacuum) [m/s]."""
    if terminal_m_per_s is None:
        return math.sqrt(2.0 * G_M_PER_S2 * drop_height_m)
    vt2 = terminal_m_per_s ** 2
    return math.sqrt(vt2 * (1.0 - math.exp(-2.0 * G_M_PER_S2 * drop_height_m / vt2)))


def rise_height_m(speed_m_per_s: float, terminal_m_per_s: float | None) -> float:
    """Height a body thrown up at `speed_m_per_s` rises through air (None: in vacuum) [m]."""
    if terminal_m_per_s is None:
        return speed_m_per_s ** 2 / (2.0 * G_M_PER_S2)
    vt2 = terminal_m_per_s ** 2
    return vt2 / (2.0 * G_M_PER_S2) * math.log1p(speed_m_per_s ** 2 / vt2)


def damped_impact_speed_m_per_s(drop_height_m: float, damping_rate_per_s: float) -> float:
    """Speed at the floor after a fall from rest through `drop_height_m` under the engine's damping (a velocity
    decay at `damping_rate_per_s` in the world frame: v(t) = g/d (1 - e^-dt)), as the asset falls in our MPM [m/s]."""
    d, g = damping_rate_per_s, G_M_PER_S2
    if d <= 1e-9:
        return math.sqrt(2.0 * g * drop_height_m)
    t = math.sqrt(2.0 * drop_height_m / g)
    for _ in range(50):  # Newton on z(t) = g/d t - g/d^2 (1 - e^-dt) = h; z' = v > 0, z convex: converges from below
        v = g / d * (1.0 - math.exp(-d * t))
        z = g / d * t - g / d ** 2 * (1.0 - math.exp(-d * t))
        t -= (z - drop_height_m) / v
    return g / d * (1.0 - math.exp(-d * t))


def damped_rise_height_m(speed_m_per_s: float, damping_rate_per_s: float) -> float:
    """Height a body thrown up at `speed_m_per_s` rises under the engine's damping, v0/d - g/d^2 ln(1 + d v0 / g) [m]."""
    d, g, v0 = damping_rate_per_s, G_M_PER_S2, speed_m_per_s
    if d * v0 / g < 1e-6:
        return v0 ** 2 / (2.0 * g)
    return v0 / d - g / d ** 2 * math.log1p(d * v0 / g)
