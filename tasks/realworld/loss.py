"""The material loss of a bouncy class: its prior restitution (the coefficient of restitution of a ball of it dropped
on a hard floor, `restitution` in contracts/vocab/materials.yaml) turned into the Kelvin-Voigt viscosity that gives
this object that restitution in our engine, calibrated by the engine's own impact probe (tasks.realworld.impact).

Relation: an impact is half a cycle of a damped oscillator, e = exp(-pi zeta / sqrt(1 - zeta^2)), whose damping ratio
for a Kelvin-Voigt solid is zeta = eta omega / E with omega = pi / t_c (t_c the contact time). Measured in our MPM on
solid spheres (session 28, E 0.2-1.5 MPa, nu 0.3-0.48): the ratio of the damping ratio seen to eta omega / E is
0.92-1.29, so the closed form is only the first guess; the engine also loses energy of its own in an impact
(restitution 0.82-0.94 at eta = 0, by resolution). Hence the calibration: one impact at eta = 0 (the engine's own
restitution e0), one at the closed form's eta for the rest (e / e0), then secant steps on the damping ratio seen
against eta (nearly linear) until an impact's restitution is within RESTITUTION_TOLERANCE of the target.
The impact's speed is a fall from 2 m for a class prior, and from the rule's own drop height for a ball's rule
restitution (the restitution falls with the impact speed, and the rule states it at its height; session 33).
"""

from __future__ import annotations

import math

import numpy as np

from cache import cached_task
from contracts.concept import ConceptMatch
from contracts.material import Material
from contracts.physical import PhysicalModel
from contracts.sim import SimConfig
from tasks.realworld.impact import impact
from tasks.realworld.physics import G_M_PER_S2

TASK_VERSION = "1"
# the class's restitution is for a drop from 2 m onto a hard floor (6.26 m/s): most ball rules drop 1.8-2.54 m; a rule
# ball's restitution is calibrated at its rule's own drop (calibration_drop)
REFERENCE_DROP_M = 2.0
CORRECTION_BOUNDS = (0.25, 4.0)  # each correction stays within these factors of the last guess
RESTITUTION_TOLERANCE = 0.005  # the calibration stops once an impact's restitution is this close to the target
MAX_IMPACTS = 4  # impacts with viscosity at most (besides the one at eta = 0)


def damping_ratio(restitution: float) -> float:
    """The damping ratio zeta of a half cycle that returns `restitution` of the speed, -ln e / sqrt(pi^2 + ln^2 e)."""
    ln = math.log(min(max(restitution, 1e-6), 1.0))
    return -ln / math.sqrt(math.pi ** 2 + ln * ln)


def viscosity_for_damping_ratio(zeta: float, youngs_modulus_pa: float, contact_time_s: float) -> float:
    """Kelvin-Voigt viscosity eta [Pa s] of damping ratio zeta at omega = pi / t_c: eta = zeta E t_c / pi."""
    return zeta * youngs_modulus_pa * contact_time_s / math.pi


def drop_speed_m_per_s(drop_m: float) -> float:
    """Impact speed after a fall from `drop_m` in vacuum, sqrt(2 g h) [m/s]."""
    return math.sqrt(2.0 * G_M_PER_S2 * drop_m)


def reference_speed_m_per_s() -> float:
    """Impact speed of the class's restitution: a fall from REFERENCE_DROP_M in vacuum [m/s]."""
    return drop_speed_m_per_s(REFERENCE_DROP_M)


@cached_task(version=TASK_VERSION, name="l2.restitution_loss")
def restitution_loss_task(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel,
                          material: Material, restitution: float, speed_m_per_s: float,
                          sim: SimConfig) -> dict[str, float]:
    """The viscosity [Pa s] that gives this object `restitution` in an impact at `speed_m_per_s` on the engine's
    ground (the material's other fields as given, its viscosity ignored), with the impacts that calibrated it:
    restitution_engine (eta = 0), restitution_first (the closed form's eta), restitution (the adopted eta's)."""
    base = material.model_copy(update={"viscosity_pa_s": 0.0})

    def run(eta: float) -> dict[str, float]:
        return impact(positions_m, volumes_m3, physical, base.model_copy(update={"viscosity_pa_s": eta}),
                      speed_m_per_s, sim)

    raw0 = run(0.0)
    e0 = raw0.get("restitution", math.nan)
    out = {"target_restitution": restitution, "speed_m_per_s": speed_m_per_s, "restitution_engine": e0,
           "contact_time_engine_s": raw0.get("contact_time_s", math.nan), "viscosity_pa_s": 0.0}
    if not (math.isfinite(e0) and raw0["finite"] == 1.0) or e0 <= restitution:
        out["restitution"] = e0  # the engine alone loses as much (or failed): no viscosity
        return out
    zeta = damping_ratio(restitution / e0)
    eta = viscosity_for_damping_ratio(zeta, base.wall_modulus_pa, raw0["contact_time_s"])  # a gas shell: its wall's
    out["viscosity_first_pa_s"] = eta
    pts = [(0.0, 0.0)]  # (eta, damping ratio of e / e0) seen
    best, impacts = (0.0, e0), 1  # the last healthy impact's (eta, restitution); impacts run
    for k in range(MAX_IMPACTS):
        raw = run(eta)
        impacts += 1
        e = raw.get("restitution", math.nan)
        if k == 0:
            out["restitution_first"] = e
        if not (math.isfinite(e) and raw["finite"] == 1.0 and 0.0 < e):
            break  # keep the last healthy one
        best = (eta, e)
        if abs(e - restitution) <= RESTITUTION_TOLERANCE:
            break
        pts.append((eta, damping_ratio(min(e / e0, 1.0))))
        (a, za), (b, zb) = pts[-2], pts[-1]
        slope = (zb - za) / (b - a) if zb > za else zb / b  # secant on zeta(eta); through 0 if it went flat
        lo, hi = CORRECTION_BOUNDS
        eta = min(max(b + (zeta - zb) / max(slope, 1e-12), lo * b), hi * b)
    out.update({"viscosity_pa_s": best[0], "restitution": best[1], "impacts": float(impacts)})
    return out


def restitution_target(priors: dict[str, float], concept: ConceptMatch | None,
                       material_class: str | None) -> tuple[float, str] | None:
    """(restitution, where it comes from) that the material's loss is calibrated to: the lexicon entry's (a ball's
    rebound rule, ConceptMatch.restitution) when L0 built a concept that carries one and the material is the concept's
    own class, else the class's prior `restitution`; None when neither gives one."""
    if concept is not None and concept.restitution is not None and material_class == concept.default_material:
        return float(concept.restitution), f"lexicon: {concept.concept}"
    e = priors.get("restitution")
    if e is None:
        return None
    return float(e), f"class prior: {material_class or 'unknown'}"


def calibration_drop(concept: ConceptMatch | None, material_class: str | None) -> tuple[float, str]:
    """(drop height [m], where it comes from) of the impact the loss is calibrated at: the rule's own drop
    (ConceptMatch.restitution_drop_m) when the target is the concept's rule restitution, since the restitution falls
    with the impact speed and the rule states it at its own height; else REFERENCE_DROP_M, the class prior's."""
    if concept is not None and concept.restitution is not None and concept.restitution_drop_m is not None \
            and material_class == concept.default_material:
        return float(concept.restitution_drop_m), f"the rule's drop: {concept.concept}"
    return REFERENCE_DROP_M, "reference drop"


def material_loss(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
                  priors: dict[str, float], sim: SimConfig, concept: ConceptMatch | None = None,
                  material_class: str | None = None) -> tuple[dict[str, float], dict[str, float | str]]:
    """(fixed material fields, calibration record): {"viscosity_pa_s": eta} calibrated to the restitution of
    restitution_target (the concept's, else the class's prior) at the speed of calibration_drop's fall (the rule's
    drop, else 2 m), else nothing; the record's "source" says which restitution, "calibration_drop_m" and
    "calibration_drop_source" which drop (its "speed_m_per_s" the impact's speed)."""
    target = restitution_target(priors, concept, material_class)
    if target is None:
        return {}, {}
    e, source = target
    drop_m, drop_source = calibration_drop(concept, material_class)
    rec: dict[str, float | str] = dict(restitution_loss_task(
        positions_m=np.asarray(positions_m), volumes_m3=np.asarray(volumes_m3), physical=physical, material=material,
        restitution=e, speed_m_per_s=drop_speed_m_per_s(drop_m), sim=sim))
    rec["source"] = source
    rec["calibration_drop_m"] = drop_m
    rec["calibration_drop_source"] = drop_source
    eta = float(rec["viscosity_pa_s"])
    return ({"viscosity_pa_s": eta} if eta > 0.0 else {}), rec


__all__ = ["REFERENCE_DROP_M", "TASK_VERSION", "calibration_drop", "damping_ratio", "drop_speed_m_per_s",
           "material_loss", "reference_speed_m_per_s", "restitution_loss_task", "restitution_target", "viscosity_for_damping_ratio"]
