"""What happened in a failed pick-and-place, in words, from the trial's own data (SI units).

A trial's outcome labels say THAT it failed (not lifted, not transported, not released in the target, not settled);
the diagnosis says HOW, from what the trial measured (tasks.manipulation.outcome._what_happened): the grip force per
finger over time, how far the hand and the object rose, the object's rotation in the hand, its slip, how far it fell
when the fingers opened and how far it moved after that. One failure mode per trial, with one line of words:

  plan_failed           the plan could not be executed (no reachable pose)
  no_grip               the closing fingers never built the grip force they aimed for
  lost_contact          the grip force fell to almost nothing as the hand rose: the fingers lost the object
  rotated_out           the object turned in the hand, out of the grasp
  slipped_at_lift       the fingers kept their force but the object slid down the pads and stayed low
  dropped_in_transport  the object left the hand during the transport
  slipped_in_transport  it slid in the hand beyond the slip tolerance during the transport
  carried_off_target    it stayed in the hand but arrived away from the target
  toppled               carried to the target, it fell over when the fingers let it go
  released_off_target   carried to the target, it ended away from it after the fingers opened (without falling over)
  not_settled           it was still moving when the trial ended

`mode_flags` gives each mode as a 0/1 metric (`mode_<name>`), which is what the L3 revision routes read (the L3
contract's parameters.harness_routes.modes): a slip is answered by a firmer squeeze, a slower lift or another grasp, a
release off target by a lower release and a slower opening, never by the same plan again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from tasks.manipulation.outcome import CONTACT_LOST_FRACTION, TrialTolerances

MODES = ("plan_failed", "no_grip", "lost_contact", "rotated_out", "slipped_at_lift", "dropped_in_transport",
         "slipped_in_transport", "carried_off_target", "toppled", "released_off_target", "not_settled")
ROTATED_OUT_DEG = 30.0     # the object turned this far relative to the gripper: it rotated out of the grasp
NO_GRIP_FRACTION = 0.5     # the grip force at the lift's start below this share of its target: the fingers never gripped
DROP_WORTH_SAYING_M = 0.002  # a fall on release shorter than this is not mentioned [m]
TOPPLED_DEG = 30.0         # the object turned this far after the fingers opened: it fell over


@dataclass(frozen=True)
class Diagnosis:
    """A failed trial's failure mode (one of MODES) and what happened, in one line."""

    mode: str
    words: str


def _f(labels: dict[str, Any], key: str) -> float | None:
    """A finite number of the labels, else None."""
    v = labels.get(key)
    return float(v) if isinstance(v, (int, float)) and math.isfinite(float(v)) else None


def _mm(x: float) -> str:
    return f"{x * 1000:.0f} mm"


def diagnose(labels: dict[str, Any], tol: TrialTolerances) -> Diagnosis | None:
    """The failure mode and its words from a trial's labels; None when the pick-and-place succeeded (lifted,
    transported, released in the target, settled). Force, strain and health gates are not outcome failures."""
    if labels.get("plan_failed"):
        return Diagnosis("plan_failed", "the plan could not be executed (no reachable approach or grasp pose)")
    ok = {k: bool(labels.get(k)) for k in ("lifted", "transported", "released_in_target", "settled")}
    if all(ok.values()):
        return None
    rise, hand = _f(labels, "lift_rise_m"), _f(labels, "hand_rise_m")
    at_lift, low = _f(labels, "grip_force_at_lift_n"), _f(labels, "grip_force_min_held_n")
    target = _f(labels, "grip_force_target_n")
    turned = _f(labels, "object_rotation_deg")
    rose = (f"the object rose {_mm(rise)} while the hand rose {_mm(hand)}" if rise is not None and hand is not None
            else f"the object rose {_mm(rise)} of {_mm(tol.lift_height_m)}" if rise is not None else "")
    if not ok["lifted"]:
        if target is not None and at_lift is not None and at_lift < NO_GRIP_FRACTION * target:
            return Diagnosis("no_grip", f"not lifted: the fingers never gripped: {at_lift:.2g} N per finger when the "
                                        f"lift began, of the {target:.2g} N they closed for; {rose}")
        if turned is not None and turned >= ROTATED_OUT_DEG:
            return Diagnosis("rotated_out", f"not lifted: the object rotated {turned:.0f} deg out of the grasp; {rose}")
        lost = _f(labels, "contact_lost_hand_rise_m")
        if lost is not None and at_lift is not None:
            return Diagnosis("lost_contact", f"not lifted: the fingers lost contact at the lift: the grip force fell "
                                             f"from {at_lift:.2g} N to under {CONTACT_LOST_FRACTION * at_lift:.2g} N "
                                             f"per finger once the hand had risen {_mm(lost)}; {rose}")
        if at_lift is None:  # a record from before these measurements: only the rise is known
            return Diagnosis("slipped_at_lift", f"not lifted: {rose or 'the object stayed on the table'}")
        force = f" with {low:.2g}-{at_lift:.2g} N per finger" if low is not None else ""
        return Diagnosis("slipped_at_lift", f"not lifted: slipped at the lift: the object slid down the pads{force}; "
                                            f"{rose}")
    slip = _f(labels, "slip_distance_m")
    if not ok["transported"]:
        if labels.get("slipped") and slip is not None:
            if slip > 3.0 * tol.slip_tolerance_m:
                return Diagnosis("dropped_in_transport", f"not transported: the object fell out of the hand during "
                                                         f"the transport (it moved {_mm(slip)} in the hand)")
            return Diagnosis("slipped_in_transport", f"not transported: the object slipped {_mm(slip)} in the hand "
                                                     f"(tolerance {_mm(tol.slip_tolerance_m)})")
        if turned is not None and turned >= ROTATED_OUT_DEG:
            return Diagnosis("rotated_out", f"not transported: the object rotated {turned:.0f} deg in the hand")
        err = _f(labels, "transport_error_m")
        where = f"{_mm(err)} from the target" if err is not None else "away from the target"
        return Diagnosis("carried_off_target", f"not transported: carried to {where} "
                                               f"(tolerance {_mm(tol.place_tolerance_m)})")
    drop, drift = _f(labels, "release_drop_m"), _f(labels, "release_drift_m")
    speed = _f(labels, "settle_com_speed_m_per_s")
    fell = (f"fell {_mm(drop)} when the fingers opened" if drop is not None and drop >= DROP_WORTH_SAYING_M
            else "")
    fallen = _f(labels, "release_rotation_deg")
    toppled = fallen is not None and fallen >= TOPPLED_DEG
    if not ok["released_in_target"]:
        err, carried = _f(labels, "place_error_m"), _f(labels, "transport_error_m")
        parts = [f"carried to {_mm(carried)} from the target" if carried is not None else "", fell,
                 f"then fell over (turned {fallen:.0f} deg)" if toppled else "",
                 f"then moved {_mm(drift)} on the table" if drift is not None and not toppled else
                 f"moving {_mm(drift)}" if drift is not None else "",
                 f"still moving at {speed:.2g} m/s at the end" if not ok["settled"] and speed is not None else ""]
        head = (f"released off target by {_mm(err)} (tolerance {_mm(tol.place_tolerance_m)})" if err is not None
                else "not released in the target")
        return Diagnosis("toppled" if toppled else "released_off_target", head + ": " + ", ".join(p for p in parts if p))
    turning = _f(labels, "settle_turn_rate_deg_per_s")
    tipping = turning is not None and turning > tol.settle_turn_rate_deg_per_s
    parts = [fell, f"fell over (turned {fallen:.0f} deg)" if toppled else "",
             f"still tipping over at {turning:.0f} deg/s at the end" if tipping else "",
             f"still moving at {speed:.2g} m/s at the end" if speed is not None and not tipping else ""]
    return Diagnosis("not_settled", "not settled after the release: " + (", ".join(p for p in parts if p)
                                                                            or "still moving"))


def mode_flags(labels: dict[str, Any], tol: TrialTolerances) -> dict[str, float]:
    """Each failure mode as a 0/1 metric `mode_<name>` (all 0 when the pick-and-place succeeded)."""
    d = diagnose(labels, tol)
    return {f"mode_{m}": float(d is not None and d.mode == m) for m in MODES}


__all__ = ["Diagnosis", "MODES", "diagnose", "mode_flags"]
