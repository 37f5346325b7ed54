"""The simulators' probe runners for `deformsmith crosscheck`: L2's object compression and drop probes on an exported
asset in MuJoCo, Genesis or Drake, with each one's calibration knobs and its calibrated-file writer, and the
calibration that fits them (used by flows.crosscheck, which records it)."""

from __future__ import annotations

import importlib.util
import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from contracts.errors import InputError
from tasks.export import drake, drake_probes, genesis, genesis_probes, mujoco as mj
from tasks.export.calibrate import Calibration, Knob, fit_both, rel
from tasks.export.crosscheck import AGREEMENT_TOLERANCE, CALIBRATED_METRICS, ProbeTargets
from tasks.export.genesis import GENESIS_INSTALL
from tasks.export.inputs import ExportInputs
from tasks.export.mujoco_probes import compress, drop
from tasks.export.mujoco_scene import FlexParams, fundamental_period_s
from tasks.export.probe_schedule import TetBody
from tasks.publish import write_text_atomic

SIMULATORS = ("mujoco", "genesis", "drake")


@dataclass
class SimRunner:
    """A simulator's probes on one asset: params -> metrics (compress None where the simulator cannot run it);
    knobs() the rebound search's damping knobs (None: nothing to calibrate)."""

    name: str
    initial: dict[str, float]
    compress: Callable[[dict[str, float]], dict[str, float]] | None
    drop: Callable[[dict[str, float]], dict[str, float]]
    knobs: Callable[[dict[str, float]], list[Knob]] | None
    write_calibrated: Callable[[dict[str, float], Path], list[str]] | None


def probe_metrics(compress: dict[str, float], drop: dict[str, float]) -> dict[str, float]:
    """A compression's and a drop's metrics as one dict of floats (the compression's where both name one)."""
    return {**{k: float(v) for k, v in drop.items()}, **{k: float(v) for k, v in compress.items()}}


def calibrate(sim: str, runner: SimRunner, targets: ProbeTargets, before: dict[str, float]
              ) -> tuple[dict[str, float], Calibration]:
    """Fit the simulator `sim`'s Young's modulus to L2's effective modulus, then its damping knobs to L2's rebound
    (fit_both), from its exported parameters, whose probes measured `before`; every probe runs once per parameter set
    (the fits re-read what they measured). Returns the probes' metrics with the fitted parameters ("after") and the
    calibration (its sim_calls: the simulations beyond the exported parameters' two). Needs runner.compress and
    runner.knobs."""
    assert runner.compress is not None and runner.knobs is not None
    ours, values = targets.ours, dict(runner.initial)
    probes = {"compress": runner.compress, "drop": runner.drop}
    runs: dict[tuple, dict[str, float]] = {(kind, *sorted(values.items())): before for kind in probes}

    def probe(kind: str, v: dict[str, float]) -> dict[str, float]:
        key = (kind, *sorted(v.items()))
        if key not in runs:
            runs[key] = probes[kind](v)
        return runs[key]

    values, steps = fit_both(lambda v: float(probe("compress", v)["effective_modulus_pa"]),
                             lambda v: float(probe("drop", v).get("rebound_ratio", 0.0)), runner.knobs, values,
                             ours["effective_modulus_pa"], ours["rebound_ratio"])
    after = probe_metrics(probe("compress", values), probe("drop", values))
    residuals = {m: rel(after[m], ours[m]) for m in CALIBRATED_METRICS if m in after}
    return after, Calibration(
        sim=sim, parameters=values, initial=runner.initial, residuals=residuals,
        residuals_before={m: rel(before[m], ours[m]) for m in CALIBRATED_METRICS if m in before},
        probes=[f"compress (object, strain {targets.strain})",
                f"drop (object, height fraction {targets.height_fraction})"],
        history=steps, sim_calls=len(runs) - len(probes),
        converged=all(abs(r) <= AGREEMENT_TOLERANCE for r in residuals.values()))


def rate_knob(name: str, rate_per_s: float, period_s: float) -> Knob:
    """A velocity (mass-proportional) damping rate [1/s]: from 1/100 of its value up to critical at the fundamental
    mode (c = 2 w0 = 4 pi / T) or 4x its value."""
    c = max(rate_per_s, 1e-3)
    return Knob(name, c, c * 1e-2, max(4.0 * math.pi / period_s, 4.0 * c))


def mujoco_runner(inputs: ExportInputs, targets: ProbeTargets, area_m2: float) -> SimRunner:
    nodes, tets = inputs.tet.nodes_m, inputs.tet.tets
    p0 = mj.flex_params(nodes, tets, inputs.material)
    body = TetBody(nodes, tets, inputs.material.density_kg_per_m3, targets.spacing_m,
                   inputs.material.youngs_modulus_pa)

    def params(values: dict[str, float]) -> FlexParams:
        dt = values.get("timestep_s", p0.timestep_s)  # the contacts' time constant keeps its ratio to the step
        return FlexParams(young_pa=values["young_pa"], poisson=p0.poisson, damping_s=values["damping_s"],
                          mass_kg=p0.mass_kg, friction=p0.friction, timestep_s=dt,
                          contact_timeconst_s=p0.contact_timeconst_s * dt / p0.timestep_s,
                          contact_dampratio=values["contact_dampratio"])

    def knobs(values: dict[str, float]) -> list[Knob]:
        # 1. the timestep, down to a quarter of the exported one in halvings (each costs more wall time): the discrete
        #    integrator's numerical dissipation takes a stiff body's impact energy (rubber ball: rebound 0.59 at
        #    0.25 ms, 0.66 at 0.2, 0.72 at 0.15, 0.77 at 0.1, 0.84 at 0.05 ms; L2's 0.76);
        # 2. the flex damping up to 4 x critical at the fundamental mode (ratio b w0 / 2 = 4): the overdamped mode
        #    still relaxes within the compression's hold (plush turtle: modulus +5 % from 1 x to 4 x); beyond, the body
        #    turns viscous and the compression no longer reads its static modulus (1000 x the exported: -26 %)
        b = max(values["damping_s"], 1e-9)
        b_critical = 2.0 * body.period_s / (2.0 * math.pi)
        dt = values.get("timestep_s", p0.timestep_s)
        return [Knob("timestep_s", dt, p0.timestep_s / 4.0, p0.timestep_s, max_step=2.0),
                Knob("damping_s", b, b * 1e-3, max(4.0 * b_critical, 2.0 * b))]

    def write(values: dict[str, float], folder: Path) -> list[str]:
        name = f"{inputs.slug}{mj.CALIBRATED_SUFFIX}.xml"
        mj.write_scene(folder / name, nodes, tets, params(values), inputs.slug,
                       "DeformSmith export calibrated against L2's object compression and drop probes "
                       "(deformsmith crosscheck; calibration.json)")
        return [name]

    init = {k: v for k, v in mj.parameters_dict(p0).items()
            if k in ("young_pa", "damping_s", "contact_dampratio", "timestep_s")}
    return SimRunner("mujoco", init,
                     lambda v: compress(body, params(v), targets.strain, area_m2),
                     lambda v: drop(body, params(v), targets.height_fraction), knobs, write)


def genesis_runner(inputs: ExportInputs, targets: ProbeTargets, area_m2: float, folder: Path) -> SimRunner:
    scene = folder / genesis.SCENE
    m = inputs.material
    z = inputs.tet.nodes_m[:, 2]
    height = float(z.max() - z.min())
    period = fundamental_period_s(height, m.youngs_modulus_pa, m.density_kg_per_m3)

    def knobs(values: dict[str, float]) -> list[Knob]:
        return [rate_knob("damping_rate_per_s", values["damping_rate_per_s"], period)]  # scene.py's Drag rate

    def write(values: dict[str, float], out: Path) -> list[str]:
        params = json.loads((out / "params.json").read_text(encoding="utf-8"))
        genesis.write_scene(out / genesis.CALIBRATED_SCENE,
                            genesis.calibrated_params(params, values["young_pa"], values["damping_rate_per_s"]),
                            inputs.slug, "Calibrated against L2's object compression and drop probes (deformsmith "
                            "crosscheck; calibration.json): E and the damping rate in PARAMS are the fitted ones.")
        return [genesis.CALIBRATED_SCENE]

    return SimRunner(
        "genesis", {"young_pa": m.youngs_modulus_pa, "damping_rate_per_s": m.damping_rate_per_s},
        lambda v: genesis_probes.compress(scene, targets.strain, area_m2, v["young_pa"], v["damping_rate_per_s"]),
        lambda v: genesis_probes.drop(scene, targets.height_fraction, v["young_pa"], v["damping_rate_per_s"]),
        knobs, write)


def drake_runner(inputs: ExportInputs, targets: ProbeTargets, area_m2: float, folder: Path) -> SimRunner:
    m = inputs.material
    body = TetBody(inputs.tet.nodes_m, inputs.tet.tets, m.density_kg_per_m3, targets.spacing_m, m.youngs_modulus_pa)
    vtk = folder / f"{inputs.slug}.vtk"

    def params(values: dict[str, float]) -> drake_probes.DrakeParams:
        material = m.model_copy(update={"youngs_modulus_pa": values["young_pa"],
                                        "damping_rate_per_s": values["mass_damping_per_s"]})
        return drake_probes.DrakeParams(material, values["timestep_s"])

    def knobs(values: dict[str, float]) -> list[Knob]:
        # 1. the timestep, down to 1/16 of the exported one in halvings: Drake's first-order Newmark scheme for
        #    deformables takes an impact's energy in proportion to w dt (kitchen sponge, T = 3.9 ms: rebound 0.009 at
        #    1 ms against L2's 0.119); 2. the Rayleigh mass damping (a velocity damping rate, as Genesis's)
        dt = values["timestep_s"]
        return [Knob("timestep_s", dt, drake_probes.TIME_STEP_S / 16.0, drake_probes.TIME_STEP_S, max_step=2.0),
                rate_knob("mass_damping_per_s", values["mass_damping_per_s"], body.period_s)]

    def write(values: dict[str, float], out: Path) -> list[str]:
        name = f"{inputs.slug}{drake.CALIBRATED_SUFFIX}.sdf"
        write_text_atomic(out / name, drake.deformable_sdf(
            inputs.slug, vtk.name, params(values).material,
            comment=f"{drake.EXPORT_COMMENT} Calibrated against L2's object compression and drop probes "
                    f"(deformsmith crosscheck; calibration.json): E and mass_damping are the fitted ones; simulate "
                    f"with MultibodyPlantConfig(time_step={values['timestep_s']!r}, "
                    f"discrete_contact_approximation='sap')."))
        return [name]

    init = {"young_pa": m.youngs_modulus_pa, "mass_damping_per_s": m.damping_rate_per_s,
            "timestep_s": drake_probes.TIME_STEP_S}
    return SimRunner("drake", init,
                     lambda v: drake_probes.compress(body, vtk, params(v), targets.strain, area_m2),
                     lambda v: drake_probes.drop(body, vtk, params(v), targets.height_fraction), knobs, write)


def require_simulator(sim: str) -> None:
    """InputError naming the extra when the simulator's package is missing (checked before anything is written)."""
    if sim not in SIMULATORS:
        raise InputError(f"unknown simulator '{sim}'; choose one of {', '.join(SIMULATORS)}")
    if sim == "mujoco" and importlib.util.find_spec("mujoco") is None:
        raise InputError('crosscheck --sim mujoco needs the mujoco package: pip install -e ".[export]"')
    if sim == "genesis" and importlib.util.find_spec("genesis") is None:
        raise InputError(f"crosscheck --sim genesis needs genesis-world: {GENESIS_INSTALL}")
    if sim == "drake" and importlib.util.find_spec("pydrake") is None:
        raise InputError('crosscheck --sim drake needs the drake package: pip install -e ".[export]"')


def sim_runner(sim: str, inputs: ExportInputs, targets: ProbeTargets, area_m2: float, folder: Path) -> SimRunner:
    """The runner of a simulator (one of SIMULATORS) on an exported asset (folder: the simulator's export)."""
    if sim == "mujoco":
        return mujoco_runner(inputs, targets, area_m2)
    if sim == "drake":
        return drake_runner(inputs, targets, area_m2, folder)
    return genesis_runner(inputs, targets, area_m2, folder)
