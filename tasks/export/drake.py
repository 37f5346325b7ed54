"""Drake export: an SDFormat deformable body (`drake:deformable_properties`, the VTK tet mesh) and a static ground.

Drake's FEM has a neo-Hookean model (`<drake:material_model>neohookean</drake:material_model>`): E and nu are
exported as they are. Damping: Drake's Rayleigh damping D = alpha M + beta K; our damping v *= exp(-rate dt) is
dv/dt = -rate v, i.e. alpha (mass damping) = rate [1/s] and beta (stiffness damping) = 0.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import escape

from contracts.export import ExportMaterial, TargetManifest
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files

MAPPING = "Drake neohookean: the same constitutive model, E and nu as validated."
DAMPING = ("Drake's Rayleigh mass damping alpha = our velocity damping rate [1/s] (both are dv/dt = -rate v); "
           "stiffness damping beta = 0.")
GROUND_HALF_EXTENT_M = 0.5
GROUND_THICKNESS_M = 0.05


CALIBRATED_SUFFIX = "_calibrated"
EXPORT_COMMENT = "DeformSmith export. SI units (m, kg, s, Pa); frame z up, the body resting on z = 0."


def deformable_sdf(model: str, vtk_name: str, m: ExportMaterial, comment: str = EXPORT_COMMENT) -> str:
    """SDFormat 1.9 text of a deformable body whose rest shape is the .vtk tet mesh, at the asset frame."""
    return f"""<?xml version="1.0"?>
<!-- {escape(comment).replace("--", "- -")} -->
<sdf xmlns:drake="http://drake.mit.edu" version="1.9">
  <model name="{escape(model)}">
    <link name="{escape(model)}_body">
      <pose>0 0 0 0 0 0</pose>
      <collision name="collision">
        <geometry>
          <mesh><uri>{escape(vtk_name)}</uri></mesh>
        </geometry>
        <drake:proximity_properties>
          <drake:mu_dynamic>{m.ground_friction!r}</drake:mu_dynamic>
        </drake:proximity_properties>
      </collision>
      <drake:deformable_properties>
        <drake:youngs_modulus>{m.youngs_modulus_pa!r}</drake:youngs_modulus>
        <drake:poissons_ratio>{m.poisson_ratio!r}</drake:poissons_ratio>
        <drake:mass_density>{m.density_kg_per_m3!r}</drake:mass_density>
        <drake:material_model>neohookean</drake:material_model>
        <drake:mass_damping>{m.damping_rate_per_s!r}</drake:mass_damping>
        <drake:stiffness_damping>{m.stiffness_damping_s!r}</drake:stiffness_damping>
      </drake:deformable_properties>
    </link>
  </model>
</sdf>
"""


def ground_sdf(friction: float) -> str:
    """A static box whose top face is z = 0 (welded to the world by Drake: a static model)."""
    h, t = GROUND_HALF_EXTENT_M, GROUND_THICKNESS_M
    return f"""<?xml version="1.0"?>
<sdf xmlns:drake="http://drake.mit.edu" version="1.9">
  <model name="ground">
    <static>true</static>
    <link name="ground">
      <pose>0 0 {-t / 2!r} 0 0 0</pose>
      <collision name="collision">
        <geometry><box><size>{2 * h!r} {2 * h!r} {t!r}</size></box></geometry>
        <drake:proximity_properties>
          <drake:mu_dynamic>{friction!r}</drake:mu_dynamic>
          <drake:mu_static>{friction!r}</drake:mu_static>
        </drake:proximity_properties>
      </collision>
      <visual name="visual">
        <geometry><box><size>{2 * h!r} {2 * h!r} {t!r}</size></box></geometry>
      </visual>
    </link>
  </model>
</sdf>
"""


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """<slug>.sdf (the deformable), ground.sdf, the tet mesh files and a README."""
    sdf_name = f"{inputs.slug}.sdf"
    mesh_files = write_tet_files(inputs, out_dir)
    (out_dir / sdf_name).write_text(deformable_sdf(inputs.slug, mesh_files[0], inputs.material), encoding="utf-8")
    (out_dir / "ground.sdf").write_text(ground_sdf(inputs.material.ground_friction), encoding="utf-8")
    hint = ("pydrake: plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=0.001, "
            "discrete_contact_approximation='sap'), builder); Parser(plant).AddModels('ground.sdf'); "
            f"Parser(plant).AddModels('{sdf_name}'); plant.Finalize()")
    readme = write_readme(out_dir, "Drake", hint, [
        f"The deformable body ({sdf_name}) uses {mesh_files[0]} (linear tets) for dynamics and contact; "
        "ground.sdf is a static box with its top face at z = 0.",
        "Deformable bodies need a discrete MultibodyPlant with the SAP contact solver.",
        "Drake integrates deformables with a first-order, dissipative Newmark scheme (gamma = 1): the larger the "
        "step against the body's period, the less it bounces. `deformsmith crosscheck DIR --sim drake` measures it "
        f"and fits E, the mass damping and the step ({inputs.slug}{CALIBRATED_SUFFIX}.sdf, calibration.json here).",
        "pydrake 1.51.1 logs 'SDFormat Error ... Missing element description for [drake:wall_boundary_condition]' "
        "while parsing any deformable link (its parser probing an optional tag): harmless, the body loads.",
        f"Mapping: {MAPPING} Damping: {DAMPING}"], material=inputs.material)
    return TargetManifest(target="drake", files=[sdf_name, "ground.sdf", *mesh_files, readme], load_hint=hint,
                          material=inputs.material, mapping="", damping_mapping=DAMPING)


def load_and_step(folder: Path, duration_s: float = 1.0, time_step_s: float = 0.01) -> dict[str, object]:
    """Load an export folder into a discrete (SAP) MultibodyPlant with pydrake's Parser, step it and return the
    deformable's node positions before and after [m] (N, 3), and the wall time; needs the drake package."""
    import time

    import numpy as np
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
    from pydrake.multibody.tree import DeformableBodyIndex
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder

    folder = Path(folder)
    sdf = [p for p in sorted(folder.glob("*.sdf")) if p.name != "ground.sdf"]
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=time_step_s, discrete_contact_approximation="sap"),
                                 builder)
    Parser(plant).AddModels(folder / "ground.sdf")
    Parser(plant).AddModels(sdf[0])
    plant.Finalize()
    model = plant.deformable_model()
    body = model.GetBodyId(DeformableBodyIndex(0))
    simulator = Simulator(builder.Build())
    context = plant.GetMyContextFromRoot(simulator.get_mutable_context())
    def nodes() -> np.ndarray:  # pydrake returns the positions as a (3, N) matrix
        q = np.asarray(model.GetPositions(context, body))
        return (q.T if q.ndim == 2 and q.shape[0] == 3 else q.reshape(-1, 3)).copy()

    before = nodes()
    t0 = time.perf_counter()
    simulator.Initialize()
    simulator.AdvanceTo(duration_s)
    after = nodes()
    return {"positions_before_m": before, "positions_after_m": after, "wall_s": time.perf_counter() - t0,
            "deformable_bodies": model.num_bodies(), "sim_time_s": duration_s}
