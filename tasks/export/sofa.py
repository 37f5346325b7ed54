"""SOFA export: a SofaPython3 scene (scene.py) with a hyperelastic neo-Hookean tet force field and a ground plane.

SofaPython3 is not on PyPI (SOFA ships its bindings with its own binaries), so nothing here imports Sofa: the scene is
plain Python text whose createScene(root) builds the graph. Our neo-Hookean (MPM) energy is
psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2; SOFA's "NeoHookean" is the decoupled form
psi = mu/2 (I1_bar - 3) + k/2 (ln J)^2 with ParameterSet [mu, k]: mu = ours, k = bulk modulus lambda + 2 mu / 3.
"""

from __future__ import annotations

from pathlib import Path

from contracts.export import TargetManifest
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files

MAPPING = ("SOFA NeoHookean is the decoupled (isochoric + volumetric) form: ParameterSet [mu, k] with mu = our shear "
           "modulus E / (2 (1 + nu)) and k = the bulk modulus lambda + 2 mu / 3 = E / (3 (1 - 2 nu)); the same "
           "small-strain response (E, nu), different at large volume change.")
DAMPING = ("EulerImplicitSolver rayleighMass = our velocity damping rate [1/s] (mass-proportional damping, "
           "dv/dt = -rate v), rayleighStiffness = our Kelvin-Voigt viscosity as eta / mu [s] (stiffness-proportional: "
           "the same deviatoric loss, more in volume change).")
TIME_STEP_S = 0.005
SCENE = "scene.py"

_TEMPLATE = '''"""DeformSmith export of {name!r} for SOFA (SofaPython3): runSofa scene.py, or load it from Python.

SI units (m, kg, s, Pa); z up, the body resting on the ground plane z = 0.
"""

VTK = {vtk!r}
YOUNGS_MODULUS_PA = {E!r}
POISSON_RATIO = {nu!r}
DENSITY_KG_PER_M3 = {rho!r}
MASS_KG = {mass!r}
DAMPING_RATE_PER_S = {damping!r}
STIFFNESS_DAMPING_S = {beta!r}  # Kelvin-Voigt viscosity eta / mu (Rayleigh stiffness damping)
FRICTION = {friction!r}
MU_PA = {mu!r}          # shear modulus E / (2 (1 + nu))
BULK_PA = {bulk!r}      # bulk modulus E / (3 (1 - 2 nu))
TIME_STEP_S = {dt!r}


def createScene(root):
    """The SOFA graph: contact pipeline, the deformable body (neo-Hookean tets) and a static ground."""
    import os

    here = os.path.dirname(os.path.abspath(__file__))
    root.gravity = [0.0, 0.0, -9.81]
    root.dt = TIME_STEP_S
    root.addObject("RequiredPlugin", pluginName=[
        "Sofa.Component.AnimationLoop", "Sofa.Component.Collision.Detection.Algorithm",
        "Sofa.Component.Collision.Detection.Intersection", "Sofa.Component.Collision.Geometry",
        "Sofa.Component.Collision.Response.Contact", "Sofa.Component.Constraint.Lagrangian.Correction",
        "Sofa.Component.Constraint.Lagrangian.Solver", "Sofa.Component.IO.Mesh", "Sofa.Component.LinearSolver.Direct",
        "Sofa.Component.Mass", "Sofa.Component.ODESolver.Backward", "Sofa.Component.SolidMechanics.FEM.HyperElastic",
        "Sofa.Component.StateContainer", "Sofa.Component.Topology.Container.Constant",
        "Sofa.Component.Topology.Container.Dynamic", "Sofa.Component.Topology.Mapping"])
    root.addObject("FreeMotionAnimationLoop")
    root.addObject("GenericConstraintSolver", maxIterations=200, tolerance=1e-6)
    root.addObject("CollisionPipeline")
    root.addObject("BruteForceBroadPhase")
    root.addObject("BVHNarrowPhase")
    root.addObject("LocalMinDistance", alarmDistance=0.004, contactDistance=0.0005)
    root.addObject("CollisionResponse", response="FrictionContactConstraint", responseParams=f"mu={{FRICTION}}")

    body = root.addChild({slug!r})
    body.addObject("EulerImplicitSolver", rayleighMass=DAMPING_RATE_PER_S, rayleighStiffness=STIFFNESS_DAMPING_S)
    body.addObject("SparseLDLSolver", template="CompressedRowSparseMatrixMat3x3d")
    body.addObject("MeshVTKLoader", name="loader", filename=os.path.join(here, VTK))
    body.addObject("TetrahedronSetTopologyContainer", name="topology", src="@loader")
    body.addObject("TetrahedronSetTopologyModifier")
    body.addObject("MechanicalObject", name="dofs", template="Vec3d", src="@loader")
    body.addObject("MeshMatrixMass", massDensity=DENSITY_KG_PER_M3, topology="@topology")
    body.addObject("TetrahedronHyperelasticityFEMForceField", materialName="NeoHookean",
                   ParameterSet=[MU_PA, BULK_PA], topology="@topology")
    body.addObject("GenericConstraintCorrection")
    surface = body.addChild("surface")
    surface.addObject("TriangleSetTopologyContainer", name="triangles")
    surface.addObject("TriangleSetTopologyModifier")
    surface.addObject("Tetra2TriangleTopologicalMapping", input="@../topology", output="@triangles")
    surface.addObject("TriangleCollisionModel")
    surface.addObject("LineCollisionModel")
    surface.addObject("PointCollisionModel")

    ground = root.addChild("ground")
    ground.addObject("MechanicalObject", template="Vec3d",
                     position=[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]])
    ground.addObject("TriangleSetTopologyContainer", triangles=[[0, 1, 2], [0, 2, 3]])
    ground.addObject("TriangleCollisionModel", moving=False, simulated=False)
    return root
'''


def scene_text(inputs: ExportInputs, vtk_name: str) -> str:
    """The scene.py source for this asset."""
    m = inputs.material
    bulk = m.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * m.poisson_ratio))
    return _TEMPLATE.format(name=inputs.name, slug=inputs.slug, vtk=vtk_name, E=m.youngs_modulus_pa,
                            nu=m.poisson_ratio, rho=m.density_kg_per_m3, mass=m.mass_kg,
                            damping=m.damping_rate_per_s, beta=m.stiffness_damping_s, friction=m.ground_friction,
                            mu=m.mu_pa, bulk=bulk,
                            dt=TIME_STEP_S)


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """scene.py, the tet mesh files and a README."""
    mesh_files = write_tet_files(inputs, out_dir)
    (out_dir / SCENE).write_text(scene_text(inputs, mesh_files[0]), encoding="utf-8")
    hint = f"runSofa {SCENE} (SOFA >= 23.06 with SofaPython3), or Sofa.Simulation.init on a root built by createScene"
    readme = write_readme(out_dir, "SOFA", hint, [
        f"{SCENE} loads {mesh_files[0]} (MeshVTKLoader) into a TetrahedronHyperelasticityFEMForceField "
        "(NeoHookean), MeshMatrixMass from the density, friction contact with a ground plane at z = 0.",
        "Not run here: SofaPython3 is not installable from PyPI; the scene is checked by compiling it and building "
        "its graph on a recording stand-in for Sofa's node API.",
        f"Mapping: {MAPPING} Damping: {DAMPING}"], material=inputs.material)
    return TargetManifest(target="sofa", files=[SCENE, *mesh_files, readme], load_hint=hint,
                          material=inputs.material, mapping=MAPPING, damping_mapping=DAMPING)
