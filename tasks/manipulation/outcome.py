"""Outcome labels of a pick-and-place trial from its recorded arrays (SI units; each label a 0/1 metric).

  lifted              the COM rose >= lift_height - slip_tolerance while held (held = lift start .. release start)
  transported         at release start the COM is within place_tolerance (xy) of its target and still in the hand
  released_in_target  at the end the COM is within place_tolerance (xy) of the target and the object rests on the table
  settled             at the end the COM speed, the fastest particle speed (last frame interval) and the body's turn
                      rate (its rigid rotation over the last ~0.1 s) are small: a tall toy tipping over slowly is
                      not at rest, though its COM moves at a few mm/s
  slipped             the COM moved > slip_tolerance relative to the gripper frame (pad midpoint, pad axes) while held
  force_budget_violated  a finger's mean reaction force over a control interval exceeded the budget
  max_strain          largest |principal stretch - 1| of any particle in any recorded frame (singular values of F)
  strain_p99          the principal strain exceeded by at most 1 % of the body's volume, largest over the recorded
                      frames: the deformation bound's metric. A single particle's peak sits at the rim of a rigid pad,
                      a stress singularity of the continuum (the peak grows as the grid is refined and is set by one
                      particle of thousands); a volume quantile converges and measures how much of the object is
                      deformed that far
Hold evidence (the two-jaw condition 2 mu N >= m g), over the held intervals with the object off the table and
not yet slipped: mean
normal force per finger N, the mean vertical force the object puts on both fingers (/ m g = hold_vertical_ratio,
~1 since the mean acceleration over lift + transport is ~0), 2 mu N / m g (hold_friction_ratio) and its smallest
0.05 s running mean (hold_min_capacity_ratio: ~1 or below where the object slides down the pads).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contracts.physical import PhysicalModel
from contracts.robot import ActionPlan
from contracts.stage import StageContract, load_contract, packaged_parameters
from tasks.probes.metrics import extreme_stretches
from tasks.robot import Trajectory


def force_budget_n(contract: StageContract | None = None) -> float:
    """The force budget per finger [N]: the threshold of the contract's max_finger_force_n gate (a contract without
    that gate: the packaged L3 contract's)."""
    for c in (contract, load_contract("L3")):
        gate = next((g for g in c.hard_gates if g.metric == "max_finger_force_n"), None) if c is not None else None
        if gate is not None and gate.threshold is not None:
            return float(gate.threshold)
    raise ValueError("the packaged L3 contract has no max_finger_force_n gate")


def _l3_parameter(name: str) -> float:
    """Default of a tolerance: the packaged L3 contract's parameter (the one place it is set)."""
    return field(default_factory=lambda: float(packaged_parameters("L3")[name]))


@dataclass(frozen=True)
class TrialTolerances:
    """Limits the labels use (the L3 contract's parameters; defaults: the packaged contract's)."""

    lift_height_m: float = _l3_parameter("lift_height_m")
    place_tolerance_m: float = _l3_parameter("place_tolerance_m")
    slip_tolerance_m: float = _l3_parameter("slip_tolerance_m")
    force_budget_n: float = field(default_factory=force_budget_n)
    settle_speed_m_per_s: float = 0.02
    settle_particle_speed_m_per_s: float = 0.1
    settle_turn_rate_deg_per_s: float = 5.0


SETTLE_WINDOW_S = 0.1  # the span over which the COM speed and the turn rate of the `settled` label are measured


def turn_rate_deg_per_s(x_before: np.ndarray, x_now: np.ndarray, span_s: float) -> float:
    """The body's rigid rotation rate [deg/s] between two particle states span_s apart (Kabsch fit, world axes)."""
    if span_s <= 0.0:
        return float("inf")
    eye = np.eye(3)
    return _object_rotation_deg(np.asarray(x_before, dtype=np.float64), np.asarray(x_now, dtype=np.float64),
                                eye, eye) / span_s


def frame_back(frame_t_s: np.ndarray, span_s: float = SETTLE_WINDOW_S) -> int:
    """Index of the last recorded frame at least span_s before the last one (at least one frame back)."""
    t = np.asarray(frame_t_s, dtype=float)
    return int(max(0, min(len(t) - 2, int(np.searchsorted(t, t[-1] - span_s + 1e-9, side="right")) - 1)))


def _rotations(quat_xyzw: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of quaternions (N, 4)."""
    x, y, z, w = np.moveaxis(quat_xyzw, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], -2)


BULK_STRAIN_VOLUME_FRACTION = 0.01  # strain_p99: the share of the body's volume allowed beyond the bound


def principal_strains(F: np.ndarray) -> np.ndarray:
    """max(|largest singular value - 1|, |1 - smallest|) of each deformation gradient (..., 3, 3) -> (...)."""
    lo, hi = extreme_stretches(F)
    return np.maximum(hi - 1.0, 1.0 - lo)


def max_principal_strain(F: np.ndarray, strains: np.ndarray | None = None) -> float:
    """Largest |singular value - 1| over deformation gradients (..., 3, 3); nan if any is not finite. `strains`:
    their principal_strains, where already computed."""
    F = np.asarray(F).reshape(-1, 3, 3)
    if not np.all(np.isfinite(F)):
        return float("nan")
    if not len(F):
        return 0.0
    return float(np.max(principal_strains(F) if strains is None else strains))


def bulk_strain(F_frames: np.ndarray, volumes_m3: np.ndarray | None = None,
                fraction: float = BULK_STRAIN_VOLUME_FRACTION, strains: np.ndarray | None = None) -> float:
    """The principal strain exceeded by at most `fraction` of the body's volume, largest over frames (T, N, 3, 3);
    particles weighted by volume (uniform when None); nan if any F is not finite. `strains`: their principal_strains
    (T, N), where already computed."""
    F = np.asarray(F_frames)
    if not np.all(np.isfinite(F)):
        return float("nan")
    s = principal_strains(F) if strains is None else strains  # (T, N)
    w = np.ones(s.shape[1]) if volumes_m3 is None else np.asarray(volumes_m3, dtype=np.float64)
    w = w / w.sum()
    order = np.argsort(s, axis=1)
    cum = np.cumsum(w[order], axis=1)  # volume share at or below each sorted strain
    k = np.minimum(np.argmax(cum >= 1.0 - fraction - 1e-12, axis=1), s.shape[1] - 1)
    return float(np.max(np.take_along_axis(s, order, axis=1)[np.arange(len(s)), k]))


def _index_at(t: np.ndarray, time_s: float) -> int:
    """Index of the first control interval starting at or after time_s (clamped)."""
    return int(min(len(t) - 1, max(0, int(np.searchsorted(t, time_s - 1e-9)))))


CONTACT_LOST_FRACTION = 0.1  # the fingers lost contact: grip force below this share of the force at the lift's start


def _object_rotation_deg(x_ref: np.ndarray, x: np.ndarray, rot_ref: np.ndarray, rot_now: np.ndarray) -> float:
    """The object's rotation [deg] relative to the gripper between two particle states (Kabsch fit of the particles
    in the gripper's axes at each instant)."""
    a = (x_ref - x_ref.mean(axis=0)) @ rot_ref
    b = (x - x.mean(axis=0)) @ rot_now
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(u @ vt))
    r = u @ np.diag([1.0, 1.0, d]) @ vt
    # the angle from sin and cos together: arccos of the trace alone loses half the digits near no rotation (a
    # translation gave 1e-5 deg/s of 'turn' on one LAPACK, 0 on another)
    sin = 0.5 * float(np.linalg.norm([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]))
    return float(np.degrees(np.arctan2(sin, (np.trace(r) - 1.0) / 2.0)))


def _what_happened(arrays: dict[str, np.ndarray], grip_n: np.ndarray, mid: np.ndarray, rot: np.ndarray,
                   com: np.ndarray, n_done: int, k_close: int, k_lift: int, k_rel: int, held: slice,
                   released: bool) -> dict[str, float]:
    """What the trial's own data say happened, for the diagnosis of a failure (tasks.manipulation.diagnosis):

      grip_force_at_lift_n     mean normal force per finger over the last 0.02 s before the lift [N]
      grip_force_min_held_n    its smallest 0.02 s running mean while held (lift start .. release start) [N]
      contact_lost_hand_rise_m how far the hand had risen when that force first fell below CONTACT_LOST_FRACTION of
                               its value at the lift's start (absent: contact kept) [m]
      hand_rise_m              how far the hand rose while held [m]
      object_rotation_deg      the object's largest rotation relative to the gripper while held [deg]
      release_drop_m           the object's lowest point above the table when the fingers start to open [m]
      release_drift_m          how far the centre of mass moved (xy) from the release's start to the end [m]
      release_rotation_deg     how far the object turned from the release's start to the end (a topple) [deg]
    A figure that does not exist is absent (no contact lost, no release before the trial ended), never NaN.
    """
    out: dict[str, float] = {}
    if n_done <= k_lift:
        return out
    dt = float(np.mean(arrays["control_dt_s"][:n_done]))
    w = max(1, int(round(0.02 / max(dt, 1e-6))))
    smooth = np.convolve(np.nan_to_num(grip_n[:n_done]), np.ones(w) / w, mode="full")[:n_done]  # trailing mean
    at_lift = float(smooth[max(k_lift - 1, 0)])
    h = np.arange(n_done)[held]
    rise = mid[:n_done, 2] - mid[k_close, 2]
    out["grip_force_at_lift_n"] = at_lift
    if len(h):
        out["grip_force_min_held_n"] = float(np.min(smooth[h]))
        out["hand_rise_m"] = float(np.max(rise[h]))
    lost = h[smooth[h] < CONTACT_LOST_FRACTION * at_lift] if at_lift > 0 else h[:0]
    if len(lost):
        out["contact_lost_hand_rise_m"] = float(rise[lost[0]])
    frames_k = np.asarray(arrays["frame_control_index"])
    x = arrays["particles_x_m"]
    finite = [bool(np.isfinite(f).all()) for f in x]  # an unhealthy trial's frames are not fitted
    in_hold = [i for i, k in enumerate(frames_k) if k_lift <= k < min(k_rel, n_done) and finite[i]]
    if in_hold:
        i0 = in_hold[0]
        out["object_rotation_deg"] = max(
            _object_rotation_deg(x[i0].astype(np.float64), x[i].astype(np.float64), rot[frames_k[i0]],
                                 rot[frames_k[i]]) for i in in_hold)
    if released:
        i_rel = int(np.searchsorted(frames_k, k_rel))
        if i_rel < len(x) and finite[i_rel] and finite[-1]:
            out["release_drop_m"] = float(x[i_rel][:, 2].min()) - float(x[0][:, 2].min())
            eye = np.eye(3)
            out["release_rotation_deg"] = _object_rotation_deg(x[i_rel].astype(np.float64), x[-1].astype(np.float64),
                                                               eye, eye)
        if np.isfinite(com[[k_rel, n_done], :2]).all():
            out["release_drift_m"] = float(np.linalg.norm(com[n_done, :2] - com[k_rel, :2]))
    return out


def label_trial(arrays: dict[str, np.ndarray], traj: Trajectory, plan: ActionPlan, physical: PhysicalModel,
                tol: TrialTolerances, n_done: int, healthy: bool, ground_contact_m: float = 0.0) -> dict[str, float]:
    """Labels and metrics of one trial (arrays are trimmed to the n_done simulated intervals).

    ground_contact_m: how far above its first height the lowest particle of a body lying on the table may be and
    still count as resting there: the MPM's ground acts on grid nodes, so where the grid lattice sits after the hand
    carried it (it moves with the hand) a body at rest on the ground can sit up to one grid cell higher than it started
    (a 10 cm plush cube on a 16 mm grid: 11 mm). The trial passes its grid spacing; the slip tolerance is the floor."""
    t = arrays["control_t_s"][:n_done]
    com = arrays["object_com_m"][:n_done + 1]
    force = arrays["finger_force_n"][:n_done]
    pos, quat = arrays["finger_position_m"][:n_done], arrays["finger_quat_xyzw"][:n_done]
    u = arrays["closing_axis_world"]
    ph = traj.phases
    complete = healthy and n_done > 0 and t[-1] + 1e-9 >= ph["settle"][0]

    k_close, k_lift = _index_at(t, ph["closure"][0]), _index_at(t, ph["lift"][0])
    k_rel = _index_at(t, ph["release"][0])
    held = slice(k_lift, max(k_lift + 1, k_rel))
    rot = _rotations(quat[:, 0])
    mid = pos.mean(axis=1)
    rel = np.einsum("kji,kj->ki", rot, com[:n_done] - mid)  # COM in the gripper frame
    slip = float(np.max(np.linalg.norm(rel[held] - rel[k_lift], axis=1))) if n_done > k_lift else float("nan")
    rise = float(np.max(com[held, 2] - com[k_close, 2])) if n_done > k_lift else float("nan")
    target = com[k_close, :2] + np.asarray(plan.target_xy_m) - np.asarray((0.0, 0.0))
    err_transport = float(np.linalg.norm(com[k_rel, :2] - target)) if n_done > k_rel else float("nan")
    in_hand = n_done > k_rel and float(np.linalg.norm(rel[k_rel] - rel[k_lift])) <= 3.0 * tol.slip_tolerance_m

    x_frames = arrays["particles_x_m"]
    err_place = float(np.linalg.norm(com[-1, :2] - target))
    resting = (float(x_frames[-1][:, 2].min())
               <= float(x_frames[0][:, 2].min()) + max(tol.slip_tolerance_m, ground_contact_m))
    dt_frame = float(np.diff(arrays["frame_t_s"][-2:])[0]) if len(x_frames) > 1 else 0.0
    v_particles = (float(np.max(np.linalg.norm(x_frames[-1] - x_frames[-2], axis=1))) / dt_frame
                   if dt_frame > 0 else float("inf"))
    i_back = frame_back(arrays["frame_t_s"]) if len(x_frames) > 1 else 0
    turn_rate = (turn_rate_deg_per_s(x_frames[i_back], x_frames[-1],
                                     float(arrays["frame_t_s"][-1] - arrays["frame_t_s"][i_back]))
                 if len(x_frames) > 1 and np.isfinite(x_frames[-1]).all() and np.isfinite(x_frames[i_back]).all()
                 else float("inf"))
    k_back = _index_at(t, t[-1] - SETTLE_WINDOW_S)
    span = (n_done - k_back) * float(np.mean(arrays["control_dt_s"][:n_done]))
    v_com = float(np.linalg.norm(com[-1] - com[k_back]) / span) if span > 0 else float("inf")

    mag = np.linalg.norm(force, axis=2)
    max_f = np.nanmax(mag, axis=0) if n_done else np.array([np.nan, np.nan])
    normal = np.stack([-(force[:, 0] @ u), force[:, 1] @ u], axis=1)
    weight = physical.mass_kg * float(np.linalg.norm(physical.gravity_m_per_s2))
    mu = physical.gripper_friction
    ground = arrays["ground_force_n"][:n_done]
    idx = np.arange(n_done)
    drift = np.linalg.norm(rel - rel[min(k_lift, n_done - 1)], axis=1) if n_done else np.zeros(0)
    before_slip = np.maximum.accumulate(np.where(idx >= k_lift, drift, 0.0)) <= tol.slip_tolerance_m
    airborne = (idx >= k_lift) & (idx < k_rel) & (np.abs(ground[:, 2]) < 0.01 * weight) & before_slip
    n_hold = float(np.mean(normal[airborne])) if airborne.any() else float("nan")
    v_hold = float(np.mean(-(force[airborne, 0, 2] + force[airborne, 1, 2]))) if airborne.any() else float("nan")
    window = max(1, int(round(0.05 / max(float(np.mean(arrays["control_dt_s"][:n_done])), 1e-6))))
    capacity = np.convolve(2.0 * mu * normal.mean(axis=1), np.ones(window) / window, mode="same") / weight
    cap_min = float(np.min(capacity[airborne])) if airborne.any() else float("nan")
    F_frames = arrays["particles_F"]
    strains = principal_strains(F_frames) if np.all(np.isfinite(F_frames)) else None  # once for both metrics
    strain = max_principal_strain(F_frames, strains)
    strain_bulk = bulk_strain(F_frames, arrays.get("particle_volumes_m3"), strains=strains)

    lifted = complete and rise >= tol.lift_height_m - tol.slip_tolerance_m
    released = n_done > 0 and t[-1] + 1e-9 >= ph["release"][0]
    what = _what_happened(arrays, normal.mean(axis=1), mid, rot, com, n_done, k_close, k_lift, k_rel, held, released)
    return {**what,
        "lifted": float(lifted),
        "transported": float(complete and lifted and in_hand and err_transport <= tol.place_tolerance_m),
        "released_in_target": float(complete and err_place <= tol.place_tolerance_m and resting),
        "settled": float(complete and v_com <= tol.settle_speed_m_per_s
                         and v_particles <= tol.settle_particle_speed_m_per_s
                         and turn_rate <= tol.settle_turn_rate_deg_per_s),
        "slipped": float(not (slip <= tol.slip_tolerance_m)),
        "force_budget_violated": float(not bool(np.all(max_f <= tol.force_budget_n))),
        "numerically_healthy": float(healthy),
        "max_strain": strain, "strain_p99": strain_bulk,
        "max_finger_force_n": float(np.max(max_f)),
        "max_finger_force_0_n": float(max_f[0]), "max_finger_force_1_n": float(max_f[1]),
        "slip_distance_m": slip, "lift_rise_m": rise, "transport_error_m": err_transport,
        "place_error_m": err_place, "settle_com_speed_m_per_s": v_com,
        "settle_particle_speed_m_per_s": v_particles, "settle_turn_rate_deg_per_s": turn_rate,
        "hold_normal_force_n": n_hold, "hold_vertical_force_n": v_hold, "weight_n": weight,
        "hold_friction_ratio": 2.0 * mu * n_hold / weight, "hold_vertical_ratio": v_hold / weight,
        "hold_min_capacity_ratio": cap_min, "held_airborne_s": float(np.sum(arrays["control_dt_s"][:n_done][airborne])),
        "mass_kg": physical.mass_kg, "gripper_friction": mu,
    }
