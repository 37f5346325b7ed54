"""MuJoCo export: an MJCF scene with the asset as a 3-D flex (flexcomp, dim 3, from the tet mesh) on a table.

The flex takes the validated E and nu as MuJoCo's `elasticity young= poisson=`; our velocity damping rate becomes
MuJoCo's stiffness-proportional damping time at the body's fundamental frequency (tasks.export.mujoco_scene). A
crosscheck with calibration (`deformsmith crosscheck DIR --sim mujoco`) adds <slug>_calibrated.xml and
calibration.json beside the scene (tasks.export.calibrate).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from contracts.export import ExportMaterial, TargetManifest
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files
from tasks.export.mujoco_scene import FlexParams, default_params, scene_xml

MAPPING = ("MuJoCo's 3-D flex elasticity (St. Venant-Kirchhoff-type, on the element edges) takes the neo-Hookean "
           "E and nu unchanged: the two agree to first order in strain, and the crosscheck measures the difference.")
DAMPING = ("velocity damping rate c [1/s] -> flex elasticity damping b = c / w0^2 [s] (stiffness-proportional), "
           "w0 = 2 pi / T, T = 4 H / sqrt(E / rho): both damp the fundamental mode at ratio c / (2 w0).")
LOAD_HINT = "python -c \"import mujoco; m = mujoco.MjModel.from_xml_path('{xml}'); d = mujoco.MjData(m); " \
            "mujoco.mj_step(m, d, nstep=1000)\"  (or: python -m mujoco.viewer --mjcf={xml})"
CALIBRATED_SUFFIX = "_calibrated"


def flex_params(nodes_m: np.ndarray, tets: np.ndarray, material: ExportMaterial) -> FlexParams:
    """The export's MuJoCo parameters from the validated material."""
    return default_params(nodes_m, tets, young_pa=material.youngs_modulus_pa, poisson=material.poisson_ratio,
                          density_kg_per_m3=material.density_kg_per_m3,
                          damping_rate_per_s=material.damping_rate_per_s, mass_kg=material.mass_kg,
                          friction=material.ground_friction, stiffness_damping_s=material.stiffness_damping_s)


def parameters_dict(p: FlexParams) -> dict[str, float]:
    """The MuJoCo parameters by name (manifest / report)."""
    return {"young_pa": p.young_pa, "poisson": p.poisson, "damping_s": p.damping_s, "mass_kg": p.mass_kg,
            "friction": p.friction, "timestep_s": p.timestep_s, "contact_timeconst_s": p.contact_timeconst_s,
            "contact_dampratio": p.contact_dampratio}


def rest_lift_m(nodes_m: np.ndarray) -> float:
    """Shift that puts the lowest node 1 mm above the table (the body drops onto it on load)."""
    return 1e-3 - float(np.asarray(nodes_m)[:, 2].min())


def write_scene(path: Path, nodes_m: np.ndarray, tets: np.ndarray, p: FlexParams, name: str, comment: str) -> None:
    """One MJCF file: the flex body resting 1 mm above the table."""
    path.write_text(scene_xml(nodes_m, tets, p, model_name=name, pos_m=(0.0, 0.0, rest_lift_m(nodes_m)),
                              comment=comment), encoding="utf-8")


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """<slug>.xml (MJCF: flex body + table), parameters.json, the tet mesh files and a README."""
    out_dir.mkdir(parents=True, exist_ok=True)
    xml = f"{inputs.slug}.xml"
    p = flex_params(inputs.tet.nodes_m, inputs.tet.tets, inputs.material)
    write_scene(out_dir / xml, inputs.tet.nodes_m, inputs.tet.tets, p, inputs.slug,
                f"DeformSmith export of {inputs.slug}: validated material, SI units, z up, table at z = 0")
    (out_dir / "parameters.json").write_text(json.dumps(parameters_dict(p), indent=2, sort_keys=True) + "\n",
                                             encoding="utf-8")
    mesh_files = write_tet_files(inputs, out_dir)
    hint = LOAD_HINT.format(xml=xml)
    readme = write_readme(out_dir, "MuJoCo", hint, [
        f"{xml}: one flexcomp (type direct, dim 3, dof full) with the {len(inputs.tet.tets)} tetrahedra of "
        f"{mesh_files[0]}, total mass {inputs.material.mass_kg:.4g} kg, contact friction "
        f"{inputs.material.ground_friction:.3g}, on a table plane at z = 0. Needs MuJoCo >= 3.17 (integrator "
        "'discrete': flex elasticity is integrated implicitly only there).",
        f"Mapping: {MAPPING}", f"Damping: {DAMPING}",
        "Calibrated: `deformsmith crosscheck DIR --sim mujoco` fits young, the timestep (finer where the discrete "
        "integrator's numerical dissipation takes too much of the impact's energy; the contacts' time constant "
        "follows it) and the flex damping to L2's probes and writes "
        f"{inputs.slug}{CALIBRATED_SUFFIX}.xml and calibration.json here."], material=inputs.material)
    return TargetManifest(target="mujoco", files=[xml, "parameters.json", *mesh_files, readme], load_hint=hint,
                          material=inputs.material, mapping=MAPPING, damping_mapping=DAMPING)


def load_and_step(xml_path: Path, duration_s: float = 1.0) -> dict[str, float]:
    """Load an exported MJCF with the mujoco package and step duration_s; the flex's node z range before/after."""
    import mujoco

    # lazy: mujoco_probes pulls warp (1.3 s); exporting alone steps no probe
    from tasks.export.mujoco_probes import quiet_mujoco_warnings

    quiet_mujoco_warnings()
    m = mujoco.MjModel.from_xml_path(str(xml_path))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    z0 = np.array(d.flexvert_xpos[:, 2])
    mujoco.mj_step(m, d, nstep=int(round(duration_s / m.opt.timestep)))
    z1 = np.array(d.flexvert_xpos[:, 2])
    bad = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
    return {"time_s": float(d.time), "finite": float(np.all(np.isfinite(d.qpos)) and bad == 0),
            "z_min_before_m": float(z0.min()), "z_min_after_m": float(z1.min()), "z_max_after_m": float(z1.max()),
            "nflexvert": float(m.nflexvert)}


__all__ = ["CALIBRATED_SUFFIX", "DAMPING", "MAPPING", "export", "flex_params", "load_and_step", "parameters_dict",
           "write_scene"]
