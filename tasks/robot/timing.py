"""Time-scaling profiles s(t) on [0, 1] with their rates: min-jerk (quintic) and constant speed with ramps."""

from __future__ import annotations

import numpy as np


def min_jerk(tau: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
    """Quintic 10 t^3 - 15 t^4 + 6 t^5 and its derivative d/dtau, for tau in [0, 1] (clipped); rest at both ends."""
    t = np.clip(np.asarray(tau, dtype=float), 0.0, 1.0)
    s = t**3 * (10.0 - 15.0 * t + 6.0 * t**2)
    ds = 30.0 * t**2 * (1.0 - t) ** 2
    return s, ds


def ramped_travel(t: np.ndarray | float, distance: float, speed: float, ramp_s: float = 0.02
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Distance covered [m] and rate [m/s] at time t [s] when moving at ``speed`` with linear speed ramps.

    The ramps (ramp_s each, shortened for short moves) keep the velocity continuous; after arriving it holds.
    """
    t = np.asarray(t, dtype=float)
    if distance <= 0.0:
        return np.zeros_like(t), np.zeros_like(t)
    ramp = min(ramp_s, distance / speed)
    accel = speed / ramp
    cruise = distance / speed - ramp  # >= 0 by the choice of ramp
    total = cruise + 2.0 * ramp
    tc = np.clip(t, 0.0, total)
    d_up = 0.5 * accel * np.minimum(tc, ramp) ** 2
    d_cruise = speed * np.clip(tc - ramp, 0.0, cruise)
    td = np.clip(tc - ramp - cruise, 0.0, ramp)
    d_down = speed * td - 0.5 * accel * td**2
    rate = np.where(tc < ramp, accel * tc, np.where(tc < ramp + cruise, speed, speed - accel * td))
    rate = np.where(t >= total, 0.0, np.where(t <= 0.0, 0.0, rate))
    return d_up + d_cruise + d_down, rate


def ramped_travel_time(distance: float, speed: float, ramp_s: float = 0.02) -> float:
    """Duration [s] of ``ramped_travel`` over a distance [m] at a speed [m/s]."""
    if distance <= 0.0:
        return 0.0
    return distance / speed + min(ramp_s, distance / speed)
