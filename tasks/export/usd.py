"""OpenUSD export (Isaac Sim / PhysX): a UsdGeom.TetMesh volume deformable with its material, the visual mesh, the
Gaussians as coloured points, a ground collider and a physics scene, in one .usda (metres, kilograms, z up).

The deformable-body schemas are Isaac Sim 5's (OmniPhysicsDeformableBodyAPI, OmniPhysicsVolumeDeformableSimAPI,
OmniPhysicsBaseMaterialAPI, OmniPhysicsDeformableMaterialAPI, PhysxBaseDeformableBodyAPI, PhysxDeformableMaterialAPI).
They ship with Isaac Sim, not with usd-core: they are applied by name (apiSchemas metadata) and their attributes are
written as attributes with the PhysX names. UsdPhysics (scene, collision, material API, mass) is usd-core's own.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from contracts.export import ExportMaterial, TargetManifest
from tasks.export.inputs import ExportInputs, write_readme, write_tet_files
from tasks.export.tetmesh import boundary_faces

# Isaac Sim schema names (applied by name; see the module docstring)
BODY_APIS = ("OmniPhysicsDeformableBodyAPI", "PhysxBaseDeformableBodyAPI")
SIM_API = "OmniPhysicsVolumeDeformableSimAPI"
MATERIAL_APIS = ("OmniPhysicsBaseMaterialAPI", "OmniPhysicsDeformableMaterialAPI", "PhysxDeformableMaterialAPI")
MAPPING = ("PhysX volume deformables are FEM with a co-rotated elasticity model: E and nu are the neo-Hookean ones "
           "(the two models agree at small strain, differ in large compression).")
DAMPING = ("physxDeformableBody:linearDamping = our velocity damping rate [1/s] (PhysX scales velocities by "
           "1/(1 + rate dt), ours by exp(-rate dt): equal to first order in dt); "
           "physxDeformableMaterial:elasticityDamping is left 0.")
GROUND_HALF_EXTENT_M = 1.0


def _float_attr(prim: Any, name: str, value: float) -> Any:
    from pxr import Sdf

    attr = prim.CreateAttribute(name, Sdf.ValueTypeNames.Float)
    attr.Set(float(value))
    return attr


def _physics_material(stage: Any, path: str, m: ExportMaterial) -> Any:
    """The deformable's material: UsdPhysics.MaterialAPI plus the Isaac Sim deformable material attributes."""
    from pxr import Sdf, UsdPhysics, UsdShade

    material = UsdShade.Material.Define(stage, path)
    prim = material.GetPrim()
    api = UsdPhysics.MaterialAPI.Apply(prim)
    api.CreateDensityAttr(m.density_kg_per_m3)
    api.CreateStaticFrictionAttr(m.ground_friction)
    api.CreateDynamicFrictionAttr(m.ground_friction)
    api.CreateRestitutionAttr(0.0)
    for name in MATERIAL_APIS:
        prim.AddAppliedSchema(name)
    _float_attr(prim, "omniphysics:density", m.density_kg_per_m3)
    _float_attr(prim, "omniphysics:staticFriction", m.ground_friction)
    _float_attr(prim, "omniphysics:dynamicFriction", m.ground_friction)
    _float_attr(prim, "omniphysics:youngsModulus", m.youngs_modulus_pa)
    _float_attr(prim, "omniphysics:poissonsRatio", m.poisson_ratio)
    _float_attr(prim, "physxDeformableMaterial:elasticityDamping", 0.0)
    # the validated values at full precision, in our own namespace (USD floats are 32-bit)
    for name, value in (("youngsModulusPa", m.youngs_modulus_pa), ("poissonRatio", m.poisson_ratio),
                        ("densityKgPerM3", m.density_kg_per_m3), ("dampingRatePerS", m.damping_rate_per_s),
                        ("viscosityPaS", m.viscosity_pa_s),
                        ("groundFriction", m.ground_friction), ("gripperFriction", m.gripper_friction),
                        ("massKg", m.mass_kg)):
        prim.CreateAttribute(f"deformsmith:{name}", Sdf.ValueTypeNames.Double).Set(float(value))
    prim.CreateAttribute("deformsmith:constitutiveModel", Sdf.ValueTypeNames.String).Set(m.constitutive_model)
    return material


def _ground(stage: Any, path: str, friction: float) -> None:
    """A static box collider whose top face is z = 0, with its own friction material."""
    from pxr import Gf, UsdGeom, UsdPhysics, UsdShade

    cube = UsdGeom.Cube.Define(stage, path)
    cube.CreateSizeAttr(2.0 * GROUND_HALF_EXTENT_M)
    xf = UsdGeom.Xformable(cube)
    xf.AddTranslateOp().Set(Gf.Vec3d(0.0, 0.0, -0.05))
    xf.AddScaleOp().Set(Gf.Vec3f(1.0, 1.0, 0.05 / GROUND_HALF_EXTENT_M))
    UsdPhysics.CollisionAPI.Apply(cube.GetPrim())
    material = UsdShade.Material.Define(stage, path + "Material")
    api = UsdPhysics.MaterialAPI.Apply(material.GetPrim())
    api.CreateStaticFrictionAttr(friction)
    api.CreateDynamicFrictionAttr(friction)
    UsdShade.MaterialBindingAPI.Apply(cube.GetPrim()).Bind(material, UsdShade.Tokens.weakerThanDescendants, "physics")


def write_usd(inputs: ExportInputs, path: Path) -> Path:
    """The asset as one .usda stage (see the module docstring)."""
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdShade, Vt

    m, tet = inputs.material, inputs.tet
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    scene = UsdPhysics.Scene.Define(stage, "/World/PhysicsScene")
    scene.CreateGravityDirectionAttr(Gf.Vec3f(0.0, 0.0, -1.0))
    scene.CreateGravityMagnitudeAttr(9.81)
    _ground(stage, "/World/Ground", m.ground_friction)

    root = UsdGeom.Xform.Define(stage, f"/World/{inputs.slug}")
    body = root.GetPrim()
    for name in BODY_APIS:
        body.AddAppliedSchema(name)
    _float_attr(body, "omniphysics:mass", m.mass_kg)
    body.CreateAttribute("omniphysics:deformableBodyEnabled", Sdf.ValueTypeNames.Bool).Set(True)
    _float_attr(body, "physxDeformableBody:linearDamping", m.damping_rate_per_s)
    UsdPhysics.MassAPI.Apply(body).CreateMassAttr(m.mass_kg)

    sim = UsdGeom.TetMesh.Define(stage, f"/World/{inputs.slug}/simulation")
    points = Vt.Vec3fArray.FromNumpy(tet.nodes_m.astype(np.float32))
    tets = Vt.Vec4iArray.FromNumpy(tet.tets.astype(np.int32))
    sim.CreatePointsAttr(points)
    sim.CreateTetVertexIndicesAttr(tets)
    sim.CreateSurfaceFaceVertexIndicesAttr(Vt.Vec3iArray.FromNumpy(boundary_faces(tet).astype(np.int32)))
    sim.CreateOrientationAttr(UsdGeom.Tokens.rightHanded)
    lo, hi = tet.nodes_m.min(axis=0), tet.nodes_m.max(axis=0)
    sim.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))
    sim_prim = sim.GetPrim()
    sim_prim.AddAppliedSchema(SIM_API)
    sim_prim.CreateAttribute("omniphysics:restShapePoints", Sdf.ValueTypeNames.Point3fArray).Set(points)
    sim_prim.CreateAttribute("omniphysics:restTetVtxIndices", Sdf.ValueTypeNames.Int4Array).Set(tets)
    UsdPhysics.CollisionAPI.Apply(sim_prim)
    UsdGeom.Imageable(sim_prim).CreatePurposeAttr(UsdGeom.Tokens.guide)

    visual = UsdGeom.Mesh.Define(stage, f"/World/{inputs.slug}/visual")
    visual.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(inputs.surface_vertices_m.astype(np.float32)))
    visual.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(inputs.surface_faces), 3, np.int32)))
    visual.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(inputs.surface_faces.astype(np.int32).ravel()))
    visual.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    s_lo, s_hi = inputs.surface_vertices_m.min(axis=0), inputs.surface_vertices_m.max(axis=0)
    visual.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, s_lo)), Gf.Vec3f(*map(float, s_hi))]))
    if inputs.surface_colors is not None:
        rgb = inputs.surface_colors[:, :3].astype(np.float32) / 255.0
        visual.CreateDisplayColorPrimvar(UsdGeom.Tokens.vertex).Set(Vt.Vec3fArray.FromNumpy(rgb))

    g = inputs.gaussians
    if g is not None and len(g["positions_m"]):
        pts = UsdGeom.Points.Define(stage, f"/World/{inputs.slug}/gaussians")
        pos = np.asarray(g["positions_m"], np.float32)
        pts.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(pos))
        widths = 2.0 * np.asarray(g["scales_m"], np.float64).max(axis=1)  # diameter: twice the largest sigma
        pts.CreateWidthsAttr(Vt.FloatArray.FromNumpy(widths.astype(np.float32)))
        pts.CreateWidthsAttr().SetMetadata("interpolation", UsdGeom.Tokens.vertex)
        colors = np.clip(np.asarray(g["colors"], np.float32), 0.0, 1.0)
        pts.CreateDisplayColorPrimvar(UsdGeom.Tokens.vertex).Set(Vt.Vec3fArray.FromNumpy(colors))
        if "opacities" in g:
            opacity = np.asarray(g["opacities"], np.float32)
            pts.CreateDisplayOpacityPrimvar(UsdGeom.Tokens.vertex).Set(Vt.FloatArray.FromNumpy(opacity))
        p_lo, p_hi = pos.min(axis=0), pos.max(axis=0)
        pts.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, p_lo)), Gf.Vec3f(*map(float, p_hi))]))

    material = _physics_material(stage, f"/World/{inputs.slug}/PhysicsMaterial", m)
    UsdShade.MaterialBindingAPI.Apply(body).Bind(material, UsdShade.Tokens.weakerThanDescendants, "physics")
    body.SetCustomDataByKey("deformsmith:units", "SI: m, kg, s, Pa")
    stage.GetRootLayer().documentation = (f"DeformSmith export of {inputs.name}: volume deformable (neo-Hookean "
                                          "E, nu validated by L2), SI units, z up, resting on z = 0")
    stage.GetRootLayer().Save()
    return path


def export(inputs: ExportInputs, out_dir: Path) -> TargetManifest:
    """<slug>.usda plus the tet mesh files and a README."""
    usd_name = f"{inputs.slug}.usda"
    write_usd(inputs, out_dir / usd_name)
    files = [usd_name, *write_tet_files(inputs, out_dir)]
    hint = (f"Isaac Sim 5: open or reference {usd_name} (stage z up, metres); in Python: "
            f"pxr.Usd.Stage.Open('{usd_name}')")
    files.append(write_readme(out_dir, "OpenUSD (Isaac Sim)", hint, [
        f"Deformable body: /World/{inputs.slug} (OmniPhysicsDeformableBodyAPI), its tet mesh "
        f"/World/{inputs.slug}/simulation (UsdGeom.TetMesh, OmniPhysicsVolumeDeformableSimAPI), visual mesh "
        f"/World/{inputs.slug}/visual, Gaussians as coloured points /World/{inputs.slug}/gaussians.",
        "The Isaac Sim deformable schemas are not part of usd-core: they are applied by name and their attributes "
        "written with the PhysX names; the validated values at full precision are the deformsmith:* attributes "
        "of the physics material.",
        f"Mapping: {MAPPING} Damping: {DAMPING}",
        "USD is a scene description, not a simulator: this export is validated by opening it with usd-core, "
        "not by stepping it."], material=inputs.material))
    return TargetManifest(target="usd", files=files, load_hint=hint, material=inputs.material, mapping=MAPPING,
                          damping_mapping=DAMPING)
