"""The Planner's `choose_gripper` action: which gripper goes on the Panda's flange for an object, and why.

Deterministic rule (the L3 contract's `choose_gripper`): the packaged grippers are tried from the smallest stroke up.
For each, grasps are sampled on the object's surface (tasks.robot.grasp, with the soft pre-press its stiffness allows)
and the best one is judged: a grasp is *good* when its centre is within ``com_tolerance`` of the centre of mass
(horizontally: the object hangs from the pads, and an offset turns it about them) and the hold force the mass needs
(tasks.robot.squeeze: 2 mu N >= m g with margin) is reachable within the gripper's force and within the squeeze a
stiffness estimate allows. The smallest gripper with a good grasp is chosen; when none has one, the gripper whose best
grasp comes nearest the centre of mass; when no gripper has any grasp, there is no choice (the reason of each says why).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contracts.robot import GraspCandidate, gripper_names
from tasks.robot.grasp import GraspSelection, GraspSettings, select_grasps
from tasks.robot.gripper import gripper
from tasks.robot.squeeze import SqueezePlan, squeeze_plan


@dataclass(frozen=True)
class GripperOption:
    """One gripper as the Planner judged it for this object."""

    name: str
    stroke_m: float
    selection: GraspSelection
    squeeze: SqueezePlan | None
    com_offset_m: float
    good: bool
    note: str

    @property
    def best(self) -> GraspCandidate | None:
        return self.selection.candidates[0] if self.selection.candidates else None


@dataclass(frozen=True)
class GripperChoice:
    """The chosen gripper (None when no gripper has a grasp), why, and every option considered."""

    name: str | None
    reason: str
    options: list[GripperOption] = field(default_factory=list)

    def option(self, name: str) -> GripperOption:
        return next(o for o in self.options if o.name == name)

    def summary(self) -> list[dict[str, object]]:
        """The options as JSON rows (manipulation.json)."""
        rows = []
        for o in self.options:
            b = o.best
            rows.append({"gripper": o.name, "stroke_m": o.stroke_m, "good": o.good, "note": o.note,
                         "grasps": len(o.selection.candidates), "best_width_m": b.width_m if b else None,
                         "com_offset_m": o.com_offset_m if b else None,
                         "squeeze": o.squeeze.as_dict() if o.squeeze else None})
        return rows


def _horizontal_offset(center_m: tuple[float, float, float], com: np.ndarray) -> float:
    """Horizontal distance of a grasp centre from the centre of mass [m]."""
    return float(np.hypot(center_m[0] - com[0], center_m[1] - com[1]))


def grasp_settings(name: str, soft_indent_m: float) -> GraspSettings:
    """The sampler's settings for a gripper: the soft pre-press, and for any but the widest packaged gripper no grasp
    wider than its stroke (a wider soft part goes to a wider gripper, not into a pressed smaller one)."""
    widest = max(gripper(n).stroke_m for n in gripper_names())
    g = gripper(name)
    return GraspSettings(gripper=name, soft_indent_m=soft_indent_m,
                         max_width_m=None if g.stroke_m >= widest else g.stroke_m)


def judge_gripper(name: str, points_m: np.ndarray, normals: np.ndarray, com: np.ndarray, friction: float,
                  youngs_modulus_pa: float, poisson_ratio: float, mass_kg: float, gravity_m_per_s2: float,
                  budget_n: float, com_tolerance_m: float, margin: float = 3.0, floor_n: float = 1.0,
                  seed: int = 0) -> GripperOption:
    """Sample grasps for one gripper and judge its best one (see the module docstring)."""
    g = gripper(name)
    args = (youngs_modulus_pa, poisson_ratio)
    rest = (mass_kg, gravity_m_per_s2, friction, budget_n, g.spec.max_grip_force_n)
    nominal = squeeze_plan(*args, g.stroke_m, g.pad_area_m2, *rest, margin=margin, floor_n=floor_n)
    sel = select_grasps(points_m, normals, com, friction, seed=seed,
                        settings=grasp_settings(name, nominal.soft_indent_m))
    if not sel.ok:
        return GripperOption(name, g.stroke_m, sel, None, float("inf"), False, sel.reason)
    best = sel.candidates[0]
    sq = squeeze_plan(*args, best.width_m, g.pad_area_m2, *rest, margin=margin, floor_n=floor_n)
    offset = _horizontal_offset(best.center_m, com)
    reachable = sq.depth_m <= sq.high_m + 1e-12
    good = offset <= com_tolerance_m and reachable
    note = (f"best grasp {best.width_m * 1000:.0f} mm wide, {offset * 1000:.0f} mm from the centre of mass; hold "
            f"target {sq.force_target_n:.2f} N per finger at an estimated squeeze of {sq.depth_m * 1000:.1f} mm")
    if not reachable:
        note += f" (beyond the {sq.high_m * 1000:.1f} mm the width allows)"
    return GripperOption(name, g.stroke_m, sel, sq, offset, good, note)


def choose_gripper(points_m: np.ndarray, normals: np.ndarray, center_of_mass_m: np.ndarray, friction: float,
                   youngs_modulus_pa: float, poisson_ratio: float, mass_kg: float, gravity_m_per_s2: float = 9.81,
                   budget_n: float = 20.0, extents_m: np.ndarray | None = None, margin: float = 3.0,
                   floor_n: float = 1.0, names: list[str] | None = None, seed: int = 0) -> GripperChoice:
    """The Planner's gripper for an object: surface points [m] with outward normals, centre of mass [m], pad friction,
    material (E [Pa], nu), mass [kg], force budget per finger [N]; extents [m] set the centre-of-mass tolerance
    (max(2 cm, 10 % of the largest horizontal extent))."""
    com = np.asarray(center_of_mass_m, dtype=float)
    ext = np.ptp(points_m, axis=0) if extents_m is None else np.asarray(extents_m, dtype=float)
    tol = max(0.02, 0.1 * float(np.max(ext[:2])))
    names = names or gripper_names()
    order = sorted(names, key=lambda n: (gripper(n).stroke_m, n))
    options = [judge_gripper(n, points_m, normals, com, friction, youngs_modulus_pa, poisson_ratio, mass_kg,
                             gravity_m_per_s2, budget_n, tol, margin, floor_n, seed) for n in order]
    smaller: list[GripperOption] = []
    for o in options:
        if o.good:
            why = (f"{o.name} (stroke {o.stroke_m * 1000:.0f} mm), the smallest gripper with a grasp within "
                   f"{tol * 1000:.0f} mm of the centre of mass: {o.note}")
            if smaller:
                why += "; smaller: " + "; ".join(f"{s.name}: {s.note}" for s in smaller)
            return GripperChoice(o.name, why, options)
        smaller.append(o)
    usable = [o for o in options if o.best is not None]
    if not usable:
        return GripperChoice(None, "no gripper can hold the object: " + "; ".join(f"{o.name}: {o.note}"
                                                                                    for o in options), options)
    o = min(usable, key=lambda x: (x.com_offset_m, x.stroke_m))
    return GripperChoice(o.name, f"{o.name}: no gripper has a grasp within {tol * 1000:.0f} mm of the centre of "
                         f"mass; its best grasp comes nearest ({o.note})", options)


__all__ = ["GripperChoice", "GripperOption", "choose_gripper", "grasp_settings", "judge_gripper"]
