"""How hard and how deep to squeeze: the hold-force target and the stiffness-scaled squeeze range (SI units).

The two-jaw friction hold needs 2 mu N >= m g: the force target per finger is ``margin * m g / (2 mu)``, at least
``floor_n`` and at most half the force budget and the gripper's own maximum. How deep the pads go to reach it comes
from a linear estimate of the pad's stiffness on the object, two springs in series: the local indentation of a rigid
flat punch of the pad's area on an elastic half-space, ``k_local = 2 a E / (1 - nu^2)`` with ``a = sqrt(A / pi)``
(Johnson, Contact Mechanics, 5.2), and the bulk compression of the object between the two pads, ``k_bulk = 2 E A / w``
(both fingers move by d: strain 2 d / w over the pad area). The squeeze range spans ``low_factor .. high_factor`` times
the estimated depth, bounded by the gripper (the fingers cannot close past zero) and by a share of the width: sub-mm
on a stiff rubber ball, centimetres on a plush toy. The closure itself is force-controlled (the fingers stop at the
target), so the range's top is only how deep they may go if the estimate was too stiff. A soft object may be a little
wider than the gripper's stroke: the open fingers may press it as they come down by the depth that gives a quarter of
the target force, at most 5 % of the width (``soft_indent_m``; tasks.robot.grasp).

A grasp whose closing axis misses the centre of mass by a lever d also has to hold the weight's torque m g d about
that axis, by the pads' torsional friction. A stiff object touches a flat pad on a small Hertzian patch, radius
``a = (3 N R / (4 E*))^(1/3)`` (R: the surface's radius there, taken as half the grasp width; E* = E / (1 - nu^2)),
whose torsional friction is ``(3 pi / 16) mu N a`` per pad (Johnson, Contact Mechanics, 7.3): the force per finger
that holds ``margin x m g d`` with two pads is ``N = (margin m g d / (2 (3 pi / 16) mu c))^(3/4)``, ``a = c N^(1/3)``.
A soft object whose patch at the hold force already fills the pad is held by the pads sunk into it: no torsion term.
A rubber duck gripped by its head (d = 25-30 mm, E = 1.6 MPa) turned 29 deg in the hand at the 1 N floor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SqueezePlan:
    """Force target per finger [N], estimated depth to reach it [m], the squeeze range [m] and the descent pre-press
    a soft object allows [m]; ``stiffness_n_per_m`` is the estimate per finger."""

    force_target_n: float
    stiffness_n_per_m: float
    depth_m: float
    low_m: float
    high_m: float
    soft_indent_m: float
    torsion_force_n: float = 0.0  # the force per finger the weight's torque about the closing axis asks for [N]

    def as_dict(self) -> dict[str, float]:
        return dict(self.__dict__)


def force_target_n(mass_kg: float, gravity_m_per_s2: float, friction: float, budget_n: float,
                   gripper_max_n: float, margin: float = 3.0, floor_n: float = 1.0) -> float:
    """Per-finger hold force [N]: margin x the two-jaw friction minimum m g / (2 mu), within [floor, budget / 2]."""
    need = margin * mass_kg * gravity_m_per_s2 / (2.0 * max(friction, 1e-6))
    return float(min(max(need, floor_n), 0.5 * budget_n, gripper_max_n))


def torsion_force_n(mass_kg: float, gravity_m_per_s2: float, friction: float, lever_m: float,
                    youngs_modulus_pa: float, poisson_ratio: float, radius_m: float, pad_radius_m: float,
                    hold_n: float, margin: float = 3.0) -> float:
    """Per-finger force [N] whose Hertzian torsional friction on two pads holds margin x the weight's torque about the
    closing axis (lever_m [m]); 0 without a lever or when the patch at hold_n already fills the pad (radius [m])."""
    if lever_m <= 0.0 or radius_m <= 0.0:
        return 0.0
    e_star = youngs_modulus_pa / (1.0 - poisson_ratio**2)
    c = (3.0 * radius_m / (4.0 * e_star)) ** (1.0 / 3.0)  # patch radius per N^(1/3) [m]
    if c * hold_n ** (1.0 / 3.0) >= pad_radius_m:
        return 0.0
    torque = margin * mass_kg * gravity_m_per_s2 * lever_m
    return float((torque / (2.0 * (3.0 * math.pi / 16.0) * max(friction, 1e-6) * c)) ** 0.75)


def pad_stiffness_n_per_m(youngs_modulus_pa: float, poisson_ratio: float, width_m: float, pad_area_m2: float) -> float:
    """Linear stiffness of one pad pressed into the object [N/m]: flat-punch indentation and bulk compression in
    series."""
    a = math.sqrt(pad_area_m2 / math.pi)
    k_local = 2.0 * a * youngs_modulus_pa / (1.0 - poisson_ratio**2)
    k_bulk = 2.0 * youngs_modulus_pa * pad_area_m2 / max(width_m, 1e-6)
    return 1.0 / (1.0 / k_local + 1.0 / k_bulk)


def squeeze_plan(youngs_modulus_pa: float, poisson_ratio: float, width_m: float, pad_area_m2: float, mass_kg: float,
                 gravity_m_per_s2: float, friction: float, budget_n: float, gripper_max_n: float,
                 margin: float = 3.0, floor_n: float = 1.0, low_factor: float = 0.3, high_factor: float = 1.6,
                 max_width_share: float = 0.35, min_depth_m: float = 1e-4, lever_m: float = 0.0) -> SqueezePlan:
    """The force target and the stiffness-scaled squeeze range of one grasp (width [m], pad area [m^2]; lever_m: how
    far its closing axis passes the centre of mass horizontally [m])."""
    target = force_target_n(mass_kg, gravity_m_per_s2, friction, budget_n, gripper_max_n, margin, floor_n)
    twist = torsion_force_n(mass_kg, gravity_m_per_s2, friction, lever_m, youngs_modulus_pa, poisson_ratio,
                            0.5 * width_m, math.sqrt(pad_area_m2 / math.pi), target, margin)
    target = float(min(max(target, twist), 0.5 * budget_n, gripper_max_n))
    k = pad_stiffness_n_per_m(youngs_modulus_pa, poisson_ratio, width_m, pad_area_m2)
    depth = target / k
    cap = max(min_depth_m, max_width_share * width_m)  # at most this share of the width per finger
    high = min(max(high_factor * depth, min_depth_m), cap)
    low = min(max(low_factor * depth, min_depth_m), high)
    indent = min(0.25 * depth, 0.05 * width_m)  # the descent's pre-press: a quarter of the target force, <= 5 % of w
    return SqueezePlan(target, k, depth, low, high, indent, twist)


def torque_lever_m(center_m: np.ndarray, closing_axis: np.ndarray, center_of_mass_m: np.ndarray) -> float:
    """The weight's lever about a grasp's closing axis [m]: the horizontal offset of the centre of mass from it,
    perpendicular to it (``|(u x (com - centre)) . z|``)."""
    u = np.asarray(closing_axis, dtype=float)
    u = u / np.linalg.norm(u)
    return float(abs(np.cross(u, np.asarray(center_of_mass_m, float) - np.asarray(center_m, float))[2]))


__all__ = ["SqueezePlan", "force_target_n", "pad_stiffness_n_per_m", "squeeze_plan", "torque_lever_m",
           "torsion_force_n"]
