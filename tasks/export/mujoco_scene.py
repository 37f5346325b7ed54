"""MJCF text of a tet-mesh body as a MuJoCo 3-D flex (flexcomp type="direct", dim=3) on a table (numpy only).

The body is one `flexcomp` whose points are the tet-mesh nodes and whose elements are its tetrahedra; each node is a
body with three slide joints (dof="full"). MuJoCo's flex elasticity takes Young's modulus and Poisson's ratio
(`<elasticity young= poisson=>`, a St. Venant-Kirchhoff-type model on the element edges) and a stiffness-proportional
(Rayleigh) damping time `damping` [s]; DeformSmith's velocity damping rate c [1/s] maps to it at the body's
fundamental frequency w0 = 2 pi / T, T = 4 H / sqrt(E / rho) (the L2 probes' period): a mass-proportional rate c
damps mode w with ratio c / (2 w), a stiffness-proportional time b with b w / 2, so b = c / w0^2.
Flex elasticity is integrated implicitly only by the `discrete` integrator in MuJoCo 3.17, so the scene uses it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

FLEX_NAME = "body"
TABLE_NAME = "table"
PLATE_NAME = "plate"
CONTACT_DAMPRATIO = 1.0  # contact impedance: critically damped soft constraint (MuJoCo's default ratio)
# MuJoCo's soft contacts are compliant in proportion to the effective mass of what they touch: a flex node weighs
# ~1e-5 kg, so at the default impedance (0.9, 0.95) a plate sinks into a sponge with 1/25 of its stiffness. An
# impedance near 1 makes the contacts stiff against the body, whatever the node mass.
CONTACT_SOLIMP = "0.99 0.999 0.001 0.5 2"


@dataclass
class FlexParams:
    """What MuJoCo is given for the body: its own elasticity parameters and the contact settings."""

    young_pa: float
    poisson: float
    damping_s: float          # stiffness-proportional damping time [s]
    mass_kg: float
    friction: float           # body-table Coulomb friction [-]
    timestep_s: float
    contact_timeconst_s: float  # solref time constant of the body's contacts [s]
    contact_dampratio: float = CONTACT_DAMPRATIO  # solref damping ratio of the body's contacts (1: no bounce of its own)


def fundamental_period_s(height_m: float, young_pa: float, density_kg_per_m3: float) -> float:
    """4 H / sqrt(E / rho) [s], as L2's probes (tasks.probes.rollout.fundamental_period_s)."""
    return 4.0 * height_m / math.sqrt(young_pa / density_kg_per_m3)


def damping_time_s(rate_per_s: float, height_m: float, young_pa: float, density_kg_per_m3: float) -> float:
    """MuJoCo's stiffness-proportional damping time b = c / w0^2 for DeformSmith's velocity damping rate c."""
    w0 = 2.0 * math.pi / fundamental_period_s(height_m, young_pa, density_kg_per_m3)
    return float(rate_per_s) / (w0 * w0)


def min_edge_m(nodes_m: np.ndarray, tets: np.ndarray) -> float:
    """Shortest tet edge [m]."""
    x = np.asarray(nodes_m, np.float64)[np.asarray(tets)]
    edges = [x[:, a] - x[:, b] for a, b in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))]
    return float(min(np.linalg.norm(e, axis=1).min() for e in edges))


def mean_edge_m(nodes_m: np.ndarray, tets: np.ndarray) -> float:
    """Mean tet edge [m]."""
    x = np.asarray(nodes_m, np.float64)[np.asarray(tets)]
    edges = [x[:, a] - x[:, b] for a, b in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))]
    return float(np.mean([np.linalg.norm(e, axis=1).mean() for e in edges]))


def default_params(nodes_m: np.ndarray, tets: np.ndarray, *, young_pa: float, poisson: float, density_kg_per_m3: float,
                   damping_rate_per_s: float, mass_kg: float, friction: float,
                   stiffness_damping_s: float = 0.0) -> FlexParams:
    """The export's MuJoCo parameters: the validated E and nu, the mapped damping (the velocity damping rate's and
    the viscosity's stiffness-proportional time eta / mu, both MuJoCo's one flex damping time), a stable step for
    the mesh."""
    height = float(np.ptp(np.asarray(nodes_m)[:, 2]))
    c = math.sqrt(young_pa / density_kg_per_m3)
    # the discrete integrator is implicit in the elastic forces; half a wave crossing of the mean edge resolves the
    # impact, within [0.25 ms, 1 ms] (a stiff rubber ball would ask for 0.1 ms: 2 s of drop then cost ~6 min on a
    # shared CPU core; its numerical dissipation takes part of a stiff body's rebound, and the crosscheck's
    # calibration refines the step only where the drop shows it)
    dt = min(1e-3, max(2.5e-4, 0.5 * mean_edge_m(nodes_m, tets) / c))
    return FlexParams(young_pa=young_pa, poisson=poisson,
                      damping_s=damping_time_s(damping_rate_per_s, height, young_pa, density_kg_per_m3)
                      + stiffness_damping_s,
                      mass_kg=mass_kg, friction=friction, timestep_s=dt, contact_timeconst_s=2.0 * dt)


def _nums(a: np.ndarray, fmt: str) -> str:
    return " ".join(format(float(v), fmt) if fmt else str(int(v)) for v in np.asarray(a).ravel())


def flexcomp_xml(nodes_m: np.ndarray, tets: np.ndarray, p: FlexParams, *, pos_m: tuple[float, float, float] = (0, 0, 0),
                 condim: int = 3, rgba: str = "0.85 0.55 0.25 1") -> str:
    """The `<flexcomp>` element of the body (asset frame positions, shifted by pos_m)."""
    radius = max(1e-4, 0.05 * min_edge_m(nodes_m, tets))
    return (
        f'<flexcomp name="{FLEX_NAME}" type="direct" dim="3" dof="full" mass="{p.mass_kg:.9g}" radius="{radius:.6g}" '
        f'pos="{pos_m[0]:.9g} {pos_m[1]:.9g} {pos_m[2]:.9g}" rgba="{rgba}"\n'
        f'          point="{_nums(nodes_m, ".9g")}"\n'
        f'          element="{_nums(tets, "")}">\n'
        f'  <contact condim="{condim}" friction="{p.friction:.6g}" selfcollide="none" '
        f'solref="{p.contact_timeconst_s:.6g} {p.contact_dampratio:.6g}" solimp="{CONTACT_SOLIMP}"/>\n'
        f'  <edge equality="false"/>\n'
        f'  <elasticity young="{p.young_pa:.9g}" poisson="{p.poisson:.6g}" damping="{p.damping_s:.6g}"/>\n'
        f'</flexcomp>')


def scene_xml(nodes_m: np.ndarray, tets: np.ndarray, p: FlexParams, *, model_name: str = "deformsmith_asset",
              pos_m: tuple[float, float, float] = (0, 0, 0), frictionless: bool = False,
              plate_half_m: tuple[float, float, float] | None = None, plate_pos_m: tuple[float, float, float] = (0, 0, 1),
              comment: str = "") -> str:
    """A whole MJCF: the flex body on a table plane (z = 0), optionally a mocap plate (the compression probe).

    frictionless: condim 1 contacts (the compression probe's frictionless plate and ground)."""
    condim = 1 if frictionless else 3
    # MuJoCo mixes the solref/solimp of the two sides of a contact: the table and plate carry the body's
    soft = f'solref="{p.contact_timeconst_s:.6g} {p.contact_dampratio:.6g}" solimp="{CONTACT_SOLIMP}"'
    plate = ""
    if plate_half_m is not None:
        h = plate_half_m
        plate = (f'    <body name="{PLATE_NAME}" mocap="true" pos="{plate_pos_m[0]:.9g} {plate_pos_m[1]:.9g} '
                 f'{plate_pos_m[2]:.9g}">\n'
                 f'      <geom name="{PLATE_NAME}" type="box" size="{h[0]:.6g} {h[1]:.6g} {h[2]:.6g}" '
                 f'condim="{condim}" friction="0" {soft} rgba="0.5 0.5 0.6 0.5"/>\n'
                 f'    </body>\n')
    note = f"<!-- {comment} -->\n" if comment else ""
    return (
        f'<mujoco model="{model_name}">\n{note}'
        f'  <compiler autolimits="true"/>\n'
        f'  <option timestep="{p.timestep_s:.6g}" integrator="discrete" solver="CG" gravity="0 0 -9.81"/>\n'
        f'  <size memory="64M"/>\n'
        f'  <worldbody>\n'
        f'    <light pos="0 0 1" dir="0 0 -1"/>\n'
        f'    <geom name="{TABLE_NAME}" type="plane" size="1 1 0.01" condim="{condim}" '
        f'friction="{0.0 if frictionless else p.friction:.6g}" {soft} rgba="0.8 0.8 0.8 1"/>\n'
        f'{plate}'
        f'    {flexcomp_xml(nodes_m, tets, p, pos_m=pos_m, condim=condim)}\n'
        f'  </worldbody>\n'
        f'</mujoco>\n')


__all__ = ["FLEX_NAME", "FlexParams", "PLATE_NAME", "TABLE_NAME", "damping_time_s", "default_params",
           "flexcomp_xml", "fundamental_period_s", "mean_edge_m", "min_edge_m", "scene_xml"]
